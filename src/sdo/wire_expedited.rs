//! The expedited client's own decoder of the responses it can get
//! (feature `sdo-client-segmented` off; CiA 301 section 7.2.4.3, SDO
//! protocols): the initiate upload response (expedited, with or without
//! the size, or segmented), the initiate download response and the abort,
//! read from byte 0, the frame's length and its one data word, instead of
//! the general `ServerCommand` decoder (which also decodes every segment
//! and block command's fields). Every other command is [`Response::Invalid`]
//! (the client aborts it, 05040001h).
//!
//! It accepts and ignores the same frames as the general decoder: a frame
//! shorter than its command needs decodes to `None` (the tests compare
//! every byte 0 at every length with `ServerCommand::of_frame`).

use super::super::super::words;
use super::super::super::AbortCode;
use crate::frame::CanFrame;

/// A response, as the expedited client uses it. `mux` is the multiplexer
/// as one word: the index in bits 0..=15, the sub-index in bits 16..=23
/// (bytes 1..=3 of the frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Response {
    /// scs = 2, e = 1: `len` data bytes (0..=4), little-endian in `data`
    /// (bytes 4..=7 of the frame as received, zero past its length; only
    /// the first `len` are the value's).
    Expedited { mux: u32, data: u32, len: usize },
    /// scs = 2, e = 0: the server would go on segmented (with the size
    /// or without).
    Segmented { mux: u32 },
    /// scs = 3.
    Downloaded { mux: u32 },
    /// scs = 4: the server's abort code as the client reports it (0, no
    /// code, as 08000000h; the multiplexer is not used).
    Abort(AbortCode),
    /// Any other command (scs 0, 1, 5, 6, 7): none fits an expedited
    /// transfer.
    Invalid,
}

/// The length the general decoder needs for the response of byte 0 `b0`
/// (a shorter frame does not decode).
#[inline(always)]
const fn needed(b0: u8) -> u8 {
    match b0 >> 5 {
        0 => words::segment_needed(b0),
        2 => words::initiate_needed(b0),
        3 => 4,
        4 => 8,
        // Block download: initiate (blksize in byte 4), ack (ackseq,
        // blksize); end byte 0 alone.
        5 => match b0 & 0x03 {
            0 => 5,
            2 => 3,
            _ => 1,
        },
        // Block upload: end (CRC), initiate (the size when indicated).
        6 => match b0 & 0x03 {
            0x01 | 0x03 => 3,
            0x02 => 8,
            _ => 4,
        },
        // A download segment acknowledged, scs = 7: byte 0 alone.
        _ => 1,
    }
}

/// The response of `frame` (a data frame on the client's response
/// identifier), `None` when it is too short for its command.
#[inline(always)]
pub(super) fn response(frame: &CanFrame) -> Option<Response> {
    let bytes = frame.padded_data();
    let [b0, ..] = bytes;
    let len = frame.dlc().min(8);
    if len < needed(b0) {
        return None;
    }
    let word = u64::from_le_bytes(bytes);
    let mux = (word >> 8) as u32 & 0x00FF_FFFF;
    let tail = (word >> 32) as u32;
    Some(match b0 >> 5 {
        2 if b0 & 0x02 != 0 => Response::Expedited {
            mux,
            data: tail,
            len: if b0 & 0x01 != 0 {
                4 - usize::from((b0 >> 2) & 0x03)
            } else {
                // Every data byte the frame carried (it has 4 or more).
                usize::from(len).saturating_sub(4)
            },
        },
        2 => Response::Segmented { mux },
        3 => Response::Downloaded { mux },
        4 => Response::Abort(AbortCode::from_u32(match tail {
            0 => AbortCode::GeneralError.to_u32(),
            code => code,
        })),
        _ => Response::Invalid,
    })
}

#[cfg(test)]
mod tests {
    use super::super::super::super::wire::ServerCommand;
    use super::super::super::super::InitiatePayload;
    use super::*;

    /// What the expedited client took of the general decoder's command
    /// (as its response path used it before this decoder).
    fn general(frame: &CanFrame) -> Option<Response> {
        let command = ServerCommand::of_frame(frame).ok()?;
        let mux = |index: u16, sub: u8| u32::from(index) | u32::from(sub) << 16;
        Some(match command {
            ServerCommand::InitiateUpload {
                index,
                sub,
                payload: InitiatePayload::Expedited { data, .. },
            } => {
                let mut word = [0u8; 4];
                word[..data.len()].copy_from_slice(data.as_slice());
                Response::Expedited {
                    mux: mux(index, sub),
                    data: u32::from_le_bytes(word),
                    len: data.len(),
                }
            }
            ServerCommand::InitiateUpload { index, sub, .. } => Response::Segmented {
                mux: mux(index, sub),
            },
            ServerCommand::InitiateDownload { index, sub } => Response::Downloaded {
                mux: mux(index, sub),
            },
            ServerCommand::Abort {
                code: AbortCode::Other(0),
                ..
            } => Response::Abort(AbortCode::GeneralError),
            ServerCommand::Abort { code, .. } => Response::Abort(code),
            _ => Response::Invalid,
        })
    }

    /// The first `n` bytes of `data` as a little-endian word.
    fn masked(data: u32, n: usize) -> u32 {
        data & u32::MAX.checked_shr(32 - 8 * n as u32).unwrap_or(0)
    }

    /// Every byte 0 at every length, with several payloads: the same
    /// frames decode, to the same response (an expedited upload's bytes
    /// compared as far as its length).
    #[test]
    fn same_responses_as_the_general_decoder() {
        let tails = [
            [0x08, 0x10, 0x02, 0x11, 0x22, 0x33, 0x44],
            [0xFF; 7],
            [0x00, 0x20, 0x7F, 0x01, 0x00, 0x04, 0x05],
            [0x00; 7],
        ];
        let (mut decoded, mut kinds) = (0, [false; 5]);
        for b0 in 0..=255u8 {
            for tail in tails {
                for len in 0..=8usize {
                    let mut data = [0u8; 8];
                    data[0] = b0;
                    data[1..].copy_from_slice(&tail);
                    let frame = CanFrame::standard(0x582, &data[..len]).unwrap();
                    let ours = response(&frame);
                    match (ours, general(&frame)) {
                        (
                            Some(Response::Expedited { mux, data, len }),
                            Some(Response::Expedited {
                                mux: m,
                                data: d,
                                len: l,
                            }),
                        ) => {
                            assert_eq!((mux, len), (m, l), "{frame:?}");
                            assert_eq!(masked(data, len), d, "{frame:?}");
                        }
                        (ours, theirs) => assert_eq!(ours, theirs, "{frame:?}"),
                    }
                    decoded += usize::from(ours.is_some());
                    if let Some(r) = ours {
                        let kind = match r {
                            Response::Expedited { .. } => 0,
                            Response::Segmented { .. } => 1,
                            Response::Downloaded { .. } => 2,
                            Response::Abort(_) => 3,
                            Response::Invalid => 4,
                        };
                        kinds[kind] = true;
                    }
                }
            }
        }
        // Frames too short for their command are among them, and every
        // kind of response was compared.
        assert!(decoded > 0 && decoded < 256 * 4 * 9, "{decoded}");
        assert_eq!(kinds, [true; 5]);
    }

    /// A few responses by hand.
    #[test]
    fn responses_by_hand() {
        let frame = |data: &[u8]| CanFrame::standard(0x582, data).unwrap();
        assert_eq!(
            response(&frame(&[0x4B, 0x17, 0x10, 0x00, 0xE8, 0x03, 0xAA, 0xBB])),
            Some(Response::Expedited {
                mux: 0x1017,
                data: 0xBBAA_03E8,
                len: 2
            })
        );
        // Expedited without the size: every byte the frame carries.
        assert_eq!(
            response(&frame(&[0x42, 0x00, 0x10, 0x01, 0x91])),
            Some(Response::Expedited {
                mux: 0x0001_1000,
                data: 0x91,
                len: 1
            })
        );
        // Expedited with 2 data bytes indicated but only 1 present.
        assert_eq!(response(&frame(&[0x4B, 0x17, 0x10, 0x00, 0xE8])), None);
        assert_eq!(
            response(&frame(&[0x41, 0x08, 0x10, 0x00, 20, 0, 0, 0])),
            Some(Response::Segmented { mux: 0x1008 })
        );
        // Segmented with the size but without it in the frame.
        assert_eq!(response(&frame(&[0x41, 0x08, 0x10, 0x00])), None);
        assert_eq!(
            response(&frame(&[0x60, 0x00, 0x20, 0x7F])),
            Some(Response::Downloaded { mux: 0x007F_2000 })
        );
        assert_eq!(
            response(&frame(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04, 0x05])),
            Some(Response::Abort(AbortCode::SdoProtocolTimedOut))
        );
        assert_eq!(response(&frame(&[0x80, 0, 0, 0, 0x00, 0x00, 0x04])), None);
        // No code: reported as 08000000h.
        assert_eq!(
            response(&frame(&[0x80, 0x08, 0x10, 0, 0, 0, 0, 0])),
            Some(Response::Abort(AbortCode::GeneralError))
        );
        assert_eq!(response(&frame(&[0x20])), Some(Response::Invalid));
        assert_eq!(response(&frame(&[0x00, 1, 2])), None);
        assert_eq!(response(&frame(&[])), None);
    }
}
