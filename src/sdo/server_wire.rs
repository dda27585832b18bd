//! The [`Server`](super::Server)'s own decoder of the requests it serves
//! besides the segment of a running transfer (CiA 301 section 7.2.4.3, SDO
//! protocols): exactly what the server takes of each command, read from
//! byte 0, the frame's length and its one data word, instead of the general
//! `ClientCommand` decoder (which also decodes every block command's fields,
//! a segment's data and the expedited data into `InlineData`).
//!
//! It accepts and ignores the same frames as the general decoder: a frame
//! shorter than its command needs decodes to `None` (the tests compare
//! every byte 0 at every length with `ClientCommand::of_frame`).

use super::words;
use super::AbortCode;
use crate::frame::CanFrame;

/// What an initiate-download request carries, as the server uses it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Download {
    /// e = 1: `len` data bytes (0..=4), little-endian in `data` (bytes
    /// 4..=7 of the frame as received; only the first `len` are the
    /// value's), with the s bit.
    Expedited {
        data: u32,
        len: usize,
        size_indicated: bool,
    },
    /// e = 0: a segmented download follows, of `size` bytes when indicated.
    Segmented { size: Option<u32> },
}

/// A request the server answers outside a running segmented transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Request {
    /// ccs = 1.
    InitiateDownload {
        index: u16,
        sub: u8,
        payload: Download,
    },
    /// ccs = 2.
    InitiateUpload { index: u16, sub: u8 },
    /// ccs = 4: the client's abort code (its multiplexer is not used).
    Abort(AbortCode),
    /// A block initiate (ccs = 5 cs = 0, ccs = 6 cs = 0) of `index`/`sub`.
    BlockInitiate { index: u16, sub: u8 },
    /// Any other block command (ccs = 5 or 6).
    Block,
    /// A segment command (ccs = 0 or 3) outside the transfer it belongs
    /// to, or ccs = 7: answered with 05040001h.
    Invalid,
}

/// The length the general decoder needs for the command of byte 0 `b0`
/// (a shorter frame does not decode).
#[inline(always)]
const fn needed(b0: u8) -> u8 {
    match b0 >> 5 {
        0 => words::segment_needed(b0),
        1 => words::initiate_needed(b0),
        2 => 4,
        4 => 8,
        // Block upload: initiate (blksize, pst), ack (ackseq, blksize),
        // start and end byte 0 alone.
        5 => match b0 & 0x03 {
            0 => 6,
            2 => 3,
            _ => 1,
        },
        // Block download: initiate (the size when indicated), end (CRC).
        6 => match b0 & 0x03 {
            0x02 => 8,
            0x00 => 4,
            _ => 3,
        },
        _ => 1,
    }
}

/// The request of `frame` (a data frame on the server's request
/// identifier), `None` when it is too short for its command.
#[inline(always)]
pub(crate) fn request(frame: &CanFrame) -> Option<Request> {
    let bytes = frame.padded_data();
    let [b0, ..] = bytes;
    let len = frame.dlc().min(8);
    if len < needed(b0) {
        return None;
    }
    let word = u64::from_le_bytes(bytes);
    let index = (word >> 8) as u16;
    let sub = (word >> 24) as u8;
    let tail = (word >> 32) as u32;
    Some(match b0 >> 5 {
        1 => {
            let size_indicated = b0 & 0x01 != 0;
            let payload = if b0 & 0x02 != 0 {
                let len = if size_indicated {
                    4 - usize::from((b0 >> 2) & 0x03)
                } else {
                    // Every data byte the frame carried (it has 4 or more).
                    usize::from(len).saturating_sub(4)
                };
                Download::Expedited {
                    data: tail,
                    len,
                    size_indicated,
                }
            } else {
                Download::Segmented {
                    size: if size_indicated { Some(tail) } else { None },
                }
            };
            Request::InitiateDownload {
                index,
                sub,
                payload,
            }
        }
        2 => Request::InitiateUpload { index, sub },
        4 => Request::Abort(AbortCode::from_u32(tail)),
        5 if b0 & 0x03 == 0 => Request::BlockInitiate { index, sub },
        6 if b0 & 0x01 == 0 => Request::BlockInitiate { index, sub },
        5 | 6 => Request::Block,
        _ => Request::Invalid,
    })
}

#[cfg(test)]
mod tests {
    use super::super::super::wire::{ClientBlockDownload, ClientBlockUpload, ClientCommand};
    use super::super::super::InitiatePayload;
    use super::*;

    /// What the server took of the general decoder's command (as
    /// `handle_request` used it before this decoder).
    fn general(frame: &CanFrame) -> Option<Request> {
        let command = ClientCommand::of_frame(frame).ok()?;
        Some(match command {
            ClientCommand::InitiateDownload {
                index,
                sub,
                payload,
            } => Request::InitiateDownload {
                index,
                sub,
                payload: match payload {
                    InitiatePayload::Expedited {
                        data,
                        size_indicated,
                    } => {
                        let mut word = [0u8; 4];
                        word[..data.len()].copy_from_slice(data.as_slice());
                        Download::Expedited {
                            data: u32::from_le_bytes(word),
                            len: data.len(),
                            size_indicated,
                        }
                    }
                    InitiatePayload::Segmented { size } => Download::Segmented { size },
                },
            },
            ClientCommand::InitiateUpload { index, sub } => Request::InitiateUpload { index, sub },
            ClientCommand::Abort { code, .. } => Request::Abort(code),
            ClientCommand::BlockUpload(ClientBlockUpload::Initiate { index, sub, .. })
            | ClientCommand::BlockDownload(ClientBlockDownload::Initiate { index, sub, .. }) => {
                Request::BlockInitiate { index, sub }
            }
            ClientCommand::BlockUpload(_) | ClientCommand::BlockDownload(_) => Request::Block,
            ClientCommand::UploadSegment { .. }
            | ClientCommand::DownloadSegment(_)
            | ClientCommand::Unknown(_) => Request::Invalid,
        })
    }

    /// The first `n` bytes of `data` as a little-endian word.
    fn masked(data: u32, n: usize) -> u32 {
        data & u32::MAX.checked_shr(32 - 8 * n as u32).unwrap_or(0)
    }

    /// Every byte 0 at every length, with several payloads: the same
    /// frames decode, to the same request (an expedited download's bytes
    /// compared as far as its length).
    #[test]
    fn same_requests_as_the_general_decoder() {
        let tails = [
            [0x17, 0x10, 0x00, 0xE8, 0x03, 0x00, 0x00],
            [0xFF; 7],
            [0x00, 0x20, 0x7F, 0x01, 0x00, 0x04, 0x05],
            [0x00; 7],
        ];
        let mut decoded = 0;
        for b0 in 0..=255u8 {
            for tail in tails {
                for len in 0..=8usize {
                    let mut data = [0u8; 8];
                    data[0] = b0;
                    data[1..].copy_from_slice(&tail);
                    let frame = CanFrame::standard(0x601, &data[..len]).unwrap();
                    let ours = request(&frame);
                    let theirs = general(&frame);
                    match (ours, theirs) {
                        (
                            Some(Request::InitiateDownload {
                                index,
                                sub,
                                payload:
                                    Download::Expedited {
                                        data,
                                        len,
                                        size_indicated,
                                    },
                            }),
                            Some(Request::InitiateDownload {
                                index: i,
                                sub: s,
                                payload:
                                    Download::Expedited {
                                        data: d,
                                        len: l,
                                        size_indicated: si,
                                    },
                            }),
                        ) => {
                            assert_eq!((index, sub, len, size_indicated), (i, s, l, si));
                            assert_eq!(masked(data, len), d, "{frame:?}");
                        }
                        (ours, theirs) => assert_eq!(ours, theirs, "{frame:?}"),
                    }
                    decoded += usize::from(ours.is_some());
                }
            }
        }
        // Frames too short for their command are among them.
        assert!(decoded > 0 && decoded < 256 * 4 * 9, "{decoded}");
    }

    /// A few requests by hand.
    #[test]
    fn requests_by_hand() {
        let frame = |data: &[u8]| CanFrame::standard(0x601, data).unwrap();
        assert_eq!(
            request(&frame(&[0x40, 0x17, 0x10, 0x00])),
            Some(Request::InitiateUpload {
                index: 0x1017,
                sub: 0
            })
        );
        assert_eq!(
            request(&frame(&[0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0])),
            Some(Request::InitiateDownload {
                index: 0x1017,
                sub: 0,
                payload: Download::Expedited {
                    data: 0x03E8,
                    len: 2,
                    size_indicated: true
                }
            })
        );
        // Expedited with 2 data bytes indicated but only 1 present.
        assert_eq!(request(&frame(&[0x2B, 0x17, 0x10, 0x00, 0xE8])), None);
        assert_eq!(
            request(&frame(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04, 0x05])),
            Some(Request::Abort(AbortCode::SdoProtocolTimedOut))
        );
        assert_eq!(request(&frame(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04])), None);
        assert_eq!(request(&frame(&[0xE0])), Some(Request::Invalid));
        assert_eq!(request(&frame(&[])), None);
    }
}
