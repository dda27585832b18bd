//! The SDO wire layer (`canopen_codec::sdo::SdoFrame`, `ClientCommand`,
//! `ServerCommand`, `BlockSegment`) on any 0..=8 data bytes: never panics;
//! a frame parses exactly when it has the bytes `needed` gives; whatever
//! parses, emitted over the frame's own bytes, gives them back; emitted
//! onto zero bytes (as the machines send it), it parses to the same
//! command.
//!
//! Input layout: the data bytes themselves (inputs above 8 bytes are
//! refused by `SdoFrame::new_checked` and must stay refused).
#![no_main]

use canopen_codec::sdo::{
    needed, BlockSegment, ClientCommand, SdoFrame, SdoRequest, SdoResponse, ServerCommand, Side,
};
use canopen_codec::Codec;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(frame) = SdoFrame::new_checked(data) else {
        assert!(data.is_empty() || data.len() > 8);
        return;
    };
    let mut padded = [0u8; 8];
    padded[..data.len()].copy_from_slice(data);

    let request = ClientCommand::parse(&frame);
    assert_eq!(request.is_ok(), data.len() >= needed(Side::Client, data[0]));
    if let Ok(cmd) = request {
        let mut buf = padded;
        assert!(cmd.emit(&mut buf) <= data.len());
        assert_eq!(buf, padded, "{cmd:?}");
        let mut fresh = [0u8; 8];
        let n = cmd.emit(&mut fresh);
        let again = SdoFrame::new_checked(&fresh[..n]).unwrap();
        assert_eq!(ClientCommand::parse(&again), Ok(cmd));
        let (bytes, len) = SdoRequest::parse(data).unwrap().encode();
        assert_eq!(&bytes[..len], data);
    }

    let response = ServerCommand::parse(&frame);
    assert_eq!(response.is_ok(), data.len() >= needed(Side::Server, data[0]));
    if let Ok(cmd) = response {
        let mut buf = padded;
        assert!(cmd.emit(&mut buf) <= data.len());
        assert_eq!(buf, padded, "{cmd:?}");
        let mut fresh = [0u8; 8];
        let n = cmd.emit(&mut fresh);
        let again = SdoFrame::new_checked(&fresh[..n]).unwrap();
        assert_eq!(ServerCommand::parse(&again), Ok(cmd));
        let (bytes, len) = SdoResponse::parse(data).unwrap().encode();
        assert_eq!(&bytes[..len], data);
    }

    let segment = BlockSegment::parse(&frame);
    let mut buf = padded;
    assert_eq!(segment.emit(&mut buf), data.len());
    assert_eq!(buf, padded);
});
