//! The SDO client's response decoder without segmented (and block)
//! transfer (feature `sdo-client-segmented` off): only the commands an
//! expedited client takes are built.

use super::{DecodeError, RawSdo, Reader, ServerCommand};
use crate::frame::CanFrame;

impl ServerCommand {
    /// The decoder of a client without segmented (and block) transfer
    /// (feature `sdo-client-segmented` off): the commands it takes (scs 2,
    /// 3 and 4: initiate upload, initiate download, abort) as `of_frame`
    /// decodes them; every other command as `Unknown` with its byte 0 (the
    /// client aborts it as a command that does not fit, 05040001h), after
    /// the same length check, so that a frame too short for its command is
    /// still an error (and ignored), not a command.
    pub(crate) fn of_frame_expedited(frame: &CanFrame) -> Result<Self, DecodeError> {
        let raw = RawSdo::of_frame(frame);
        let r = Reader { raw: &raw };
        r.need(1)?;
        let cmd = r.b(0);
        Ok(match cmd >> 5 {
            2 => {
                let (index, sub) = r.multiplexer()?;
                ServerCommand::InitiateUpload {
                    index,
                    sub,
                    payload: r.initiate_payload()?,
                }
            }
            3 => {
                let (index, sub) = r.multiplexer()?;
                ServerCommand::InitiateDownload { index, sub }
            }
            4 => {
                let (index, sub, code) = r.abort()?;
                ServerCommand::Abort { index, sub, code }
            }
            _ => {
                r.need(other_len(cmd))?;
                ServerCommand::Unknown(cmd)
            }
        })
    }
}

/// The bytes `decode_raw` needs for a command of scs 0, 1, 5, 6 or 7 with
/// byte 0 `cmd`.
const fn other_len(cmd: u8) -> usize {
    match cmd >> 5 {
        // A segment: byte 0 and 7 - n data bytes.
        0 => 8 - ((cmd >> 1) & 0x07) as usize,
        // Block download: initiate (blksize in byte 4), ack (bytes 1, 2).
        5 => match cmd & 0x03 {
            0 => 5,
            2 => 3,
            _ => 1,
        },
        // Block upload: end (CRC in bytes 1, 2), initiate (+ size).
        6 => {
            if cmd & 0x01 != 0 {
                3
            } else if cmd & 0x02 != 0 {
                8
            } else {
                4
            }
        }
        _ => 1,
    }
}
