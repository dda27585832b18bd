//! Every protocol's wire representation (`canopen_codec::wire::Codec`) on
//! any payload: `parse` never panics; whatever parses emits back exactly
//! the bytes it came from (`buffer_len` of them); the frame fast path
//! (`parse_frame`) reads a frame as `parse` reads its bytes, and refuses a
//! remote frame.
//!
//! Input layout: byte 0 is the payload length (taken modulo 9), the rest
//! the payload (fewer bytes if the input ends first).
#![no_main]

use canopen_codec::bytes::Payload;
use canopen_codec::emcy::Emergency;
use canopen_codec::lss::{LssRequest, LssResponse};
use canopen_codec::nmt::{Heartbeat, NmtCommand};
use canopen_codec::sdo::{SdoRequest, SdoResponse};
use canopen_codec::sync::SyncMessage;
use canopen_codec::time::TimeOfDay;
use canopen_codec::{CanFrame, CanId, Codec, DecodeError};
use libfuzzer_sys::fuzz_target;

fn check<T: Codec + core::fmt::Debug + PartialEq>(data: &[u8]) {
    if let Ok(value) = T::parse(data) {
        let mut buf = [0xA5u8; 8];
        let len = value.emit(&mut buf);
        assert_eq!(len, value.buffer_len(), "{value:?}");
        assert_eq!(&buf[..len], data, "round trip of {value:?}");
    }
    let frame = CanFrame::new(CanId::Standard(0x123), data).expect("0..=8 bytes");
    assert_eq!(T::parse_frame(&frame), T::parse(data), "{frame}");
    let remote = CanFrame::remote(CanId::Standard(0x123), frame.dlc()).expect("DLC 0..=8");
    assert_eq!(T::parse_frame(&remote).err(), Some(DecodeError::UnexpectedRemote));
}

fuzz_target!(|bytes: &[u8]| {
    let Some((&len, rest)) = bytes.split_first() else {
        return;
    };
    let data = &rest[..rest.len().min(usize::from(len % 9))];
    check::<NmtCommand>(data);
    check::<Heartbeat>(data);
    check::<Emergency>(data);
    check::<SyncMessage>(data);
    check::<TimeOfDay>(data);
    check::<LssRequest>(data);
    check::<LssResponse>(data);
    check::<Payload>(data);
    check::<SdoRequest>(data);
    check::<SdoResponse>(data);
});
