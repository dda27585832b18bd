//! The MF4 reader on hand-built files: a tiny writer of the blocks the
//! module docs give (python-can's layout: a float64 time channel and a
//! composed `CAN_DataFrame` channel with its members), then each error
//! case named on a file broken in one place.

use super::*;
use crate::trace::inflate::{Inflate, NoInflate, Zlib};
use std::io::Write;
use std::string::{String, ToString};
use std::vec;
use std::vec::Vec;

/// A file being built: blocks appended, links patched by offset.
struct File(Vec<u8>);

impl File {
    /// The `##ID` block of version `version`.
    fn new(version: u16) -> Self {
        let mut f = b"MDF     4.10    test    ".to_vec();
        f.resize(64, 0);
        f[28..30].copy_from_slice(&version.to_le_bytes());
        File(f)
    }

    /// Appends a block; its offset.
    fn block(&mut self, id: &[u8; 4], links: &[u64], data: &[u8]) -> u64 {
        let at = self.0.len() as u64;
        let len = 24 + 8 * links.len() + data.len();
        self.0.extend_from_slice(id);
        self.0.extend_from_slice(&[0; 4]);
        self.0.extend_from_slice(&(len as u64).to_le_bytes());
        self.0
            .extend_from_slice(&(links.len() as u64).to_le_bytes());
        for l in links {
            self.0.extend_from_slice(&l.to_le_bytes());
        }
        self.0.extend_from_slice(data);
        while !self.0.len().is_multiple_of(8) {
            self.0.push(0);
        }
        at
    }

    /// Sets link `i` of the block at `at`.
    fn link(&mut self, at: u64, i: usize, to: u64) {
        let p = at as usize + 24 + 8 * i;
        self.0[p..p + 8].copy_from_slice(&to.to_le_bytes());
    }

    fn tx(&mut self, text: &str) -> u64 {
        let mut d = text.as_bytes().to_vec();
        d.push(0);
        self.block(b"##TX", &[], &d)
    }

    /// A channel: type, sync, data type, byte offset, bits.
    fn cn(&mut self, name: &str, kind: [u8; 3], byte: u32, bits: u32, cc: u64) -> u64 {
        let name = self.tx(name);
        let mut d = vec![kind[0], kind[1], kind[2], 0];
        d.extend_from_slice(&byte.to_le_bytes());
        d.extend_from_slice(&bits.to_le_bytes());
        d.resize(72, 0);
        self.block(b"##CN", &[0, 0, name, 0, cc, 0, 0, 0], &d)
    }
}

/// One frame: seconds since the start, id, IDE, data, Dir, EDL.
type Row = (f64, u32, u8, &'static [u8], u8, u8);

/// python-can's record: time f64, BusChannel, ID u32, IDE, DLC,
/// DataLength, 8 DataBytes, Dir, EDL (`prefix.` names).
fn record(r: &Row) -> Vec<u8> {
    let (t, id, ide, data, dir, edl) = *r;
    let mut v = t.to_le_bytes().to_vec();
    v.push(1);
    v.extend_from_slice(&id.to_le_bytes());
    v.extend_from_slice(&[ide, data.len() as u8, data.len() as u8]);
    let mut bytes = [0u8; 8];
    bytes[..data.len()].copy_from_slice(data);
    v.extend_from_slice(&bytes);
    v.extend_from_slice(&[dir, edl]);
    v
}

/// Record size: 8 + 1 + 4 + 3 + 8 + 2.
const RECORD: u32 = 26;

/// The channel group of an event type (`CAN_DataFrame`), with the time
/// conversion `cc` (0 none); its offset.
fn channel_group(f: &mut File, event: &str, record_id: u64, cc: u64) -> u64 {
    let time = f.cn("t", [2, 1, 4], 0, 64, cc);
    let members = [
        ("BusChannel", 8, 8),
        ("ID", 9, 32),
        ("IDE", 13, 8),
        ("DLC", 14, 8),
        ("DataLength", 15, 8),
        ("DataBytes", 16, 64),
        ("Dir", 24, 8),
        ("EDL", 25, 8),
    ];
    let mut first = 0;
    for (name, byte, bits) in members.iter().rev() {
        let dt = if *name == "DataBytes" { 10 } else { 0 };
        let cn = f.cn(&format!("{event}.{name}"), [0, 0, dt], *byte, *bits, 0);
        f.link(cn, 0, first);
        first = cn;
    }
    let composed = f.cn(event, [0, 0, 10], 8, 8 * (RECORD - 8), 0);
    f.link(composed, 1, first);
    f.link(time, 0, composed);
    let mut d = record_id.to_le_bytes().to_vec();
    d.extend_from_slice(&0u64.to_le_bytes()); // cycle count
    d.extend_from_slice(&6u16.to_le_bytes()); // bus event flags
    d.extend_from_slice(&[0; 6]);
    d.extend_from_slice(&RECORD.to_le_bytes());
    d.extend_from_slice(&0u32.to_le_bytes());
    f.block(b"##CG", &[0, time, 0, 0, 0, 0], &d)
}

/// The start: 2025-09-04 (ns).
const START_NS: u64 = 1_757_000_000_000_000_000;

/// A sorted file, one data group of `CAN_DataFrame` whose data link is
/// made by `data` from the records' bytes.
fn sorted(rows: &[Row], data: impl FnOnce(&mut File, &[u8]) -> u64) -> Vec<u8> {
    let mut f = File::new(410);
    let mut hd = START_NS.to_le_bytes().to_vec();
    hd.resize(32, 0);
    let hd_at = f.block(b"##HD", &[0, 0, 0, 0, 0, 0], &hd);
    let cg = channel_group(&mut f, "CAN_DataFrame", 0, 0);
    let bytes: Vec<u8> = rows.iter().flat_map(record).collect();
    let data = data(&mut f, &bytes);
    let dg = f.block(b"##DG", &[0, cg, data, 0], &[0; 8]);
    f.link(hd_at, 0, dg);
    f.0
}

fn dt(f: &mut File, bytes: &[u8]) -> u64 {
    f.block(b"##DT", &[], bytes)
}

/// A `##DZ` of `bytes`: zip type 0, or 1 transposed by `columns`.
fn dz(f: &mut File, bytes: &[u8], zip: u8, columns: u32) -> u64 {
    let raw = if zip == 1 {
        let rows = bytes.len() / columns as usize;
        let mut t = vec![0u8; rows * columns as usize];
        for r in 0..rows {
            for c in 0..columns as usize {
                t[c * rows + r] = bytes[r * columns as usize + c];
            }
        }
        t.extend_from_slice(&bytes[t.len()..]);
        t
    } else {
        bytes.to_vec()
    };
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(&raw).unwrap();
    let z = z.finish().unwrap();
    let mut d = b"DT".to_vec();
    d.extend_from_slice(&[zip, 0]);
    d.extend_from_slice(&columns.to_le_bytes());
    d.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    d.extend_from_slice(&(z.len() as u64).to_le_bytes());
    d.extend_from_slice(&z);
    f.block(b"##DZ", &[], &d)
}

/// A `##DL` of the given data blocks.
fn dl(f: &mut File, next: u64, blocks: &[u64]) -> u64 {
    let mut links = vec![next];
    links.extend_from_slice(blocks);
    let mut d = vec![0u8; 4];
    d.extend_from_slice(&(blocks.len() as u32).to_le_bytes());
    d.extend_from_slice(&[0; 8]);
    f.block(b"##DL", &links, &d)
}

const ROWS: [Row; 4] = [
    (0.25, 0x18A, 0, &[0x74, 0x13], 0, 0),
    (0.5, 0x701, 0, &[0x05], 1, 0),
    (0.75, 0x1234_5678, 1, &[1, 2, 3, 4, 5, 6, 7, 8], 0, 0),
    (1.0, 0x123, 0, &[9; 8], 0, 1),
];

/// Every event of `file`, with the end.
fn read_all<S: Source>(file: S, zlib: &mut dyn Inflate) -> (Vec<String>, Result<(), Mf4Error>) {
    let mut out = Vec::new();
    let mut r = match Mf4Reader::new(file) {
        Ok(r) => r,
        Err(e) => return (out, Err(e)),
    };
    loop {
        match r.next(zlib) {
            Ok(None) => return (out, Ok(())),
            Ok(Some(Mf4Event::Frame(f))) => out.push(format!(
                "{} {} {:?} {:?}",
                f.timestamp.map_or(0, Timestamp::as_micros),
                f.frame,
                f.direction,
                f.channel
            )),
            Ok(Some(Mf4Event::Unsupported { what, timestamp })) => out.push(format!(
                "{} {what:?}",
                timestamp.map_or(0, Timestamp::as_micros)
            )),
            Err(e) if e.is_fatal() => return (out, Err(e)),
            Err(e) => out.push(format!("bad: {e}")),
        }
    }
}

fn expected() -> Vec<String> {
    [
        "1757000000250000 18A#7413 Some(Rx) Some(1)",
        "1757000000500000 701#05 Some(Tx) Some(1)",
        "1757000000750000 12345678#0102030405060708 Some(Rx) Some(1)",
        "1757000001000000 CanFd",
    ]
    .map(String::from)
    .to_vec()
}

#[test]
fn a_sorted_group_in_one_data_block_reads_every_frame_with_its_time() {
    let file = sorted(&ROWS, dt);
    assert!(Mf4Reader::detect(&file));
    let r = Mf4Reader::new(&file).unwrap();
    assert_eq!(r.header().version, 410);
    assert_eq!(r.header().start.unwrap().as_micros(), START_NS / 1000);
    assert_eq!(read_all(&file, &mut NoInflate), (expected(), Ok(())));
}

#[test]
fn deflated_and_transposed_blocks_read_as_the_stored_one() {
    for (zip, columns) in [(0, 0), (1, RECORD), (1, 7)] {
        let file = sorted(&ROWS, |f, b| dz(f, b, zip, columns));
        assert_eq!(
            read_all(&file, &mut Zlib::default()),
            (expected(), Ok(())),
            "zip {zip} columns {columns}"
        );
        // Without an inflater the compressed block is the error.
        assert!(matches!(
            read_all(&file, &mut NoInflate).1,
            Err(Mf4Error::Inflate { .. })
        ));
    }
}

#[test]
fn a_record_split_across_the_blocks_of_a_list_and_its_chain_is_whole() {
    let file = sorted(&ROWS, |f, b| {
        let (a, rest) = b.split_at(30);
        let (c, d) = rest.split_at(40);
        let tail = [dz(f, d, 1, RECORD)];
        let second = dl(f, 0, &tail);
        let first = [dt(f, a), dz(f, c, 0, 0)];
        let list = dl(f, second, &first);
        f.block(b"##HL", &[list], &[0; 8])
    });
    assert_eq!(read_all(&file, &mut Zlib::default()), (expected(), Ok(())));
}

/// An unsorted data group (1-byte record ids): `CAN_DataFrame` (id 1),
/// `CAN_RemoteFrame` (2), a signal group of 3-byte records (3) and a
/// variable-length group (4), their records interleaved.
fn unsorted(bytes: &[u8]) -> Vec<u8> {
    let mut f = File::new(411);
    let mut hd = START_NS.to_le_bytes().to_vec();
    hd.resize(32, 0);
    let hd_at = f.block(b"##HD", &[0, 0, 0, 0, 0, 0], &hd);
    let data = channel_group(&mut f, "CAN_DataFrame", 1, 0);
    let remote = channel_group(&mut f, "CAN_RemoteFrame", 2, 0);
    let signal = f.cn("speed", [0, 0, 0], 0, 24, 0);
    let mut d = 3u64.to_le_bytes().to_vec();
    d.extend_from_slice(&[0; 16]);
    d.extend_from_slice(&3u32.to_le_bytes());
    d.extend_from_slice(&0u32.to_le_bytes());
    let other = f.block(b"##CG", &[0, signal, 0, 0, 0, 0], &d);
    let mut d = 4u64.to_le_bytes().to_vec();
    d.extend_from_slice(&[0; 8]);
    d.extend_from_slice(&1u16.to_le_bytes());
    d.resize(32, 0);
    let variable = f.block(b"##CG", &[0, 0, 0, 0, 0, 0], &d);
    f.link(data, 0, remote);
    f.link(remote, 0, other);
    f.link(other, 0, variable);
    let dt = f.block(b"##DT", &[], bytes);
    let dg = f.block(b"##DG", &[0, data, dt, 0], &[1, 0, 0, 0, 0, 0, 0, 0]);
    f.link(hd_at, 0, dg);
    f.0
}

#[test]
fn an_unsorted_group_reads_its_bus_records_and_skips_the_others() {
    let mut b = vec![3, 1, 2, 3];
    b.push(1);
    b.extend(record(&ROWS[0]));
    b.extend([4, 5, 0, 0, 0, 1, 2, 3, 4, 5]);
    b.push(2);
    // A remote frame: DLC 3, no data.
    b.extend(record(&(0.3, 0x601, 0, &[0, 0, 0], 0, 0)));
    b.push(1);
    b.extend(record(&ROWS[1]));
    let (got, end) = read_all(&unsorted(&b), &mut NoInflate);
    assert_eq!(end, Ok(()));
    assert_eq!(
        got,
        [
            "1757000000250000 18A#7413 Some(Rx) Some(1)",
            "1757000000300000 601#R3 Some(Rx) Some(1)",
            "1757000000500000 701#05 Some(Tx) Some(1)",
        ]
    );
    // A record id no channel group has ends the read.
    b.push(9);
    let (got, end) = read_all(&unsorted(&b), &mut NoInflate);
    assert_eq!(got.len(), 3);
    assert_eq!(end, Err(Mf4Error::UnknownRecordId { record_id: 9 }));
}

#[test]
fn data_groups_are_merged_by_time() {
    // Two sorted data groups (python-can writes one per event type).
    let first = sorted(&[ROWS[0], ROWS[2]], dt);
    let mut f = File(first);
    let cg = channel_group(&mut f, "CAN_DataFrame", 0, 0);
    let data = dt(&mut f, &record(&ROWS[1]));
    let dg2 = f.block(b"##DG", &[0, cg, data, 0], &[0; 8]);
    let hd_dg = u64::from_le_bytes(f.0[88..96].try_into().unwrap());
    f.link(hd_dg, 0, dg2);
    assert_eq!(
        read_all(&f.0, &mut NoInflate),
        (expected()[..3].to_vec(), Ok(()))
    );
}

#[test]
fn the_time_channel_goes_through_its_linear_conversion() {
    let mut f = File::new(410);
    let hd = f.block(b"##HD", &[0, 0, 0, 0, 0, 0], &[0; 32]);
    // 2 + 0.5 * raw seconds.
    let mut cc = vec![1u8, 0, 0, 0, 0, 0, 2, 0];
    cc.extend_from_slice(&[0; 16]);
    cc.extend_from_slice(&2.0f64.to_le_bytes());
    cc.extend_from_slice(&0.5f64.to_le_bytes());
    let cc = f.block(b"##CC", &[0, 0, 0, 0], &cc);
    let cg = channel_group(&mut f, "CAN_DataFrame", 0, cc);
    let data = dt(&mut f, &record(&ROWS[0]));
    let dg = f.block(b"##DG", &[0, cg, data, 0], &[0; 8]);
    f.link(hd, 0, dg);
    // No start time: the time since the start, 2 + 0.125 s.
    assert_eq!(
        read_all(&f.0, &mut NoInflate).0,
        ["2125000 18A#7413 Some(Rx) Some(1)"]
    );
}

/// The offset of the first block with identifier `id` in `file`.
fn find(file: &[u8], id: &[u8; 4]) -> usize {
    (64..file.len())
        .step_by(8)
        .find(|&i| &file[i..i + 4] == id)
        .unwrap()
}

/// `file` with the bytes at `at` set to `bytes`: a file broken in one
/// place.
fn poked(file: &[u8], at: usize, bytes: &[u8]) -> Vec<u8> {
    let mut f = file.to_vec();
    f[at..at + bytes.len()].copy_from_slice(bytes);
    f
}

/// `file` with the u64 at `at` (a link or a length) set to `v`.
fn patched(file: &[u8], at: usize, v: u64) -> Vec<u8> {
    poked(file, at, &v.to_le_bytes())
}

#[test]
fn files_broken_in_one_place_give_their_named_errors() {
    let good = sorted(&ROWS, dt);
    let err = |f: &[u8]| read_all(f, &mut Zlib::default()).1.unwrap_err();
    assert_eq!(err(b"MDX     "), Mf4Error::NotMf4);
    assert_eq!(err(b"MDF     "), Mf4Error::PastEnd { at: 0 });
    assert_eq!(
        err(&poked(&good, 28, &330u16.to_le_bytes())),
        Mf4Error::Version { version: 330 }
    );
    let hd = 64;
    let dg = find(&good, b"##DG");
    let cg = find(&good, b"##CG");
    let data = find(&good, b"##DT");
    // The first data group's link past the end; to a TX block.
    assert_eq!(
        err(&patched(&good, hd + 24, 1 << 40)),
        Mf4Error::PastEnd { at: 1 << 40 }
    );
    assert!(matches!(
        err(&patched(&good, hd + 24, find(&good, b"##TX") as u64)),
        Mf4Error::UnexpectedBlock {
            found: [b'#', b'#', b'T', b'X'],
            ..
        }
    ));
    // A length below the links; past the end.
    assert_eq!(
        err(&patched(&good, dg + 8, 30)),
        Mf4Error::BlockLength {
            at: dg as u64,
            length: 30
        }
    );
    assert_eq!(
        err(&patched(&good, dg + 8, 1 << 62)),
        Mf4Error::PastEnd { at: dg as u64 }
    );
    // Chains that loop: the data groups, the channels.
    assert_eq!(
        err(&patched(&good, dg + 24, dg as u64)),
        Mf4Error::LinkCycle { what: "data group" }
    );
    let cn = u64::from_le_bytes(good[cg + 32..cg + 40].try_into().unwrap());
    assert_eq!(
        err(&patched(&good, cn as usize + 24, cn)),
        Mf4Error::LinkCycle { what: "channel" }
    );
    // A record id size of 3; a second channel group in a sorted group.
    assert_eq!(
        err(&poked(&good, dg + 56, &[3])),
        Mf4Error::RecordIdSize {
            at: dg as u64,
            size: 3
        }
    );
    assert_eq!(
        err(&patched(&good, cg + 24, cg as u64)),
        Mf4Error::LinkCycle {
            what: "channel group"
        }
    );
    let two = {
        let mut f = File(good.clone());
        let other = channel_group(&mut f, "CAN_DataFrame", 0, 0);
        f.link(cg as u64, 0, other);
        f.0
    };
    assert_eq!(err(&two), Mf4Error::SortedGroups { at: dg as u64 });
    // Records over 1 MiB; data ending inside a record.
    let large = poked(&good, cg + 72 + 24, &(2u32 << 20).to_le_bytes());
    assert_eq!(err(&large), Mf4Error::RecordTooLarge { size: 2 << 20 });
    let short = patched(&good, data + 8, 24 + 4 * u64::from(RECORD) - 1);
    assert_eq!(
        err(&short),
        Mf4Error::RecordPastEnd {
            need: RECORD as usize,
            left: RECORD as usize - 1
        }
    );
}

#[test]
fn broken_data_lists_and_compressed_blocks_give_their_named_errors() {
    let err = |f: &[u8]| read_all(f, &mut Zlib::default()).1.unwrap_err();
    // A data list whose next link is itself.
    let looped = sorted(&ROWS, |f, b| {
        let one = [dt(f, b)];
        let list = dl(f, 0, &one);
        f.link(list, 0, list);
        list
    });
    assert_eq!(err(&looped), Mf4Error::LinkCycle { what: "data list" });
    let z = sorted(&ROWS, |f, b| dz(f, b, 0, 0));
    let at = find(&z, b"##DZ");
    let data = at + 24;
    // Over 64 MiB declared; another size declared; zip type 2; a DZ of
    // an SD block; the compressed bytes past the block.
    assert_eq!(
        err(&patched(&z, data + 8, 1 << 30)),
        Mf4Error::BlockTooLarge {
            at: at as u64,
            size: 1 << 30
        }
    );
    assert_eq!(
        err(&patched(&z, data + 8, 4 * u64::from(RECORD) + 1)),
        Mf4Error::InflatedSize {
            at: at as u64,
            declared: 4 * u64::from(RECORD) + 1,
            inflated: 4 * u64::from(RECORD)
        }
    );
    assert_eq!(
        err(&poked(&z, data + 2, &[2])),
        Mf4Error::UnknownZip {
            at: at as u64,
            zip_type: 2
        }
    );
    assert!(matches!(
        err(&poked(&z, data, b"SD")),
        Mf4Error::UnexpectedBlock { .. }
    ));
    assert_eq!(
        err(&patched(&z, data + 16, 1 << 20)),
        Mf4Error::PastEnd { at: at as u64 }
    );
    let corrupt = poked(&z, at + 24 + 24 + 4, &[0xFF; 4]);
    assert_eq!(err(&corrupt), Mf4Error::Inflate { at: at as u64 });
}

#[test]
fn a_time_channel_not_a_number_or_not_linear_is_named() {
    let good = sorted(&ROWS, dt);
    let cg = find(&good, b"##CG");
    let time = u64::from_le_bytes(good[cg + 32..cg + 40].try_into().unwrap()) as usize;
    // Data type 6: a string.
    let string = poked(&good, time + 24 + 64 + 2, &[6]);
    assert_eq!(
        read_all(&string, &mut NoInflate).1,
        Err(Mf4Error::TimeType {
            at: time as u64,
            data_type: 6
        })
    );
    let mut f = File(good);
    let cc = f.block(b"##CC", &[0, 0, 0, 0], &[7, 0, 0, 0, 0, 0, 0, 0]);
    f.link(time as u64, 4, cc);
    assert_eq!(
        read_all(&f.0, &mut NoInflate).1,
        Err(Mf4Error::TimeConversion {
            at: cc,
            conversion: 7
        })
    );
}

#[test]
fn a_bad_record_is_skipped_and_the_next_is_read() {
    let rows: [Row; 3] = [
        (0.1, 0x800, 0, &[1], 0, 0),
        (0.2, 0x18A, 0, &[2], 0, 0),
        (0.3, 0x18B, 0, &[3], 0, 0),
    ];
    let mut file = sorted(&rows, dt);
    // The third record's DataLength past its 8 data bytes.
    let data = find(&file, b"##DT") + 24;
    file[data + 2 * RECORD as usize + 15] = 8;
    file[data + 2 * RECORD as usize + 14] = 8;
    let (got, end) = read_all(&file, &mut NoInflate);
    assert_eq!(end, Ok(()));
    assert_eq!(got[0], "bad: identifier 800h is not an 11-bit identifier");
    assert_eq!(got[1], "1757000000200000 18A#02 Some(Rx) Some(1)");
    assert_eq!(
        got[2],
        "1757000000300000 18B#0300000000000000 Some(Rx) Some(1)"
    );
    assert!(!Mf4Error::BadId { raw: 0x800 }.is_fatal());
    // A data length past the field: DataBytes one byte wide.
    let cg = find(&file, b"##CG");
    let time = u64::from_le_bytes(file[cg + 32..cg + 40].try_into().unwrap()) as usize;
    let composed = u64::from_le_bytes(file[time + 24..time + 32].try_into().unwrap()) as usize;
    let mut member =
        u64::from_le_bytes(file[composed + 32..composed + 40].try_into().unwrap()) as usize;
    for _ in 0..5 {
        member = u64::from_le_bytes(file[member + 24..member + 32].try_into().unwrap()) as usize;
    }
    file[member + 24 + 64 + 8..member + 24 + 64 + 12].copy_from_slice(&8u32.to_le_bytes());
    let (got, _) = read_all(&file, &mut NoInflate);
    assert_eq!(got[2], "bad: data length 8 is past the record's data bytes");
}

#[test]
fn a_sorted_group_of_empty_records_holds_no_frames() {
    // Reading 0-byte records would take no bytes: the group is empty.
    let good = sorted(&ROWS, dt);
    let cg = find(&good, b"##CG");
    let empty = poked(&good, cg + 72 + 24, &0u32.to_le_bytes());
    assert_eq!(read_all(&empty, &mut NoInflate), (Vec::new(), Ok(())));
}

/// The link `i` of the block at `at`.
fn link_of(file: &[u8], at: usize, i: usize) -> usize {
    let p = at + 24 + 8 * i;
    u64::from_le_bytes(file[p..p + 8].try_into().unwrap()) as usize
}

/// The `DataBytes` member of the channel group at `cg` made a
/// variable-length channel (type 1) whose signal data is at `data`.
fn vlsd_data_bytes(file: &mut [u8], cg: usize, data: u64) {
    let time = link_of(file, cg, 1);
    let composed = link_of(file, time, 0);
    let mut member = link_of(file, composed, 1);
    for _ in 0..5 {
        member = link_of(file, member, 0);
    }
    file[member + 24 + 64] = 1;
    file[member + 24 + 40..member + 24 + 48].copy_from_slice(&data.to_le_bytes());
}

/// `rows` as records whose `DataBytes` is an offset into `signal`, with
/// the `##SD` values (u32 length, bytes).
fn vlsd_rows(rows: &[Row]) -> (Vec<u8>, Vec<u8>) {
    let (mut records, mut signal) = (Vec::new(), Vec::new());
    for r in rows {
        let mut rec = record(r);
        rec[16..24].copy_from_slice(&(signal.len() as u64).to_le_bytes());
        records.extend(rec);
        signal.extend((r.3.len() as u32).to_le_bytes());
        signal.extend_from_slice(r.3);
    }
    (records, signal)
}

#[test]
fn variable_length_data_bytes_read_from_signal_data_blocks() {
    let (records, signal) = vlsd_rows(&ROWS);
    for compressed in [false, true] {
        let mut f = File(sorted(&ROWS, |f, _| dt(f, &records)));
        let sd = if compressed {
            // A list of a deflated SD and a stored one, split in a value.
            let (a, b) = signal.split_at(5);
            let first = f.block(b"##SD", &[], a);
            let mut d = b"SD".to_vec();
            d.extend_from_slice(&[0; 6]);
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            z.write_all(b).unwrap();
            let z = z.finish().unwrap();
            d.extend_from_slice(&(b.len() as u64).to_le_bytes());
            d.extend_from_slice(&(z.len() as u64).to_le_bytes());
            d.extend_from_slice(&z);
            let second = f.block(b"##DZ", &[], &d);
            dl(&mut f, 0, &[first, second])
        } else {
            f.block(b"##SD", &[], &signal)
        };
        let cg = find(&f.0, b"##CG");
        vlsd_data_bytes(&mut f.0, cg, sd);
        assert_eq!(
            read_all(&f.0, &mut Zlib::default()),
            (expected(), Ok(())),
            "compressed {compressed}"
        );
    }
    // An offset behind the one read names no value; the next is read.
    let (mut records, signal) = vlsd_rows(&ROWS[..3]);
    records[RECORD as usize + 16..RECORD as usize + 24].copy_from_slice(&0u64.to_le_bytes());
    let mut f = File(sorted(&ROWS[..3], |f, _| dt(f, &records)));
    let sd = f.block(b"##SD", &[], &signal);
    let cg = find(&f.0, b"##CG");
    vlsd_data_bytes(&mut f.0, cg, sd);
    let (got, end) = read_all(&f.0, &mut NoInflate);
    assert_eq!(end, Ok(()));
    assert_eq!(
        got[1],
        "bad: no variable-length DataBytes value at offset 0"
    );
    assert_eq!(got[2], expected()[2]);
}

#[test]
fn variable_length_data_bytes_read_from_a_variable_length_group() {
    // MDF 4.2: the values are records of channel group 4 in the same
    // unsorted data group, each just before the frame pointing at it.
    let mut b = Vec::new();
    let mut offset = 0u64;
    for r in &ROWS[..3] {
        b.push(4);
        b.extend((r.3.len() as u32).to_le_bytes());
        b.extend_from_slice(r.3);
        let mut rec = record(r);
        rec[16..24].copy_from_slice(&offset.to_le_bytes());
        offset += 4 + r.3.len() as u64;
        b.push(1);
        b.extend(rec);
    }
    let mut file = unsorted(&b);
    let cg = find(&file, b"##CG");
    let variable = (0..file.len() - 24)
        .step_by(8)
        .rfind(|&i| &file[i..i + 4] == b"##CG")
        .unwrap();
    vlsd_data_bytes(&mut file, cg, variable as u64);
    assert_eq!(
        read_all(&file, &mut NoInflate),
        (expected()[..3].to_vec(), Ok(()))
    );
}

#[test]
fn the_bytes_held_across_data_groups_are_bounded() {
    let file = sorted(&ROWS, |f, b| dz(f, b, 0, 0));
    let mut r = Mf4Reader::new(&file).unwrap();
    // The inflated block (4 records) is over a limit of 3 records.
    r.held_limit = 3 * RECORD as usize;
    let e = Mf4Error::TooMuchHeld {
        held: 4 * u64::from(RECORD),
    };
    assert_eq!(r.next(&mut Zlib::default()), Err(e));
    assert!(e.is_fatal());
    assert_eq!(r.next(&mut Zlib::default()), Err(e));
}

/// A file in memory that records the largest read asked of it.
struct Largest<'a>(&'a [u8], usize);

impl Source for Largest<'_> {
    fn size(&self) -> u64 {
        self.0.len() as u64
    }
    fn read_at(&mut self, at: u64, buf: &mut [u8]) -> Result<(), Mf4Error> {
        self.1 = self.1.max(buf.len());
        (&self.0).read_at(at, buf)
    }
}

#[test]
fn a_file_read_in_place_reads_as_in_memory_in_windows() {
    // 50 000 records (1.3 MB) in one ##DT, in a list of a ##DT and a
    // transposed ##DZ.
    let rows: Vec<Row> = (0..50_000)
        .map(|i| (f64::from(i) * 0.001, 0x18A, 0, &[1, 2][..], 0, 0))
        .collect();
    let files = [
        sorted(&rows, dt),
        sorted(&rows, |f, b| {
            let (x, y) = b.split_at(1_000_003);
            let blocks = [dt(f, x), dz(f, y, 1, RECORD)];
            dl(f, 0, &blocks)
        }),
    ];
    for file in &files {
        let in_memory = read_all(file, &mut Zlib::default());
        assert_eq!(in_memory.0.len(), 50_000);
        assert_eq!(in_memory.1, Ok(()));
        let seek = SeekSource::new(std::io::Cursor::new(file)).unwrap();
        assert_eq!(read_all(seek, &mut Zlib::default()), in_memory);
        // No read of the whole file: one window of a data block at most.
        let mut largest = Largest(file, 0);
        let mut r = Mf4Reader::new(&mut largest).unwrap();
        while r.next(&mut Zlib::default()).unwrap().is_some() {}
        drop(r);
        assert!(
            largest.1 <= data::WINDOW,
            "{} bytes read at once",
            largest.1
        );
    }
}

/// A file whose reads that begin in a range of bytes fail.
struct Failing(std::io::Cursor<Vec<u8>>, core::ops::Range<u64>);

impl std::io::Read for Failing {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.1.contains(&self.0.position()) {
            return Err(std::io::Error::other("disk gone"));
        }
        self.0.read(buf)
    }
}

impl std::io::Seek for Failing {
    fn seek(&mut self, to: std::io::SeekFrom) -> std::io::Result<u64> {
        self.0.seek(to)
    }
}

#[test]
fn an_error_reading_the_file_ends_the_read_and_is_kept() {
    // 60 000 records (1.56 MB), then the data group: the second window
    // of the ##DT fails.
    let rows: Vec<Row> = (0..60_000)
        .map(|i| (f64::from(i) * 0.001, 0x18A, 0, &[1, 2][..], 0, 0))
        .collect();
    let file = sorted(&rows, dt);
    let mut src = SeekSource::new(Failing(std::io::Cursor::new(file), 900_000..1_200_000)).unwrap();
    let (frames, end) = read_all(&mut src, &mut NoInflate);
    assert!(matches!(end, Err(Mf4Error::Read { .. })), "{end:?}");
    assert!(end.is_err_and(|e| e.is_fatal()));
    assert!(!frames.is_empty() && frames.len() < 60_000);
    assert_eq!(src.take_error().unwrap().to_string(), "disk gone");
}
