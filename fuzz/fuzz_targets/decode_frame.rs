//! `Message::decode` (and `decode_lenient`) on any classic CAN frame: never
//! panics, and whatever
//! decodes re-encodes to the identical frame.
//!
//! Input layout (raw bytes, no `Arbitrary`, so the fuzzer's mutations map
//! straight onto frame fields):
//!
//! - byte 0: bit 0 extended (29-bit) id, bit 1 remote frame, bits 4-7 length
//!   (taken modulo 9; the data length of a data frame, the DLC of a remote
//!   frame);
//! - then the identifier, little-endian: 2 bytes masked to 11 bits, or 4 bytes
//!   masked to 29 bits;
//! - then up to `length` data bytes (fewer if the input ends first).
#![no_main]

use core::fmt::{self, Write};

use canopen_codec::cob_id::classify;
use canopen_codec::lss::{LssMessage, LssRequest, LssResponse};
use canopen_codec::{CanFrame, CanId, Message};
use libfuzzer_sys::fuzz_target;

/// A `fmt::Write` that throws its input away: exercises `Debug`/`Display`
/// without allocating.
struct Sink;

impl Write for Sink {
    fn write_str(&mut self, _: &str) -> fmt::Result {
        Ok(())
    }
}

fn frame_from(bytes: &[u8]) -> Option<CanFrame> {
    let (&flags, rest) = bytes.split_first()?;
    let extended = flags & 0x01 != 0;
    let remote = flags & 0x02 != 0;
    let len = (flags >> 4) % 9;
    let (id, rest) = if extended {
        let (raw, rest) = rest.split_first_chunk::<4>()?;
        (CanId::Extended(u32::from_le_bytes(*raw) & 0x1FFF_FFFF), rest)
    } else {
        let (raw, rest) = rest.split_first_chunk::<2>()?;
        (CanId::Standard(u16::from_le_bytes(*raw) & 0x7FF), rest)
    };
    let frame = if remote {
        CanFrame::remote(id, len)
    } else {
        CanFrame::new(id, &rest[..rest.len().min(usize::from(len))])
    };
    // Every id is masked into range and every length is <= 8.
    Some(frame.expect("in-range frame must build"))
}

fuzz_target!(|bytes: &[u8]| {
    let Some(frame) = frame_from(bytes) else {
        return;
    };
    let _ = write!(Sink, "{frame} {frame:?}");
    match Message::decode(&frame) {
        Ok(msg) => {
            assert_eq!(msg.encode(), frame, "round trip of {msg:?}");
            assert_eq!(msg.kind(), classify(frame.id()), "kind of {msg:?}");
            assert_eq!(msg.node(), msg.kind().node(), "node of {msg:?}");
            let _ = write!(Sink, "{msg:?}");
        }
        Err(err) => {
            let _ = write!(Sink, "{err} {err:?}");
        }
    }
    // The lenient reading agrees with the strict one where that succeeds
    // (but for an LSS frame kept raw, which it may read as its service
    // with a deviation), and otherwise says how the frame deviates (or
    // fails the same way).
    match (Message::decode(&frame), Message::decode_lenient(&frame)) {
        (
            Ok(Message::Lss(
                LssMessage::Request(LssRequest::Other(_))
                | LssMessage::Response(LssResponse::Other(_)),
            )),
            Ok((msg, Some(_))),
        ) => {
            assert_eq!(msg.kind(), classify(frame.id()), "{frame}");
            assert!(matches!(msg, Message::Lss(_)), "{frame}");
        }
        (Ok(strict), lenient) => assert_eq!(lenient, Ok((strict, None))),
        (Err(err), Ok((msg, deviation))) => {
            assert!(deviation.is_some(), "{frame}: read leniently without a deviation");
            assert_eq!(msg.kind(), classify(frame.id()), "{frame}");
            let _ = write!(Sink, "{err} {msg}");
        }
        (Err(err), Err(again)) => assert_eq!(err, again, "{frame}"),
    }
});
