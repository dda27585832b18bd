//! Byte vectors for the SDO codec: public byte-exact SDO frame sequences
//! from the test suites of python-canopen, CANopenNode and Wireshark's
//! dissector (numbered V1-V19 here; expedited, segmented, block and abort
//! transfers, some of them lenient where a strict stack aborts) and every
//! command specifier.

use super::*;
use crate::sdo::{ExpeditedData, SegmentData};

fn req(bytes: &[u8]) -> ClientCommand {
    let r = SdoRequest::parse(bytes).unwrap();
    let (b, n) = r.encode();
    assert_eq!(&b[..n], bytes, "request round trip");
    r.command
}

fn resp(bytes: &[u8]) -> ServerCommand {
    let r = SdoResponse::parse(bytes).unwrap();
    let (b, n) = r.encode();
    assert_eq!(&b[..n], bytes, "response round trip");
    r.command
}

fn exp(data: &[u8]) -> InitiatePayload {
    InitiatePayload::expedited(data).unwrap()
}

fn seg(toggle: bool, last: bool, data: &[u8]) -> Segment {
    Segment {
        toggle,
        last,
        data: SegmentData::new(data).unwrap(),
    }
}

/// Encodes a typed command with zero reserved bytes.
fn enc_req(c: ClientCommand) -> [u8; 8] {
    let (b, n) = SdoRequest::new(c).encode();
    assert_eq!(n, 8);
    b
}

fn enc_resp(c: ServerCommand) -> [u8; 8] {
    let (b, n) = SdoResponse::new(c).encode();
    assert_eq!(n, 8);
    b
}

/// A vector read and written both ways: `bytes` decode to `c` (and back to
/// `bytes`), and `c` built from scratch encodes to `bytes`.
fn both_ways_req(bytes: [u8; 8], c: ClientCommand) {
    assert_eq!(req(&bytes), c);
    assert_eq!(enc_req(c), bytes);
}

/// [`both_ways_req`] for a response.
fn both_ways_resp(bytes: [u8; 8], c: ServerCommand) {
    assert_eq!(resp(&bytes), c);
    assert_eq!(enc_resp(c), bytes);
}

#[test]
fn v1_v3_expedited_upload() {
    let up = ClientCommand::InitiateUpload {
        index: 0x1018,
        sub: 1,
    };
    both_ways_req([0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0], up);
    let r = ServerCommand::InitiateUpload {
        index: 0x1018,
        sub: 1,
        payload: exp(&[4, 0, 0, 0]),
    };
    both_ways_resp([0x43, 0x18, 0x10, 0x01, 0x04, 0, 0, 0], r);
    // V1b: DLC 5, n = 3, one byte.
    assert_eq!(
        resp(&[0x4F, 0x00, 0x14, 0x02, 0xFE]),
        ServerCommand::InitiateUpload {
            index: 0x1400,
            sub: 2,
            payload: exp(&[0xFE]),
        }
    );
    // V1c / V2: size not indicated: all 4 bytes reported.
    assert_eq!(
        resp(&[0x42, 0x00, 0x14, 0x02, 0xFE, 0, 0, 0]),
        ServerCommand::InitiateUpload {
            index: 0x1400,
            sub: 2,
            payload: InitiatePayload::Expedited {
                data: ExpeditedData::new(&[0xFE, 0, 0, 0]).unwrap(),
                size_indicated: false
            },
        }
    );
    // V3: n = 2 and n = 1 with garbage padding that must be ignored (and kept).
    assert_eq!(
        resp(&[0x4B, 0x06, 0x20, 0x00, 0xFE, 0xFD, 0xFC, 0xFB]),
        ServerCommand::InitiateUpload {
            index: 0x2006,
            sub: 0,
            payload: exp(&[0xFE, 0xFD]),
        }
    );
    assert_eq!(
        resp(&[0x47, 0x16, 0x20, 0x00, 0xFE, 0xFD, 0xFC, 0xFB]),
        ServerCommand::InitiateUpload {
            index: 0x2016,
            sub: 0,
            payload: exp(&[0xFE, 0xFD, 0xFC]),
        }
    );
}

#[test]
fn v4_v7_expedited_download() {
    let d = ClientCommand::InitiateDownload {
        index: 0x1017,
        sub: 0,
        payload: exp(&[0xA0, 0x0F]),
    };
    both_ways_req([0x2B, 0x17, 0x10, 0x00, 0xA0, 0x0F, 0, 0], d);
    let ack = ServerCommand::InitiateDownload {
        index: 0x1017,
        sub: 0,
    };
    both_ways_resp([0x60, 0x17, 0x10, 0, 0, 0, 0, 0], ack);
    // V6: 4 bytes, n = 0.
    let d = ClientCommand::InitiateDownload {
        index: 0x1400,
        sub: 1,
        payload: exp(&[0x04, 0x02, 0x00, 0x80]),
    };
    both_ways_req([0x23, 0x00, 0x14, 0x01, 0x04, 0x02, 0x00, 0x80], d);
    // V7
    assert_eq!(
        req(&[0x23, 0x16, 0x10, 0x02, 0xF0, 0x00, 0x01, 0x00]),
        ClientCommand::InitiateDownload {
            index: 0x1016,
            sub: 2,
            payload: exp(&[0xF0, 0, 1, 0]),
        }
    );
}

#[test]
fn v8_segmented_upload() {
    assert_eq!(
        resp(&[0x41, 0x08, 0x10, 0x00, 0x1A, 0, 0, 0]),
        ServerCommand::InitiateUpload {
            index: 0x1008,
            sub: 0,
            payload: InitiatePayload::Segmented { size: Some(26) },
        }
    );
    assert_eq!(
        req(&[0x60, 0, 0, 0, 0, 0, 0, 0]),
        ClientCommand::UploadSegment { toggle: false }
    );
    assert_eq!(
        req(&[0x70, 0, 0, 0, 0, 0, 0, 0]),
        ClientCommand::UploadSegment { toggle: true }
    );
    assert_eq!(
        enc_req(ClientCommand::UploadSegment { toggle: true }),
        [0x70, 0, 0, 0, 0, 0, 0, 0]
    );
    let s = ServerCommand::UploadSegment(seg(false, false, b"Tiny No"));
    both_ways_resp([0x00, 0x54, 0x69, 0x6E, 0x79, 0x20, 0x4E, 0x6F], s);
    assert_eq!(
        resp(&[0x10, 0x64, 0x65, 0x20, 0x2D, 0x20, 0x4D, 0x65]),
        ServerCommand::UploadSegment(seg(true, false, b"de - Me"))
    );
    let last = ServerCommand::UploadSegment(seg(true, true, b"ins !"));
    both_ways_resp([0x15, 0x69, 0x6E, 0x73, 0x20, 0x21, 0, 0], last);
}

#[test]
fn v9_v10_lenient_sizes_still_decode() {
    // The codec reports what the frames say; the client state machine aborts.
    assert_eq!(
        resp(&[0x41, 0x08, 0x10, 0x00, 0x04, 0, 0, 0]),
        ServerCommand::InitiateUpload {
            index: 0x1008,
            sub: 0,
            payload: InitiatePayload::Segmented { size: Some(4) },
        }
    );
    assert_eq!(
        resp(&[0x05, 0x54, 0x69, 0x6E, 0x79, 0x20, 0, 0]),
        ServerCommand::UploadSegment(seg(false, true, b"Tiny "))
    );
    assert_eq!(
        resp(&[0x41, 0x1B, 0x20, 0x00, 0xFE, 0xFD, 0xFC, 0xFB]),
        ServerCommand::InitiateUpload {
            index: 0x201B,
            sub: 0,
            payload: InitiatePayload::Segmented {
                size: Some(0xFBFC_FDFE)
            },
        }
    );
    assert_eq!(
        resp(&[0x1D, 0x19, 0x21, 0x70, 0xFE, 0xFD, 0xFC, 0xFB]),
        ServerCommand::UploadSegment(seg(true, true, &[0x19]))
    );
}

#[test]
fn v11_v14_segmented_download() {
    let init = ClientCommand::InitiateDownload {
        index: 0x2000,
        sub: 0,
        payload: InitiatePayload::Segmented { size: Some(13) },
    };
    both_ways_req([0x21, 0x00, 0x20, 0x00, 0x0D, 0, 0, 0], init);
    let s0 = ClientCommand::DownloadSegment(seg(false, false, b"A long "));
    assert_eq!(req(&[0x00, 0x41, 0x20, 0x6C, 0x6F, 0x6E, 0x67, 0x20]), s0);
    // The fixture's ack has non-zero reserved bytes: ignored, and kept.
    assert_eq!(
        resp(&[0x20, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        ServerCommand::DownloadSegment { toggle: false }
    );
    assert_eq!(
        enc_resp(ServerCommand::DownloadSegment { toggle: false }),
        [0x20, 0, 0, 0, 0, 0, 0, 0]
    );
    let s1 = ClientCommand::DownloadSegment(seg(true, true, b"string"));
    both_ways_req([0x13, 0x73, 0x74, 0x72, 0x69, 0x6E, 0x67, 0x00], s1);
    assert_eq!(
        resp(&[0x30, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        ServerCommand::DownloadSegment { toggle: true }
    );
    // V12
    assert_eq!(
        req(&[0x05, 0x6F, 0x6D, 0x61, 0x69, 0x6E, 0, 0]),
        ClientCommand::DownloadSegment(seg(false, true, b"omain"))
    );
    // V13: zero length, one empty last segment.
    assert_eq!(
        req(&[0x21, 0x00, 0x20, 0x00, 0, 0, 0, 0]),
        ClientCommand::InitiateDownload {
            index: 0x2000,
            sub: 0,
            payload: InitiatePayload::Segmented { size: Some(0) },
        }
    );
    let empty = ClientCommand::DownloadSegment(seg(false, true, &[]));
    both_ways_req([0x0F, 0, 0, 0, 0, 0, 0, 0], empty);
    // V14: size not indicated, short non-final segment.
    let nosize = ClientCommand::InitiateDownload {
        index: 0x2000,
        sub: 0,
        payload: InitiatePayload::Segmented { size: None },
    };
    both_ways_req([0x20, 0x00, 0x20, 0x00, 0, 0, 0, 0], nosize);
    assert_eq!(
        req(&[0x1A, 0x38, 0x39, 0, 0, 0, 0, 0]),
        ClientCommand::DownloadSegment(seg(true, false, b"89"))
    );
}

#[test]
fn v15_v16_abort() {
    let a = ServerCommand::Abort {
        index: 0x1018,
        sub: 1,
        code: AbortCode::SubIndexDoesNotExist,
    };
    both_ways_resp([0x80, 0x18, 0x10, 0x01, 0x11, 0x00, 0x09, 0x06], a);
    let a = ClientCommand::Abort {
        index: 0,
        sub: 0,
        code: AbortCode::SdoProtocolTimedOut,
    };
    assert_eq!(req(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04, 0x05]), a);
    assert_eq!(
        abort_code_of(&[0x80, 0x00, 0x70, 0x01, 0x01, 0x00, 0x04, 0x05]),
        Some(AbortCode::InvalidCommandSpecifier)
    );
    assert_eq!(abort_code_of(&[0x80, 0, 0]), None);
    // An abort needs its code: 7 bytes are truncated.
    assert_eq!(
        SdoResponse::parse(&[0x80, 0x18, 0x10, 0x01, 0x11, 0x00, 0x09]),
        Err(DecodeError::Truncated { need: 8, got: 7 })
    );
}

#[test]
fn v17_block_download() {
    let init = ClientCommand::BlockDownload(ClientBlockDownload::Initiate(BlockDataInitiate {
        index: 0x2000,
        sub: 0,
        crc: true,
        size: Some(30),
    }));
    both_ways_req([0xC6, 0x00, 0x20, 0x00, 0x1E, 0, 0, 0], init);
    let r = ServerCommand::BlockDownload(ServerBlockDownload::Initiate(BlockDownloadAccept {
        index: 0x2000,
        sub: 0,
        crc: true,
        blksize: 127,
    }));
    both_ways_resp([0xA4, 0x00, 0x20, 0x00, 0x7F, 0, 0, 0], r);
    // Sub-block segments have no specifier: they decode as their bits say,
    // and keep their bytes for a block state machine.
    let s = SdoRequest::parse(&[0x85, 0x2E, 0x2E, 0, 0, 0, 0, 0]).unwrap();
    assert_eq!(s.bytes(), &[0x85, 0x2E, 0x2E, 0, 0, 0, 0, 0]);
    let ack = ServerCommand::BlockDownload(ServerBlockDownload::Ack {
        ackseq: 5,
        blksize: 127,
    });
    both_ways_resp([0xA2, 0x05, 0x7F, 0, 0, 0, 0, 0], ack);
    let end = ClientCommand::BlockDownload(ClientBlockDownload::End {
        unused: 5,
        crc: 0x6945,
    });
    both_ways_req([0xD5, 0x45, 0x69, 0, 0, 0, 0, 0], end);
    let done = ServerCommand::BlockDownload(ServerBlockDownload::End);
    both_ways_resp([0xA1, 0, 0, 0, 0, 0, 0, 0], done);
}

#[test]
fn v18_v19_block_upload() {
    let init = ClientCommand::BlockUpload(ClientBlockUpload::Initiate(BlockUploadInitiate {
        index: 0x1008,
        sub: 0,
        crc: true,
        blksize: 127,
        pst: 0,
    }));
    both_ways_req([0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0], init);
    let r = ServerCommand::BlockUpload(ServerBlockUpload::Initiate(BlockDataInitiate {
        index: 0x1008,
        sub: 0,
        crc: true,
        size: Some(26),
    }));
    both_ways_resp([0xC6, 0x08, 0x10, 0x00, 0x1A, 0, 0, 0], r);
    let start = ClientCommand::BlockUpload(ClientBlockUpload::Start);
    both_ways_req([0xA3, 0, 0, 0, 0, 0, 0, 0], start);
    let ack = ClientCommand::BlockUpload(ClientBlockUpload::Ack {
        ackseq: 4,
        blksize: 127,
    });
    both_ways_req([0xA2, 0x04, 0x7F, 0, 0, 0, 0, 0], ack);
    // V19's retransmit ack.
    assert_eq!(
        req(&[0xA2, 0x32, 0x7F, 0, 0, 0, 0, 0]),
        ClientCommand::BlockUpload(ClientBlockUpload::Ack {
            ackseq: 0x32,
            blksize: 127
        })
    );
    let end = ServerCommand::BlockUpload(ServerBlockUpload::End {
        unused: 2,
        crc: 0xE140,
    });
    both_ways_resp([0xC9, 0x40, 0xE1, 0, 0, 0, 0, 0], end);
    assert_eq!(
        resp(&[0xC9, 0x3B, 0x49, 0, 0, 0, 0, 0]),
        ServerCommand::BlockUpload(ServerBlockUpload::End {
            unused: 2,
            crc: 0x493B
        })
    );
    let fin = ClientCommand::BlockUpload(ClientBlockUpload::End);
    both_ways_req([0xA1, 0, 0, 0, 0, 0, 0, 0], fin);
}

#[test]
fn unknown_specifiers_and_no_size_variants() {
    assert_eq!(req(&[0xE0]), ClientCommand::Unknown(0xE0));
    assert_eq!(resp(&[0xFF, 1, 2]), ServerCommand::Unknown(0xFF));
    assert_eq!(resp(&[0xA3, 0, 0, 0]), ServerCommand::Unknown(0xA3));
    assert_eq!(
        req(&[0xC0, 0x00, 0x20, 0x01]),
        ClientCommand::BlockDownload(ClientBlockDownload::Initiate(BlockDataInitiate {
            index: 0x2000,
            sub: 1,
            crc: false,
            size: None
        }))
    );
    assert_eq!(
        resp(&[0xC0, 0x00, 0x20, 0x01]),
        ServerCommand::BlockUpload(ServerBlockUpload::Initiate(BlockDataInitiate {
            index: 0x2000,
            sub: 1,
            crc: false,
            size: None
        }))
    );
}

#[test]
fn reserved_bits_survive_round_trip() {
    // Reserved bit 4 of an initiate, bits 4-0 of an upload request, and the
    // n field of an e=1 s=0 initiate are all kept as received.
    for bytes in [
        [0x5F, 0x18, 0x10, 0x01, 9, 9, 9, 9],
        [0x3E, 0x00, 0x20, 0x00, 1, 2, 3, 4],
        [0x7F, 1, 2, 3, 4, 5, 6, 7],
        [0x9F, 0, 0, 0, 0, 0, 0, 0],
        [0xBC, 0x08, 0x10, 0x00, 0x7F, 0, 0xAA, 0xBB],
        [0xDB, 0x45, 0x69, 0xCC, 0, 0, 0, 0],
    ] {
        let r = SdoRequest::parse(&bytes).unwrap();
        assert_eq!(r.encode(), (bytes, 8));
        let s = SdoResponse::parse(&bytes).unwrap();
        assert_eq!(s.encode(), (bytes, 8));
    }
}

#[test]
fn truncation_is_per_command() {
    let t = |need, got| Err(DecodeError::Truncated { need, got });
    assert_eq!(SdoRequest::parse(&[]).map(|r| r.command), t(1, 0));
    assert_eq!(SdoRequest::parse(&[0x40, 0x18]).map(|r| r.command), t(4, 2));
    // Expedited with n = 0 needs all 4 data bytes.
    assert_eq!(
        SdoRequest::parse(&[0x23, 0, 0x14, 1, 4, 2]).map(|r| r.command),
        t(8, 6)
    );
    // A segment with 7 - n = 3 data bytes needs 4 bytes.
    assert_eq!(SdoRequest::parse(&[0x09, 1, 2]).map(|r| r.command), t(4, 3));
    assert!(SdoRequest::parse(&[0x09, 1, 2, 3]).is_ok());
    // Segmented initiate with size needs 8.
    assert_eq!(
        SdoResponse::parse(&[0x41, 8, 0x10, 0, 0x1A]).map(|_| ()),
        Err(DecodeError::Truncated { need: 8, got: 5 })
    );
    assert_eq!(
        SdoRequest::parse(&[0; 9]).map(|r| r.command),
        Err(DecodeError::TooLong { max: 8, got: 9 })
    );
}

#[test]
fn every_one_and_two_byte_frame_is_total() {
    for b0 in 0..=255u8 {
        for len in 0..=8usize {
            let bytes = [b0, 0xFF, 0x00, 0x55, 0xAA, 1, 2, 3];
            let data = &bytes[..len];
            if let Ok(r) = SdoRequest::parse(data) {
                let (b, n) = r.encode();
                assert_eq!(&b[..n], data);
            }
            if let Ok(r) = SdoResponse::parse(data) {
                let (b, n) = r.encode();
                assert_eq!(&b[..n], data);
            }
        }
    }
}

// ---------------------------------------------------------------------
// The one layer: the length rule, parse / emit round trips, and the frames
// the machines send as byte literals.

/// Every byte 0 at every length, both sides: a frame parses exactly when
/// it has the bytes [`needed`] gives, and the error names that length.
#[test]
fn the_length_rule_decides_every_frame() {
    for b0 in 0..=255u8 {
        for len in 1..=8usize {
            let bytes = [b0, 0x17, 0x10, 0x02, 0xA1, 0xB2, 0xC3, 0xD4];
            let frame = SdoFrame::new_checked(&bytes[..len]).unwrap();
            for side in [Side::Client, Side::Server] {
                let need = needed(side, b0);
                let parsed = match side {
                    Side::Client => ClientCommand::parse(&frame).map(|_| ()),
                    Side::Server => ServerCommand::parse(&frame).map(|_| ()),
                };
                if len >= need {
                    assert_eq!(parsed, Ok(()), "{side:?} {b0:#04x} len {len}");
                } else {
                    assert_eq!(
                        parsed,
                        Err(DecodeError::Truncated { need, got: len }),
                        "{side:?} {b0:#04x} len {len}"
                    );
                }
            }
        }
    }
}

/// The checked view: 1..=8 bytes, accessors zero past the length.
#[test]
fn the_view_is_checked() {
    assert_eq!(
        SdoFrame::new_checked(&[]),
        Err(DecodeError::Truncated { need: 1, got: 0 })
    );
    assert_eq!(
        SdoFrame::new_checked(&[0; 9]),
        Err(DecodeError::TooLong { max: 8, got: 9 })
    );
    let f = SdoFrame::new_checked(&[0x2B, 0x17, 0x10, 0x00, 0xE8]).unwrap();
    assert_eq!((f.len(), f.command(), f.specifier()), (5, 0x2B, 1));
    assert_eq!((f.index(), f.sub(), f.u32_at_4()), (0x1017, 0, 0xE8));
    assert_eq!((f.byte(4), f.byte(5), f.byte(100)), (0xE8, 0, 0));
    assert_eq!(f.as_bytes(), &[0x2B, 0x17, 0x10, 0x00, 0xE8]);
    let empty = crate::frame::CanFrame::standard(0x601, &[]).unwrap();
    assert!(SdoFrame::of_frame(&empty).is_err());
}

/// The frames the client and the server send, as byte literals: what
/// `to_bytes` makes of each command (DLC 8, undefined bytes zero).
#[test]
fn machine_frames_as_byte_literals() {
    let c = |cmd: ClientCommand| cmd.to_bytes();
    let s = |cmd: ServerCommand| cmd.to_bytes();
    let (index, sub) = (0x2000, 0x7F);
    assert_eq!(
        c(ClientCommand::InitiateUpload { index, sub }),
        [0x40, 0x00, 0x20, 0x7F, 0, 0, 0, 0]
    );
    assert_eq!(
        s(ServerCommand::InitiateDownload { index, sub }),
        [0x60, 0x00, 0x20, 0x7F, 0, 0, 0, 0]
    );
    let code = AbortCode::SdoProtocolTimedOut;
    assert_eq!(
        c(ClientCommand::Abort { index, sub, code }),
        [0x80, 0x00, 0x20, 0x7F, 0x00, 0x00, 0x04, 0x05]
    );
    assert_eq!(
        s(ServerCommand::Abort { index, sub, code }),
        [0x80, 0x00, 0x20, 0x7F, 0x00, 0x00, 0x04, 0x05]
    );
    for (data, b0) in [
        (&[0xA1][..], 0x0F),
        (&[0xA1, 0xB2][..], 0x0B),
        (&[0xA1, 0xB2, 0xC3][..], 0x07),
        (&[0xA1, 0xB2, 0xC3, 0xD4][..], 0x03),
    ] {
        let payload = exp(data);
        let mut want = [0x20 | b0, 0x00, 0x20, 0x7F, 0, 0, 0, 0];
        want[4..4 + data.len()].copy_from_slice(data);
        let request = ClientCommand::InitiateDownload {
            index,
            sub,
            payload,
        };
        assert_eq!(c(request), want);
        want[0] = 0x40 | b0;
        let response = ServerCommand::InitiateUpload {
            index,
            sub,
            payload,
        };
        assert_eq!(s(response), want);
    }
    let payload = InitiatePayload::Segmented {
        size: Some(0x0102_0304),
    };
    #[rustfmt::skip]
    let requests: &[(ClientCommand, [u8; 8])] = &[
        (ClientCommand::InitiateDownload { index, sub, payload }, [0x21, 0x00, 0x20, 0x7F, 0x04, 0x03, 0x02, 0x01]),
        (ClientCommand::DownloadSegment(seg(false, false, &[1, 2, 3, 4, 5, 6, 7])), [0x00, 1, 2, 3, 4, 5, 6, 7]),
        (ClientCommand::DownloadSegment(seg(false, true, &[])), [0x0F, 0, 0, 0, 0, 0, 0, 0]),
        (ClientCommand::UploadSegment { toggle: true }, [0x70, 0, 0, 0, 0, 0, 0, 0]),
        // Block transfer.
        (ClientCommand::BlockUpload(ClientBlockUpload::Initiate(BlockUploadInitiate { index, sub, crc: true, blksize: 127, pst: 4 })), [0xA4, 0x00, 0x20, 0x7F, 127, 4, 0, 0]),
        (ClientCommand::BlockDownload(ClientBlockDownload::Initiate(BlockDataInitiate { index, sub, crc: true, size: Some(7) })), [0xC6, 0x00, 0x20, 0x7F, 7, 0, 0, 0]),
        (ClientCommand::BlockUpload(ClientBlockUpload::Ack { ackseq: 5, blksize: 127 }), [0xA2, 5, 127, 0, 0, 0, 0, 0]),
        (ClientCommand::BlockDownload(ClientBlockDownload::End { unused: 3, crc: 0x1234 }), [0xCD, 0x34, 0x12, 0, 0, 0, 0, 0]),
        (ClientCommand::BlockUpload(ClientBlockUpload::Start), [0xA3, 0, 0, 0, 0, 0, 0, 0]),
        (ClientCommand::BlockUpload(ClientBlockUpload::End), [0xA1, 0, 0, 0, 0, 0, 0, 0]),
    ];
    #[rustfmt::skip]
    let responses: &[(ServerCommand, [u8; 8])] = &[
        (ServerCommand::InitiateUpload { index, sub, payload }, [0x41, 0x00, 0x20, 0x7F, 0x04, 0x03, 0x02, 0x01]),
        (ServerCommand::UploadSegment(seg(true, true, &[9])), [0x1D, 9, 0, 0, 0, 0, 0, 0]),
        (ServerCommand::DownloadSegment { toggle: true }, [0x30, 0, 0, 0, 0, 0, 0, 0]),
        // Block transfer.
        (ServerCommand::BlockDownload(ServerBlockDownload::Initiate(BlockDownloadAccept { index, sub, crc: true, blksize: 127 })), [0xA4, 0x00, 0x20, 0x7F, 127, 0, 0, 0]),
        (ServerCommand::BlockUpload(ServerBlockUpload::Initiate(BlockDataInitiate { index, sub, crc: false, size: Some(7) })), [0xC2, 0x00, 0x20, 0x7F, 7, 0, 0, 0]),
        (ServerCommand::BlockDownload(ServerBlockDownload::Ack { ackseq: 5, blksize: 127 }), [0xA2, 5, 127, 0, 0, 0, 0, 0]),
        (ServerCommand::BlockUpload(ServerBlockUpload::End { unused: 3, crc: 0x1234 }), [0xCD, 0x34, 0x12, 0, 0, 0, 0, 0]),
        (ServerCommand::BlockDownload(ServerBlockDownload::End), [0xA1, 0, 0, 0, 0, 0, 0, 0]),
    ];
    for (command, bytes) in requests {
        assert_eq!(c(*command), *bytes, "{command:?}");
    }
    for (command, bytes) in responses {
        assert_eq!(s(*command), *bytes, "{command:?}");
    }
}

/// What the server and the expedited client read of a few requests and
/// responses by hand (the vectors of their former own decoders).
#[test]
fn requests_and_responses_by_hand() {
    let request = |data: &[u8]| SdoFrame::new_checked(data).and_then(|f| ClientCommand::parse(&f));
    let response = |data: &[u8]| SdoFrame::new_checked(data).and_then(|f| ServerCommand::parse(&f));
    assert_eq!(
        request(&[0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0]),
        Ok(ClientCommand::InitiateDownload {
            index: 0x1017,
            sub: 0,
            payload: exp(&[0xE8, 0x03])
        })
    );
    // Expedited with 2 data bytes indicated but only 1 present.
    assert!(request(&[0x2B, 0x17, 0x10, 0x00, 0xE8]).is_err());
    assert_eq!(
        request(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04, 0x05]),
        Ok(ClientCommand::Abort {
            index: 0,
            sub: 0,
            code: AbortCode::SdoProtocolTimedOut
        })
    );
    assert!(request(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04]).is_err());
    assert_eq!(request(&[0xE0]), Ok(ClientCommand::Unknown(0xE0)));
    assert_eq!(
        response(&[0x4B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0xAA, 0xBB]),
        Ok(ServerCommand::InitiateUpload {
            index: 0x1017,
            sub: 0,
            payload: exp(&[0xE8, 0x03])
        })
    );
    // Expedited without the size: every byte the frame carries.
    assert_eq!(
        response(&[0x42, 0x00, 0x10, 0x01, 0x91]),
        Ok(ServerCommand::InitiateUpload {
            index: 0x1000,
            sub: 1,
            payload: InitiatePayload::Expedited {
                data: ExpeditedData::new(&[0x91]).unwrap(),
                size_indicated: false
            }
        })
    );
    // Segmented with the size but without it in the frame.
    assert!(response(&[0x41, 0x08, 0x10, 0x00]).is_err());
    assert_eq!(
        response(&[0x60, 0x00, 0x20, 0x7F]),
        Ok(ServerCommand::InitiateDownload {
            index: 0x2000,
            sub: 0x7F
        })
    );
    assert_eq!(
        response(&[0x20]),
        Ok(ServerCommand::DownloadSegment { toggle: false })
    );
    assert!(response(&[0x00, 1, 2]).is_err());
}

/// A block sub-block segment: sequence number and c bit in byte 0, every
/// byte after it data.
#[test]
fn block_segments() {
    let f = SdoFrame::new_checked(&[0x85, 1, 2, 3, 4, 5, 6, 7]).unwrap();
    let seg = BlockSegment::parse(&f);
    assert_eq!((seg.seqno, seg.last), (5, true));
    assert_eq!(seg.data.as_slice(), &[1, 2, 3, 4, 5, 6, 7]);
    let mut buf = [0u8; 8];
    assert_eq!(seg.emit(&mut buf), 8);
    assert_eq!(buf, [0x85, 1, 2, 3, 4, 5, 6, 7]);
}

/// The segment reading of `decode_frame` gives what `parse` gives, for
/// every byte 0 at every length (the data bytes do not choose the command).
#[test]
fn segment_reading_agrees_with_parse() {
    for b0 in 0..=u8::MAX {
        for len in 1..=8usize {
            let bytes = [b0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77];
            let frame = SdoFrame::new_checked(&bytes[..len]).unwrap();
            if ClientCommand::is_segment(&frame) {
                let cmd = ClientCommand::parse_segment(&frame);
                assert_eq!(Ok(cmd), ClientCommand::parse(&frame), "{b0:#04x} {len}");
            }
            if ServerCommand::is_segment(&frame) {
                let cmd = ServerCommand::parse_segment(&frame);
                assert_eq!(Ok(cmd), ServerCommand::parse(&frame), "{b0:#04x} {len}");
            }
            let can = CanFrame::standard(0x581, &bytes[..len]).unwrap();
            assert_eq!(SdoRequest::decode_frame(&can), SdoRequest::from_view(frame));
            assert_eq!(
                SdoResponse::decode_frame(&can),
                SdoResponse::from_view(frame)
            );
        }
    }
}

mod props {
    use super::*;
    use proptest::prelude::*;

    fn frame_bytes() -> impl Strategy<Value = ([u8; 8], usize)> {
        (any::<[u8; 8]>(), 0..=8usize)
    }

    proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 4096,
        ..crate::testing::proptest_config("tests/proptest-regressions/src-sdo-wire-tests.txt")
    })]

        /// `emit(parse(x)) == x` for every input that parses, both sides:
        /// emitted over the frame's own bytes, the command gives them back.
        #[test]
        fn emit_over_the_frame_gives_it_back((bytes, len) in frame_bytes()) {
            let data = &bytes[..len];
            if let Ok(frame) = SdoFrame::new_checked(data) {
                if let Ok(cmd) = ClientCommand::parse(&frame) {
                    let mut buf = bytes;
                    prop_assert!(cmd.emit(&mut buf) <= len);
                    prop_assert_eq!(buf, bytes);
                    let (b, n) = SdoRequest::from_view(frame).unwrap().encode();
                    prop_assert_eq!(&b[..n], data);
                }
                if let Ok(cmd) = ServerCommand::parse(&frame) {
                    let mut buf = bytes;
                    prop_assert!(cmd.emit(&mut buf) <= len);
                    prop_assert_eq!(buf, bytes);
                    let (b, n) = SdoResponse::from_view(frame).unwrap().encode();
                    prop_assert_eq!(&b[..n], data);
                }
                let seg = BlockSegment::parse(&frame);
                let mut buf = bytes;
                prop_assert_eq!(seg.emit(&mut buf), len);
                prop_assert_eq!(buf, bytes);
            }
        }

        /// The segment reading agrees with `parse` on any bytes.
        #[test]
        fn segment_reading_agrees_on_any_bytes((bytes, len) in frame_bytes()) {
            if let Ok(frame) = SdoFrame::new_checked(&bytes[..len]) {
                if ClientCommand::is_segment(&frame) {
                    prop_assert_eq!(Ok(ClientCommand::parse_segment(&frame)), ClientCommand::parse(&frame));
                }
                if ServerCommand::is_segment(&frame) {
                    prop_assert_eq!(Ok(ServerCommand::parse_segment(&frame)), ServerCommand::parse(&frame));
                }
            }
        }

        /// `parse(emit(c)) == c`: a command that parsed, emitted onto zero
        /// bytes (as the machines send it), parses to the same command,
        /// and its length is `buffer_len`, which the length rule accepts.
        #[test]
        fn parse_of_emit_is_the_command((bytes, len) in frame_bytes()) {
            if let Ok(frame) = SdoFrame::new_checked(&bytes[..len]) {
                if let Ok(cmd) = ClientCommand::parse(&frame) {
                    let mut buf = [0u8; 8];
                    let n = cmd.emit(&mut buf);
                    prop_assert_eq!(n, cmd.buffer_len());
                    prop_assert!(n >= needed(Side::Client, buf[0]));
                    let again = SdoFrame::new_checked(&buf[..n]).unwrap();
                    prop_assert_eq!(ClientCommand::parse(&again), Ok(cmd));
                }
                if let Ok(cmd) = ServerCommand::parse(&frame) {
                    let mut buf = [0u8; 8];
                    let n = cmd.emit(&mut buf);
                    prop_assert_eq!(n, cmd.buffer_len());
                    prop_assert!(n >= needed(Side::Server, buf[0]));
                    let again = SdoFrame::new_checked(&buf[..n]).unwrap();
                    prop_assert_eq!(ServerCommand::parse(&again), Ok(cmd));
                }
            }
        }
    }
}
