//! Writing Vector BLF: the layouts the [reader](super) reads (file header,
//! version 1 `CAN_MESSAGE` objects with nanosecond timestamps, objects
//! padded by `size % 4`, `LOG_CONTAINER`s of a bounded payload), as
//! python-can's `BLFWriter` writes them, so that other tools read our
//! files and tests and benches build theirs from frames.
//!
//! The library has no zlib: a container is stored unless the caller hands
//! [`BlfWriter::finish`] a [`Deflate`] (flate2's `ZlibEncoder` in the
//! programs), whose output goes into the container with method 2.
//!
//! ```
//! use canopen_codec::trace::blf::{BlfEvent, BlfReader, BlfWriter};
//! use canopen_codec::CanFrame;
//!
//! let mut writer = BlfWriter::new(None, 128 * 1024);
//! writer.push(1_500_000, &CanFrame::standard(0x18A, &[0x74, 0x13]).unwrap(), false);
//! let file = writer.finish(None);
//!
//! let mut reader = BlfReader::new();
//! let mut data = &file[..];
//! let mut frames = Vec::new();
//! while let Some(event) = reader.read(&mut data).unwrap() {
//!     if let BlfEvent::Frame(f) = event {
//!         frames.push(f);
//!     }
//! }
//! reader.finish().unwrap();
//! assert_eq!(frames[0].frame.to_string(), "18A#7413");
//! assert_eq!(frames[0].timestamp.unwrap().as_micros(), 1_500_000);
//! ```

use alloc::vec::Vec;

use super::{object_type, FILE_SIGNATURE, OBJECT_SIGNATURE};
use crate::frame::{CanFrame, CanId};

/// The file header's size, as Vector's tools and python-can write it.
pub const FILE_HEADER_SIZE: usize = 144;
/// The application id, its version, and the BLF version, as python-can
/// writes them in the file header (application 5, version 0.0.0, BLF
/// 2.6.8.1).
const APPLICATION: [u8; 8] = [5, 0, 0, 0, 2, 6, 8, 1];
/// Object flags: the timestamp counts nanoseconds.
pub const TIME_ONE_NANS: u32 = 2;
/// Object flags: the timestamp counts units of 10 us.
pub const TIME_TEN_MICS: u32 = 1;
/// Container compression methods.
const STORED: u16 = 0;
const ZLIB: u16 = 2;

/// A Windows `SYSTEMTIME` as BLF stores the measurement's start and end:
/// year, month, weekday, day, hour, minute, second, millisecond.
pub type SystemTime = [u16; 8];

/// Compresses one container's payload as a zlib stream (RFC 1950): the
/// caller's zlib, since the library has none.
pub trait Deflate {
    /// Appends the zlib stream of `payload` to `out`.
    fn deflate(&mut self, payload: &[u8], out: &mut Vec<u8>);
}

/// The base object header (`LOBJ`, header size, header version, object
/// size, object type) of an object of `size` bytes, header included.
fn base_header(out: &mut Vec<u8>, header_size: u16, version: u16, size: usize, kind: u32) {
    out.extend_from_slice(&OBJECT_SIGNATURE);
    out.extend_from_slice(&header_size.to_le_bytes());
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&u32::try_from(size).unwrap_or(u32::MAX).to_le_bytes());
    out.extend_from_slice(&kind.to_le_bytes());
}

/// Pads an object of `size` bytes that began at `start` of `out` by
/// `size % 4` zero bytes, as python-can does (the reader accepts up to 3).
fn pad(out: &mut Vec<u8>, start: usize, size: usize) {
    out.resize(start + size + size % 4, 0);
}

/// Appends one object with a version 1 header (32 bytes: the base header,
/// then flags, client index, object version and timestamp) and `body`.
/// `flags` gives the timestamp's unit ([`TIME_ONE_NANS`] or
/// [`TIME_TEN_MICS`]); `ticks` counts from the measurement's start.
pub fn object_v1(out: &mut Vec<u8>, kind: u32, flags: u32, ticks: u64, body: &[u8]) {
    const HEADER: u16 = 32;
    let start = out.len();
    let size = usize::from(HEADER) + body.len();
    base_header(out, HEADER, 1, size, kind);
    out.extend_from_slice(&flags.to_le_bytes());
    out.extend_from_slice(&[0; 4]); // client index, object version
    out.extend_from_slice(&ticks.to_le_bytes());
    out.extend_from_slice(body);
    pad(out, start, size);
}

/// The 16-byte `CAN_MESSAGE` body of `frame` on channel 1: channel, flags
/// (bit 0 transmitted, bit 7 remote), DLC, identifier (bit 31 set for a
/// 29-bit one), the data padded to 8 bytes.
#[must_use]
pub fn can_message_body(frame: &CanFrame, transmitted: bool) -> [u8; 16] {
    let id = match frame.id() {
        CanId::Standard(id) => u32::from(id),
        CanId::Extended(id) => id | 1 << 31,
    };
    let flags = u8::from(transmitted) | if frame.is_remote() { 0x80 } else { 0 };
    let mut body = [0u8; 16];
    let (head, data) = body.split_at_mut(8);
    head[..4].copy_from_slice(&[1, 0, flags, frame.dlc()]);
    head[4..].copy_from_slice(&id.to_le_bytes());
    data.copy_from_slice(&frame.padded_data());
    body
}

/// Appends one `LOG_CONTAINER` holding `payload`: stored, or the zlib
/// stream `deflate` makes of it.
pub fn container(out: &mut Vec<u8>, payload: &[u8], deflate: Option<&mut (dyn Deflate + '_)>) {
    const HEADER: u16 = 16;
    let start = out.len();
    // The header is written once the data's length is known.
    out.resize(start + 32, 0);
    let method = match deflate {
        Some(z) => {
            z.deflate(payload, out);
            ZLIB
        }
        None => {
            out.extend_from_slice(payload);
            STORED
        }
    };
    let size = out.len() - start;
    let mut header = Vec::with_capacity(32);
    base_header(&mut header, HEADER, 1, size, object_type::LOG_CONTAINER);
    header.extend_from_slice(&method.to_le_bytes());
    header.extend_from_slice(&[0; 6]);
    let uncompressed = u32::try_from(payload.len()).unwrap_or(u32::MAX);
    header.extend_from_slice(&uncompressed.to_le_bytes());
    header.extend_from_slice(&[0; 4]);
    out[start..start + 32].copy_from_slice(&header);
    pad(out, start, size);
}

/// The file header: signature, its size (144), the application and BLF
/// version (python-can's), the file's size and its size with every
/// container stored, the number of objects (and 0 objects read, as
/// python-can writes), the measurement's start and end.
#[must_use]
pub fn file_header(
    file_size: u64,
    uncompressed_size: u64,
    objects: u32,
    start: Option<SystemTime>,
    end: Option<SystemTime>,
) -> [u8; FILE_HEADER_SIZE] {
    let mut h = [0u8; FILE_HEADER_SIZE];
    let mut fields = Vec::with_capacity(72);
    fields.extend_from_slice(&FILE_SIGNATURE);
    fields.extend_from_slice(&(FILE_HEADER_SIZE as u32).to_le_bytes());
    fields.extend_from_slice(&APPLICATION);
    fields.extend_from_slice(&file_size.to_le_bytes());
    fields.extend_from_slice(&uncompressed_size.to_le_bytes());
    fields.extend_from_slice(&objects.to_le_bytes());
    fields.extend_from_slice(&[0; 4]); // objects read
    for time in [start, end] {
        for v in time.unwrap_or_default() {
            fields.extend_from_slice(&v.to_le_bytes());
        }
    }
    h[..fields.len()].copy_from_slice(&fields);
    h
}

/// A BLF file built in memory: frames go in with their time since the
/// measurement's start, as `CAN_MESSAGE` objects with nanosecond
/// timestamps; containers hold at most `container_payload` bytes of
/// objects each (python-can uses 128 KiB), so an object may straddle two.
#[derive(Debug, Clone)]
pub struct BlfWriter {
    start: Option<SystemTime>,
    container_payload: usize,
    objects: Vec<u8>,
    count: u32,
}

impl BlfWriter {
    /// An empty file whose measurement began at `start` (`None`: zeros).
    #[must_use]
    pub fn new(start: Option<SystemTime>, container_payload: usize) -> Self {
        BlfWriter {
            start,
            container_payload: container_payload.max(1),
            objects: Vec::new(),
            count: 0,
        }
    }

    /// Appends `frame`, seen `micros` after the measurement's start.
    pub fn push(&mut self, micros: u64, frame: &CanFrame, transmitted: bool) {
        let body = can_message_body(frame, transmitted);
        let ns = micros.saturating_mul(1000);
        self.push_object(object_type::CAN_MESSAGE, TIME_ONE_NANS, ns, &body);
    }

    /// Appends any object with a version 1 header (an error frame, a
    /// type the reader skips).
    pub fn push_object(&mut self, kind: u32, flags: u32, ticks: u64, body: &[u8]) {
        object_v1(&mut self.objects, kind, flags, ticks, body);
        self.count = self.count.saturating_add(1);
    }

    /// The whole file: header, then the objects in containers, each
    /// compressed by `deflate` when given.
    #[must_use]
    pub fn finish(self, mut deflate: Option<&mut dyn Deflate>) -> Vec<u8> {
        let mut body = Vec::with_capacity(self.objects.len() + 64);
        let mut uncompressed = FILE_HEADER_SIZE as u64;
        for part in self.objects.chunks(self.container_payload) {
            container(&mut body, part, deflate.as_deref_mut());
            let stored = 32 + part.len();
            uncompressed += (stored + stored % 4) as u64;
        }
        let size = (FILE_HEADER_SIZE + body.len()) as u64;
        let header = file_header(size, uncompressed, self.count, self.start, self.start);
        let mut file = Vec::with_capacity(FILE_HEADER_SIZE + body.len());
        file.extend_from_slice(&header);
        file.extend_from_slice(&body);
        file
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// python-can 4's `BLFWriter(path, compression_level=0)` given one
    /// frame 18A#7413 at its start: a stored container, byte for byte.
    const PYTHON_CAN_ONE_FRAME: &str = concat!(
        "4c4f4747900000000500000002060801e000000000000000e000000000000000",
        "0100000000000000000000000000000000000000000000000000000000000000",
        "0000000000000000000000000000000000000000000000000000000000000000",
        "0000000000000000000000000000000000000000000000000000000000000000",
        "00000000000000000000000000000000",
        "4c4f424a10000100500000000a00000000000000000000003000000000000000",
        "4c4f424a20000100300000000100000002000000000000000000000000000000",
        "010000028a0100007413000000000000",
    );

    fn hex(bytes: &[u8]) -> alloc::string::String {
        bytes.iter().map(|b| format!("{b:02x}")).collect()
    }

    #[test]
    fn one_stored_frame_is_what_python_can_writes() {
        let mut w = BlfWriter::new(None, 128 * 1024);
        w.push(0, &CanFrame::standard(0x18A, &[0x74, 0x13]).unwrap(), false);
        assert_eq!(hex(&w.finish(None)), PYTHON_CAN_ONE_FRAME);
    }

    #[test]
    fn objects_straddle_containers_and_read_back() {
        // Containers of 40 bytes: the 48-byte CAN message straddles two,
        // the 37-byte object (1 padding byte) two more.
        let mut w = BlfWriter::new(None, 40);
        let remote = CanFrame::remote(CanId::Extended(0x18DA_F110), 2).unwrap();
        w.push(10, &remote, true);
        w.push_object(65, TIME_TEN_MICS, 1, b"text!");
        let data = CanFrame::standard(0x70A, &[0x05]).unwrap();
        w.push(2_000, &data, false);
        let file = w.finish(None);
        // 48 + 38 + 48 = 134 bytes of objects in 4 containers.
        let containers: usize = [40, 40, 40, 14].iter().map(|n| 32 + n + (32 + n) % 4).sum();
        assert_eq!(file.len(), FILE_HEADER_SIZE + containers);
        let mut reader = super::super::BlfReader::new();
        let (mut frames, mut skipped) = (alloc::vec::Vec::new(), 0);
        let mut input = &file[..];
        while let Some(event) = reader.read(&mut input).unwrap() {
            match event {
                super::super::BlfEvent::Frame(f) => {
                    frames.push((f.timestamp.unwrap().as_micros(), f.direction, f.frame));
                }
                super::super::BlfEvent::Skipped { object_type: 65 } => skipped += 1,
                _ => {}
            }
        }
        reader.finish().unwrap();
        use super::super::RxTx;
        assert_eq!(frames, [(10, RxTx::Tx, remote), (2_000, RxTx::Rx, data)]);
        assert_eq!(skipped, 1);
    }
}
