//! BLF files for the tests, written by the library's writer
//! (`trace::blf::write`), zlib containers by flate2 (a dev-dependency);
//! `object` also writes the version 2 headers the library's writer never
//! does, to test that the reader takes them.
#![allow(dead_code)]

use canopen_codec::trace::blf::write::{self, Deflate, SystemTime, TIME_ONE_NANS, TIME_TEN_MICS};
use canopen_codec::CanFrame;

/// Object flags: timestamps in nanoseconds / in 10 us units.
pub const NS: u32 = TIME_ONE_NANS;
pub const TEN_US: u32 = TIME_TEN_MICS;

/// flate2's zlib, as `canopen-decode` links it.
pub struct Zlib;

impl Deflate for Zlib {
    fn deflate(&mut self, payload: &[u8], out: &mut Vec<u8>) {
        use std::io::Write;
        let mut z = flate2::write::ZlibEncoder::new(out, flate2::Compression::default());
        z.write_all(payload).expect("writing to a Vec");
        z.finish().expect("writing to a Vec");
    }
}

/// An object: base header, v1 (32 bytes, the library's) or v2 (40) header,
/// body, padding.
pub fn object(version: u16, object_type: u32, flags: u32, ticks: u64, body: &[u8]) -> Vec<u8> {
    let mut o = Vec::new();
    if version != 2 {
        write::object_v1(&mut o, object_type, flags, ticks, body);
        return o;
    }
    let size = 40 + body.len();
    o.extend_from_slice(b"LOBJ");
    o.extend_from_slice(&40u16.to_le_bytes());
    o.extend_from_slice(&2u16.to_le_bytes());
    o.extend_from_slice(&(size as u32).to_le_bytes());
    o.extend_from_slice(&object_type.to_le_bytes());
    o.extend_from_slice(&flags.to_le_bytes());
    o.extend_from_slice(&[0; 4]);
    o.extend_from_slice(&ticks.to_le_bytes());
    o.extend_from_slice(&ticks.to_le_bytes());
    o.extend_from_slice(body);
    o.resize(size + size % 4, 0);
    o
}

/// A CAN_MESSAGE body of `frame` (channel 1; flags bit 0 Tx, bit 7 RTR).
pub fn can_body(frame: &CanFrame, tx: bool) -> Vec<u8> {
    write::can_message_body(frame, tx).to_vec()
}

/// A container of `payload`: stored, or zlib.
pub fn container(zlib: bool, payload: &[u8]) -> Vec<u8> {
    let mut o = Vec::new();
    let mut z = Zlib;
    write::container(&mut o, payload, if zlib { Some(&mut z) } else { None });
    o
}

/// The 144-byte file header; `start` a SYSTEMTIME (year, month, weekday,
/// day, hour, minute, second, ms), zeros for none; sizes and counts zero
/// (the reader does not need them).
pub fn header(start: SystemTime) -> Vec<u8> {
    write::file_header(0, 0, 0, Some(start), None).to_vec()
}

/// A file of `objects` in containers of at most `max` payload bytes.
pub fn file(start: SystemTime, objects: &[u8], max: usize, zlib: bool) -> Vec<u8> {
    let mut f = header(start);
    for part in objects.chunks(max.max(1)) {
        f.extend(container(zlib, part));
    }
    f
}

/// `frames` as v1 CAN_MESSAGE objects, times (us since the start) in ns.
pub fn can_objects(frames: &[(u64, CanFrame)]) -> Vec<u8> {
    frames
        .iter()
        .flat_map(|(us, f)| object(1, 1, NS, us * 1000, &can_body(f, false)))
        .collect()
}
