//! A tiny Vector BLF writer for the tests and benches (the layouts of the
//! `trace::blf` module docs): file header, v1 / v2 objects with `size % 4`
//! padding, CAN_MESSAGE bodies, stored and zlib containers (flate2, a
//! dev-dependency) cut at a given payload size so that objects straddle.
#![allow(dead_code)]

use canopen_codec::{CanFrame, CanId};

/// Object flags: timestamps in nanoseconds / in 10 us units.
pub const NS: u32 = 2;
pub const TEN_US: u32 = 1;

/// An object: base header, v1 (32 bytes) or v2 (40) header, body, padding.
pub fn object(version: u16, object_type: u32, flags: u32, ticks: u64, body: &[u8]) -> Vec<u8> {
    let header = if version == 2 { 40 } else { 32 };
    let size = header + body.len();
    let mut o = Vec::with_capacity(size + 3);
    o.extend_from_slice(b"LOBJ");
    o.extend_from_slice(&(header as u16).to_le_bytes());
    o.extend_from_slice(&version.to_le_bytes());
    o.extend_from_slice(&(size as u32).to_le_bytes());
    o.extend_from_slice(&object_type.to_le_bytes());
    o.extend_from_slice(&flags.to_le_bytes());
    o.extend_from_slice(&[0; 4]);
    o.extend_from_slice(&ticks.to_le_bytes());
    if version == 2 {
        o.extend_from_slice(&ticks.to_le_bytes());
    }
    o.extend_from_slice(body);
    o.resize(size + size % 4, 0);
    o
}

/// A CAN_MESSAGE body of `frame` (channel 1; flags bit 0 Tx, bit 7 RTR).
pub fn can_body(frame: &CanFrame, tx: bool) -> Vec<u8> {
    let id = match frame.id() {
        CanId::Standard(id) => u32::from(id),
        CanId::Extended(id) => id | 1 << 31,
    };
    let flags = u8::from(tx) | if frame.is_remote() { 0x80 } else { 0 };
    let mut b = vec![1, 0, flags, frame.dlc()];
    b.extend_from_slice(&id.to_le_bytes());
    b.extend_from_slice(&frame.padded_data());
    b
}

/// A container of `payload`: method 0 stored, 2 zlib.
pub fn container(zlib: bool, payload: &[u8]) -> Vec<u8> {
    let data = if zlib {
        use std::io::Write;
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(payload).unwrap();
        z.finish().unwrap()
    } else {
        payload.to_vec()
    };
    let size = 32 + data.len();
    let mut o = Vec::with_capacity(size + 3);
    o.extend_from_slice(b"LOBJ");
    o.extend_from_slice(&16u16.to_le_bytes());
    o.extend_from_slice(&1u16.to_le_bytes());
    o.extend_from_slice(&(size as u32).to_le_bytes());
    o.extend_from_slice(&10u32.to_le_bytes());
    o.extend_from_slice(&(if zlib { 2u16 } else { 0 }).to_le_bytes());
    o.extend_from_slice(&[0; 6]);
    o.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    o.extend_from_slice(&[0; 4]);
    o.extend_from_slice(&data);
    o.resize(size + size % 4, 0);
    o
}

/// The 144-byte file header; `start` a SYSTEMTIME (year, month, weekday,
/// day, hour, minute, second, ms), zeros for none.
pub fn header(start: [u16; 8]) -> Vec<u8> {
    let mut h = vec![0u8; 144];
    h[..4].copy_from_slice(b"LOGG");
    h[4..8].copy_from_slice(&144u32.to_le_bytes());
    h[8] = 5;
    for (i, v) in start.iter().enumerate() {
        h[40 + 2 * i..42 + 2 * i].copy_from_slice(&v.to_le_bytes());
    }
    h
}

/// A file of `objects` in containers of at most `max` payload bytes.
pub fn file(start: [u16; 8], objects: &[u8], max: usize, zlib: bool) -> Vec<u8> {
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
