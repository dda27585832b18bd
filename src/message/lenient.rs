//! Reading frames that deviate from CiA 301 in harmless ways, for log
//! readers (lenient in, strict out: the state machines stay strict).
//!
//! Real devices send NMT commands of 1 byte, TIME frames of 8 bytes, EMCY
//! frames of fewer than 8 and SYNC or heartbeat frames with extra bytes.
//! [`Message::decode_lenient`] reads such a frame as far as it goes and says
//! how it deviates ([`Deviation`]); [`Message::decode`] refuses it.

use core::fmt;

use crate::cob_id::{classify, CobKind};
use crate::error::DecodeError;
use crate::frame::CanFrame;
use crate::lss::{LssMessage, LssRequest, LssResponse};
use crate::message::Message;

/// How a frame deviates from the layout CiA 301 gives its object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Deviation {
    /// Fewer bytes than the layout has; the missing ones were read as 0.
    Short {
        /// Bytes the layout has.
        need: usize,
        /// Bytes the frame has.
        got: usize,
    },
    /// More bytes than the layout has; the extra ones were ignored.
    Long {
        /// Bytes the layout has at most.
        max: usize,
        /// Bytes the frame has.
        got: usize,
    },
    /// Reserved bytes (from byte `from` on) that are not zero; they were
    /// read as zero (LSS, CiA 305).
    ReservedNotZero {
        /// The first reserved byte.
        from: usize,
    },
}

impl fmt::Display for Deviation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Deviation::Short { need, got } => write!(
                f,
                "{got} bytes where CiA 301 has {need} (the missing ones read as 0)"
            ),
            Deviation::Long { max, got } => write!(
                f,
                "{got} bytes where CiA 301 has at most {max} (the extra ones ignored)"
            ),
            Deviation::ReservedNotZero { from } => {
                write!(f, "reserved bytes {from}..=7 not zero (read as 0, CiA 305)")
            }
        }
    }
}

impl Message {
    /// Decodes like [`Message::decode`], but a frame of a fixed-layout
    /// object with the wrong length is read as far as it goes and the
    /// deviation returned (the only frames `Message::decode` accepts that
    /// this reads differently are the LSS frames it keeps raw, below):
    ///
    /// - NMT with 1 byte (the node byte read as 0, all nodes), EMCY with
    ///   fewer than 8 bytes (missing bytes read as 0);
    /// - TIME with more than 6 bytes, SYNC with more than 1, NMT with more
    ///   than 2, EMCY with more than 8 (impossible on classic CAN) and
    ///   heartbeat with more than 1 (extra bytes ignored).
    ///
    /// - LSS (CiA 305) with a listed command specifier but fewer than 8
    ///   bytes (missing bytes read as 0) or reserved bytes that are not
    ///   zero (read as 0), which [`Message::decode`] keeps raw.
    ///
    /// An empty NMT, TIME or heartbeat frame, SDO frames (which have their
    /// own leniency) and remote frames where none are defined stay errors.
    ///
    /// ```
    /// use canopen_codec::message::lenient::Deviation;
    /// use canopen_codec::{CanFrame, Message};
    /// let time = CanFrame::standard(0x100, &[0, 0, 0, 0, 0x10, 0x27, 0xAA, 0xBB]).unwrap();
    /// assert!(Message::decode(&time).is_err());
    /// let (msg, deviation) = Message::decode_lenient(&time).unwrap();
    /// assert!(matches!(msg, Message::Time(_)));
    /// assert_eq!(deviation, Some(Deviation::Long { max: 6, got: 8 }));
    /// ```
    pub fn decode_lenient(frame: &CanFrame) -> Result<(Message, Option<Deviation>), DecodeError> {
        let err = match Message::decode(frame) {
            Ok(Message::Lss(lss)) => return Ok(lss_lenient(frame, lss)),
            Ok(m) => return Ok((m, None)),
            Err(e) => e,
        };
        let kind = classify(frame.id());
        let (len, deviation) = match (kind, err) {
            (CobKind::Emcy(_), DecodeError::Truncated { need, got })
            | (CobKind::Nmt, DecodeError::Truncated { need, got: got @ 1 }) => {
                (need, Deviation::Short { need, got })
            }
            (
                CobKind::Nmt
                | CobKind::Sync
                | CobKind::Time
                | CobKind::Emcy(_)
                | CobKind::NmtErrorControl(_),
                DecodeError::TooLong { max, got },
            ) => (max, Deviation::Long { max, got }),
            _ => return Err(err),
        };
        let mut bytes = [0u8; 8];
        for (d, s) in bytes.iter_mut().zip(frame.data()) {
            *d = *s;
        }
        let repaired =
            CanFrame::new(frame.id(), bytes.get(..len).unwrap_or(&[])).map_err(|_| err)?;
        let msg = Message::decode(&repaired).map_err(|_| err)?;
        Ok((msg, Some(deviation)))
    }
}

/// An LSS frame kept raw that becomes a listed service once padded to 8
/// bytes or once its trailing reserved bytes are read as 0.
fn lss_lenient(frame: &CanFrame, lss: LssMessage) -> (Message, Option<Deviation>) {
    let raw = matches!(
        lss,
        LssMessage::Request(LssRequest::Other(_)) | LssMessage::Response(LssResponse::Other(_))
    );
    let data = frame.data();
    if !raw || data.is_empty() {
        return (Message::Lss(lss), None);
    }
    let typed = |bytes: &[u8]| {
        LssMessage::parse(lss.direction(), bytes).ok().filter(|m| {
            !matches!(
                m,
                LssMessage::Request(LssRequest::Other(_))
                    | LssMessage::Response(LssResponse::Other(_))
            )
        })
    };
    let mut bytes = [0u8; 8];
    crate::bytes::copy_payload(&mut bytes, data);
    if data.len() < 8 {
        return match typed(&bytes) {
            Some(m) => (
                Message::Lss(m),
                Some(Deviation::Short {
                    need: 8,
                    got: data.len(),
                }),
            ),
            None => (Message::Lss(lss), None),
        };
    }
    // The fewest trailing bytes read as 0 that make it a listed service.
    for from in (1..8usize).rev() {
        let mut masked = bytes;
        for b in masked.iter_mut().skip(from) {
            *b = 0;
        }
        if let Some(m) = typed(&masked) {
            return (Message::Lss(m), Some(Deviation::ReservedNotZero { from }));
        }
    }
    (Message::Lss(lss), None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    use crate::frame::standard_frame as f;

    #[test]
    fn every_deviation_row() {
        // (frame, deviation, what it reads as)
        let rows: [(CanFrame, Option<Deviation>, &str); 8] = [
            (
                f(0x000, &[0x01]),
                Some(Deviation::Short { need: 2, got: 1 }),
                "NMT start, all nodes",
            ),
            (
                f(0x000, &[0x01, 0x0A, 0x00]),
                Some(Deviation::Long { max: 2, got: 3 }),
                "NMT start, node 10",
            ),
            (
                f(0x08A, &[]),
                Some(Deviation::Short { need: 8, got: 0 }),
                "EMCY node 10: 0000h",
            ),
            (
                f(0x08A, &[0x30, 0x81, 0x01]),
                Some(Deviation::Short { need: 8, got: 3 }),
                "EMCY node 10: 8130h",
            ),
            (
                f(0x080, &[1, 2]),
                Some(Deviation::Long { max: 1, got: 2 }),
                "SYNC",
            ),
            (
                f(0x100, &[0; 8]),
                Some(Deviation::Long { max: 6, got: 8 }),
                "TIME",
            ),
            (
                f(0x70A, &[0x05, 0xFF]),
                Some(Deviation::Long { max: 1, got: 2 }),
                "heartbeat node 10: operational",
            ),
            (f(0x70A, &[0x05]), None, "heartbeat node 10: operational"),
        ];
        for (frame, want, text) in rows {
            let (msg, got) = Message::decode_lenient(&frame).unwrap();
            assert_eq!(got, want, "{frame}");
            assert!(msg.to_string().starts_with(text), "{frame}: {msg}");
            assert_eq!(Message::decode(&frame).is_ok(), want.is_none(), "{frame}");
        }
        // Still errors: empty NMT / TIME / heartbeat, short SDO, remote SYNC.
        for frame in [
            f(0x000, &[]),
            f(0x100, &[1, 2]),
            f(0x70A, &[]),
            f(0x60A, &[0x40]),
            CanFrame::remote(crate::CanId::Standard(0x080), 0).unwrap(),
        ] {
            assert_eq!(
                Message::decode_lenient(&frame).err(),
                Message::decode(&frame).err(),
                "{frame}"
            );
        }
        assert_eq!(
            Deviation::Short { need: 8, got: 3 }.to_string(),
            "3 bytes where CiA 301 has 8 (the missing ones read as 0)"
        );
    }

    #[test]
    fn lss_short_and_reserved_set_frames() {
        let rows: [(CanFrame, Option<Deviation>, &str); 6] = [
            (
                f(0x7E5, &[0x04, 0x01]),
                Some(Deviation::Short { need: 8, got: 2 }),
                "LSS master: switch state global configuration",
            ),
            (
                f(0x7E4, &[0x4F]),
                Some(Deviation::Short { need: 8, got: 1 }),
                "LSS slave: identify slave",
            ),
            (
                f(0x7E5, &[0x11, 0x05, 0, 0, 0, 0, 0, 0xAA]),
                Some(Deviation::ReservedNotZero { from: 7 }),
                "LSS master: configure node-ID 5",
            ),
            (
                f(0x7E4, &[0x5E, 0x05, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]),
                Some(Deviation::ReservedNotZero { from: 2 }),
                "LSS slave: node-ID 5",
            ),
            // Unlisted, or listed and strict: as Message::decode reads them.
            (
                f(0x7E5, &[0x99, 1, 2, 3, 4, 5, 6, 7]),
                None,
                "LSS master: unknown",
            ),
            (
                f(0x7E5, &[0x51, 1, 2, 3, 4, 5, 6, 7]),
                None,
                "LSS fastscan id 04030201 bit 5 sub 6 next 7",
            ),
        ];
        for (frame, want, text) in rows {
            let (msg, got) = Message::decode_lenient(&frame).unwrap();
            assert_eq!(got, want, "{frame}");
            assert!(msg.to_string().starts_with(text), "{frame}: {msg}");
            if want.is_none() {
                assert_eq!(Message::decode(&frame).unwrap(), msg);
            }
        }
        assert_eq!(
            Deviation::ReservedNotZero { from: 2 }.to_string(),
            "reserved bytes 2..=7 not zero (read as 0, CiA 305)"
        );
        let empty = f(0x7E5, &[]);
        assert_eq!(Message::decode_lenient(&empty).unwrap().1, None);
    }
}
