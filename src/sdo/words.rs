//! The frames the client and the server send, each as the one
//! little-endian word of its 8 data bytes (DLC 8, every byte the command
//! leaves undefined zero): exactly what `SdoRequest::new(command).encode()`
//! and `SdoResponse::new(command).encode()` make of the same command (the
//! tests compare every one), in a few shifts at the call site instead of
//! the general encoder's match over every command and merge with decoded
//! bytes.

use super::AbortCode;

/// Byte 0 `b0`, the multiplexer (index, sub-index) in bytes 1..=3 and
/// `tail` in bytes 4..=7: the shape of every initiate and abort.
#[inline(always)]
#[must_use]
pub(crate) const fn mux(b0: u8, index: u16, sub: u8, tail: u32) -> u64 {
    b0 as u64 | (index as u64) << 8 | (sub as u64) << 24 | (tail as u64) << 32
}

/// An abort (cs = 4) of `index`/`sub` with `code`.
#[inline(always)]
#[must_use]
pub(crate) const fn abort(index: u16, sub: u8, code: AbortCode) -> u64 {
    mux(0x80, index, sub, code.to_u32())
}

/// An expedited initiate with the size indicated: command specifier
/// `specifier` (1 download request, 2 upload response), `n` (1..=4)
/// data bytes, the little-endian `data` (zero past them).
#[inline(always)]
#[must_use]
pub(crate) const fn expedited(specifier: u8, index: u16, sub: u8, data: u32, n: usize) -> u64 {
    mux(expedited_b0(specifier, n), index, sub, data)
}

/// Byte 0 of [`expedited`].
#[inline(always)]
#[must_use]
pub(crate) const fn expedited_b0(specifier: u8, n: usize) -> u8 {
    let unused = (4 - if n > 4 { 4 } else { n }) as u8;
    specifier << 5 | unused << 2 | 0x03
}

/// A segmented initiate with the size indicated (specifier as for
/// [`expedited`]): the segmented client's request (the server sends
/// [`segmented_b0`] with the size itself).
#[cfg(any(test, feature = "sdo-client-segmented"))]
#[inline(always)]
#[must_use]
pub(crate) const fn segmented(specifier: u8, index: u16, sub: u8, size: u32) -> u64 {
    mux(segmented_b0(specifier), index, sub, size)
}

/// Byte 0 of `segmented` (the server's segmented upload response).
#[inline(always)]
#[must_use]
pub(crate) const fn segmented_b0(specifier: u8) -> u8 {
    specifier << 5 | 0x01
}

/// Byte 0 of an upload segment response (scs = 0) with toggle `toggle`,
/// `n` (0..=7) data bytes and the c bit `last`.
#[inline(always)]
#[must_use]
pub(crate) const fn upload_segment(toggle: bool, n: usize, last: bool) -> u8 {
    // n is at most 7: the 3-bit count of unused bytes is 7 - n.
    let unused = 7 - if n > 7 { 7 } else { n } as u8;
    (toggle as u8) << 4 | unused << 1 | last as u8
}

/// A block acknowledgement (`b0` A2h, both directions): `ackseq`, then
/// the next block size.
/// The bytes a frame needs for the segment command byte `b0` (server or
/// client): byte 0 and 7 - n data bytes.
#[inline(always)]
pub(crate) const fn segment_needed(b0: u8) -> u8 {
    8 - ((b0 >> 1) & 0x07)
}

/// The bytes a frame needs for the initiate command byte `b0` (upload
/// response or download request): expedited with the size indicated the
/// multiplexer and 4 - n bytes; segmented with the size the whole frame;
/// otherwise the multiplexer.
#[inline(always)]
pub(crate) const fn initiate_needed(b0: u8) -> u8 {
    match b0 & 0x03 {
        0x03 => 8 - ((b0 >> 2) & 0x03),
        0x01 => 8,
        _ => 4,
    }
}

#[cfg(feature = "sdo-block")]
#[inline(always)]
#[must_use]
pub(crate) const fn block_ack(ackseq: u8, blksize: u8) -> u64 {
    0xA2 | (ackseq as u64) << 8 | (blksize as u64) << 16
}

/// A block end frame with data (`b0` base C1h, both directions): the
/// unused bytes of the last segment and the CRC.
#[cfg(feature = "sdo-block")]
#[inline(always)]
#[must_use]
pub(crate) const fn block_end(unused: u8, crc: u16) -> u64 {
    (0xC1 | (unused & 0x07) << 2) as u64 | (crc as u64) << 8
}

#[cfg(test)]
mod tests {
    use super::super::wire::{ClientCommand, SdoRequest, SdoResponse, ServerCommand};
    use super::super::{
        AbortCode, ExpeditedData, InitiatePayload, Segment, SegmentData, ALL_ABORT_CODES,
    };
    use super::*;

    fn request(command: ClientCommand) -> u64 {
        let (bytes, len) = SdoRequest::new(command).encode();
        assert_eq!(len, 8, "{command:?}");
        u64::from_le_bytes(bytes)
    }

    fn response(command: ServerCommand) -> u64 {
        let (bytes, len) = SdoResponse::new(command).encode();
        assert_eq!(len, 8, "{command:?}");
        u64::from_le_bytes(bytes)
    }

    const OBJECTS: [(u16, u8); 4] = [(0, 0), (0x1017, 0), (0x2000, 0x7F), (0xFFFF, 0xFF)];

    /// Every word equals the general encoder's frame of the same command.
    #[test]
    fn words_are_the_encoders_frames() {
        let value = [0xA1, 0xB2, 0xC3, 0xD4];
        for (index, sub) in OBJECTS {
            assert_eq!(
                mux(0x40, index, sub, 0),
                request(ClientCommand::InitiateUpload { index, sub })
            );
            assert_eq!(
                mux(0x60, index, sub, 0),
                response(ServerCommand::InitiateDownload { index, sub })
            );
            for code in ALL_ABORT_CODES
                .into_iter()
                .chain([AbortCode::Other(0x1234_5678)])
            {
                let abort = abort(index, sub, code);
                assert_eq!(abort, request(ClientCommand::Abort { index, sub, code }));
                assert_eq!(abort, response(ServerCommand::Abort { index, sub, code }));
            }
            for n in 1..=4 {
                let data = ExpeditedData::new(&value[..n]).unwrap();
                let payload = InitiatePayload::Expedited {
                    data,
                    size_indicated: true,
                };
                let mut word = [0u8; 4];
                word[..n].copy_from_slice(&value[..n]);
                let word = u32::from_le_bytes(word);
                assert_eq!(
                    expedited(1, index, sub, word, n),
                    request(ClientCommand::InitiateDownload {
                        index,
                        sub,
                        payload
                    })
                );
                assert_eq!(
                    expedited(2, index, sub, word, n),
                    response(ServerCommand::InitiateUpload {
                        index,
                        sub,
                        payload
                    })
                );
            }
            for size in [0, 5, 1000, u32::MAX] {
                let payload = InitiatePayload::Segmented { size: Some(size) };
                assert_eq!(
                    segmented(1, index, sub, size),
                    request(ClientCommand::InitiateDownload {
                        index,
                        sub,
                        payload
                    })
                );
                assert_eq!(
                    segmented(2, index, sub, size),
                    response(ServerCommand::InitiateUpload {
                        index,
                        sub,
                        payload
                    })
                );
            }
        }
        for (toggle, last, data) in [
            (false, false, &[1u8, 2, 3, 4, 5, 6, 7][..]),
            (true, true, &[9][..]),
            (false, true, &[][..]),
            (true, false, &[1, 2, 3][..]),
        ] {
            let segment = ServerCommand::UploadSegment(Segment {
                toggle,
                last,
                data: SegmentData::new(data).unwrap(),
            });
            let [b0, ..] = SdoResponse::new(segment).encode().0;
            assert_eq!(upload_segment(toggle, data.len(), last), b0);
        }
        assert_eq!(
            0x60,
            request(ClientCommand::UploadSegment { toggle: false })
        );
        assert_eq!(
            0x60 | 1 << 4,
            request(ClientCommand::UploadSegment { toggle: true })
        );
    }

    /// The block frames, as the block code of the client and the server
    /// writes them.
    #[cfg(feature = "sdo-block")]
    #[test]
    fn block_words_are_the_encoders_frames() {
        use super::super::wire::{
            ClientBlockDownload, ClientBlockUpload, ServerBlockDownload, ServerBlockUpload,
        };
        for (index, sub) in OBJECTS {
            for crc in [false, true] {
                let c = u8::from(crc) << 2;
                for (blksize, pst) in [(1, 0), (127, 4), (0xFF, 0xFF)] {
                    assert_eq!(
                        mux(
                            0xA0 | c,
                            index,
                            sub,
                            u32::from_le_bytes([blksize, pst, 0, 0])
                        ),
                        request(ClientCommand::BlockUpload(ClientBlockUpload::Initiate {
                            index,
                            sub,
                            crc,
                            blksize,
                            pst
                        }))
                    );
                    assert_eq!(
                        mux(0xA0 | c, index, sub, u32::from(blksize)),
                        response(ServerCommand::BlockDownload(
                            ServerBlockDownload::Initiate {
                                index,
                                sub,
                                crc,
                                blksize
                            }
                        ))
                    );
                }
                for size in [0, 7, u32::MAX] {
                    let size_some = Some(size);
                    assert_eq!(
                        mux(0xC2 | c, index, sub, size),
                        request(ClientCommand::BlockDownload(
                            ClientBlockDownload::Initiate {
                                index,
                                sub,
                                crc,
                                size: size_some
                            }
                        ))
                    );
                    assert_eq!(
                        mux(0xC2 | c, index, sub, size),
                        response(ServerCommand::BlockUpload(ServerBlockUpload::Initiate {
                            index,
                            sub,
                            crc,
                            size: size_some
                        }))
                    );
                }
            }
        }
        for (ackseq, blksize) in [(0, 1), (5, 127), (0xFF, 0xFF)] {
            let ack = block_ack(ackseq, blksize);
            assert_eq!(
                ack,
                request(ClientCommand::BlockUpload(ClientBlockUpload::Ack {
                    ackseq,
                    blksize
                }))
            );
            assert_eq!(
                ack,
                response(ServerCommand::BlockDownload(ServerBlockDownload::Ack {
                    ackseq,
                    blksize
                }))
            );
        }
        for unused in 0..=7 {
            for crc in [0, 0x1234, 0xFFFF] {
                let end = block_end(unused, crc);
                assert_eq!(
                    end,
                    request(ClientCommand::BlockDownload(ClientBlockDownload::End {
                        unused,
                        crc
                    }))
                );
                assert_eq!(
                    end,
                    response(ServerCommand::BlockUpload(ServerBlockUpload::End {
                        unused,
                        crc
                    }))
                );
            }
        }
        assert_eq!(
            0xA3,
            request(ClientCommand::BlockUpload(ClientBlockUpload::Start))
        );
        assert_eq!(
            0xA1,
            request(ClientCommand::BlockUpload(ClientBlockUpload::End))
        );
        assert_eq!(
            0xA1,
            response(ServerCommand::BlockDownload(ServerBlockDownload::End))
        );
    }
}
