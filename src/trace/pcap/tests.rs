use std::prelude::rust_2021::*;
use std::vec;

use super::reader::{block_time, Interface, NO_INTERFACE};
use super::*;

/// Writes fields in one byte order.
struct W {
    big: bool,
    out: Vec<u8>,
}

impl W {
    fn new(big: bool) -> W {
        W {
            big,
            out: Vec::new(),
        }
    }
    /// A number, given in both byte orders: the file's is written.
    fn ordered<const N: usize>(&mut self, little: [u8; N], big: [u8; N]) -> &mut W {
        self.bytes(if self.big { &big } else { &little })
    }
    fn u16(&mut self, v: u16) -> &mut W {
        self.ordered(v.to_le_bytes(), v.to_be_bytes())
    }
    fn u32(&mut self, v: u32) -> &mut W {
        self.ordered(v.to_le_bytes(), v.to_be_bytes())
    }
    fn bytes(&mut self, b: &[u8]) -> &mut W {
        self.out.extend_from_slice(b);
        self
    }
    /// A pcapng block: type, length, body padded to 4, length.
    fn block(&mut self, block_type: u32, body: &[u8]) -> &mut W {
        let padded = (body.len() + 3) & !3;
        let length = u32::try_from(12 + padded).unwrap();
        self.u32(block_type).u32(length).bytes(body);
        self.out.resize(self.out.len() + padded - body.len(), 0);
        self.u32(length)
    }
}

/// A SocketCAN packet: identifier word (big-endian), length, FD flags,
/// two reserved bytes, the payload padded to `size`.
fn can(word: u32, data: &[u8], fd_flags: u8, size: usize) -> Vec<u8> {
    let mut p = word.to_be_bytes().to_vec();
    p.extend_from_slice(&[u8::try_from(data.len()).unwrap(), fd_flags, 0, 0]);
    p.extend_from_slice(data);
    p.resize(size.max(p.len()), 0);
    p
}

fn pcap_file(big: bool, nanos: bool, link: u32, packets: &[(u32, u32, Vec<u8>)]) -> Vec<u8> {
    let mut w = W::new(big);
    w.u32(if nanos { PCAP_NANOS } else { PCAP_MICROS });
    w.u16(2).u16(4).u32(0).u32(0).u32(65_535).u32(link);
    for (sec, frac, data) in packets {
        let n = u32::try_from(data.len()).unwrap();
        w.u32(*sec).u32(*frac).u32(n).u32(n).bytes(data);
    }
    w.out
}

fn shb(w: &mut W) {
    let mut body = W::new(w.big);
    body.u32(BYTE_ORDER_MAGIC).u16(1).u16(0);
    body.bytes(&[0xFF; 8]); // section length: unknown
    w.block(SHB, &body.out);
}

/// An IDB with options `(code, value)`.
fn idb(w: &mut W, link: u16, options: &[(u16, &[u8])]) {
    let mut body = W::new(w.big);
    body.u16(link).u16(0).u32(0);
    for (code, value) in options {
        body.u16(*code)
            .u16(u16::try_from(value.len()).unwrap())
            .bytes(value);
        let pad = (4 - value.len() % 4) % 4;
        body.bytes(&vec![0; pad]);
    }
    if !options.is_empty() {
        body.u32(0);
    }
    w.block(IDB, &body.out);
}

fn epb(w: &mut W, interface: u32, ts: u64, data: &[u8]) {
    let mut body = W::new(w.big);
    let n = u32::try_from(data.len()).unwrap();
    body.u32(interface)
        .u32((ts >> 32) as u32)
        .u32(ts as u32)
        .u32(n)
        .u32(n)
        .bytes(data);
    w.block(EPB, &body.out);
}

/// Every event and error of `file` fed in chunks of `chunk` bytes, and
/// `finish`'s result.
fn read_all(
    file: &[u8],
    chunk: usize,
) -> (
    Vec<Result<PcapEvent, PcapError>>,
    Result<(), PcapError>,
    PcapReader,
) {
    let mut r = PcapReader::new();
    let mut out = Vec::new();
    'file: for mut piece in file.chunks(chunk) {
        loop {
            match r.read(&mut piece) {
                Ok(None) => break,
                Ok(Some(e)) => out.push(Ok(e)),
                Err(e) => {
                    out.push(Err(e));
                    if e.is_fatal() {
                        break 'file;
                    }
                }
            }
        }
    }
    let end = r.finish();
    (out, end, r)
}

fn frames(events: &[Result<PcapEvent, PcapError>]) -> Vec<(String, Option<u64>, u32)> {
    events
        .iter()
        .filter_map(|e| match e {
            Ok(PcapEvent::Frame(f)) => Some((
                f.frame.to_string(),
                f.timestamp.map(Timestamp::as_micros),
                f.interface,
            )),
            _ => None,
        })
        .collect()
}

#[test]
fn pcap_of_either_byte_order_and_time_unit_gives_its_frames_in_any_chunks() {
    for big in [false, true] {
        for nanos in [false, true] {
            let frac = |us: u32| if nanos { us * 1000 + 499 } else { us };
            let packets = [
                (1_756_955_646, frac(68_614), can(0x70A, &[0x7F], 0, 16)),
                (
                    1_756_955_647,
                    frac(999_999),
                    can(EFF_FLAG | 0x1234_5678, &[1, 2, 3], 0, 11),
                ),
                (1_756_955_648, frac(0), can(0x60A | RTR_FLAG, &[], 0, 8)),
            ];
            let file = pcap_file(big, nanos, 227, &packets);
            assert_eq!(Flavor::detect(&file), Some(Flavor::Pcap { nanos }));
            for chunk in [1, 3, 7, 4096] {
                let (events, end, r) = read_all(&file, chunk);
                assert_eq!(end, Ok(()), "big {big} nanos {nanos} chunk {chunk}");
                assert_eq!(r.flavor(), Some(Flavor::Pcap { nanos }));
                assert_eq!(
                    frames(&events),
                    [
                        ("70A#7F".to_string(), Some(1_756_955_646_068_614), 0),
                        (
                            "12345678#010203".to_string(),
                            Some(1_756_955_647_999_999),
                            0
                        ),
                        ("60A#R".to_string(), Some(1_756_955_648_000_000), 0),
                    ],
                    "big {big} nanos {nanos} chunk {chunk}"
                );
            }
        }
    }
}

const EFF_FLAG: u32 = 0x8000_0000;
const RTR_FLAG: u32 = 0x4000_0000;

#[test]
fn pcapng_sections_interfaces_and_resolutions_are_honoured() {
    let mut files = Vec::new();
    for big in [false, true] {
        let mut w = W::new(big);
        shb(&mut w);
        // Interface 0: microseconds (no option), a name before the end.
        idb(&mut w, 227, &[(2, b"can0")]);
        // Interface 1: nanoseconds, 10 s offset, a long description first.
        let offset = if big {
            10u64.to_be_bytes()
        } else {
            10u64.to_le_bytes()
        };
        idb(&mut w, 227, &[(3, &[b'x'; 37]), (9, &[9]), (14, &offset)]);
        // Interface 2: 2^-10 s.
        idb(&mut w, 227, &[(9, &[0x8A])]);
        // A Name Resolution Block and a custom block: skipped.
        w.block(4, &[0; 12]);
        w.block(0x0000_0BAD, &[1, 2, 3, 4, 5]);
        epb(&mut w, 0, 1_500_000, &can(0x18A, &[0x74, 0x13], 0, 16));
        epb(&mut w, 1, 2_000_000_499, &can(0x18A, &[1], 0, 16));
        epb(&mut w, 2, 1024 * 3 + 512, &can(0x28A, &[2], 0, 16));
        // A Simple Packet Block (interface 0, no time).
        let spb = can(0x38A, &[3], 0, 16);
        let mut body = W::new(big);
        body.u32(16).bytes(&spb);
        w.block(SPB, &body.out);
        // An obsolete Packet Block on interface 0.
        let mut body = W::new(big);
        let p = can(0x48A, &[4], 0, 16);
        body.u16(0).u16(0).u32(0).u32(7).u32(16).u32(16).bytes(&p);
        w.block(PB, &body.out);
        files.push((big, w.out));
    }
    // Both sections in one file: the second forgets the first's interfaces.
    let mut two = files[0].1.clone();
    two.extend_from_slice(&files[1].1);
    let want = [
        ("18A#7413".to_string(), Some(1_500_000), 0),
        ("18A#01".to_string(), Some(12_000_000), 1),
        ("28A#02".to_string(), Some(3_500_000), 2),
        ("38A#03".to_string(), None, 0),
        ("48A#04".to_string(), Some(7), 0),
    ];
    for (name, file) in [("le", &files[0].1), ("be", &files[1].1), ("both", &two)] {
        assert_eq!(Flavor::detect(file), Some(Flavor::PcapNg));
        for chunk in [1, 5, 4096] {
            let (events, end, _) = read_all(file, chunk);
            assert_eq!(end, Ok(()), "{name} {chunk}");
            let got = frames(&events);
            let times = if name == "both" { 2 } else { 1 };
            assert_eq!(got.len(), want.len() * times, "{name} {chunk}: {events:?}");
            for (g, w) in got.iter().zip(want.iter().cycle()) {
                assert_eq!(g, w, "{name} {chunk}");
            }
        }
    }
}

#[test]
fn what_is_not_a_classic_frame_is_one_unsupported_event_per_packet() {
    let packets = [
        (1, 0, can(0x123 | 0x2000_0000, &[0; 8], 0, 16)),
        (2, 0, can(0x123, &[1; 12], FDF_FLAG | 1, 72)),
        (3, 0, can(0x123, &[1; 4], 0, 72)),
        (4, 0, can(0x123, &[1; 4], FDF_FLAG, 16)),
        (5, 0, {
            let mut p = can(0x123, &[0; 4], 0, 16);
            p[4] = 0x80;
            p
        }),
        (6, 0, can(0x123, &[9], 0, 16)),
    ];
    let file = pcap_file(false, false, 227, &packets);
    let (events, end, _) = read_all(&file, 4096);
    assert_eq!(end, Ok(()));
    let what: Vec<_> = events
        .iter()
        .map(|e| match e {
            Ok(PcapEvent::Unsupported { what, on_bus, .. }) => format!("{what:?} {on_bus:?}"),
            Ok(PcapEvent::Frame(f)) => f.frame.to_string(),
            Err(e) => e.to_string(),
        })
        .collect();
    // The FD frames with their identifier, flags (BRS the first) and data
    // for the bus load.
    assert_eq!(
        what,
        [
            "ErrorFrame Some(ErrorFrame)",
            "CanFd Some(Fd(123##1010101010101010101010101))",
            "CanFd Some(Fd(123##001010101))",
            "CanFd Some(Fd(123##001010101))",
            "CanXl None",
            "123#09"
        ]
    );
    // Ethernet packets: each one is reported, not dropped.
    let file = pcap_file(true, false, 1, &[(1, 0, vec![0; 60]), (2, 0, vec![0; 14])]);
    let (events, end, _) = read_all(&file, 4096);
    assert_eq!(end, Ok(()));
    assert_eq!(
        events,
        [1, 2].map(|s| Ok(PcapEvent::Unsupported {
            what: Unsupported::LinkType,
            link_type: 1,
            timestamp: Some(Timestamp::from_micros(s * 1_000_000)),
            on_bus: None,
        }))
    );
}

const FDF_FLAG: u8 = 0x04;

#[test]
fn malformed_packets_are_skipped_and_structure_errors_end_the_read() {
    let mut w = W::new(false);
    shb(&mut w);
    idb(&mut w, 227, &[]);
    epb(&mut w, 3, 0, &can(0x18A, &[1], 0, 16)); // no interface 3
    epb(&mut w, 0, 0, &can(0x1234, &[1], 0, 16)); // 11-bit id above 7FFh
    epb(&mut w, 0, 0, &[0, 0, 1]); // shorter than the header
    epb(&mut w, 0, 0, &can(0x18A, &[1, 2], 0, 16)[..9]); // payload cut
    epb(&mut w, 0, 5, &can(0x18A, &[1], 0, 16));
    let good = w.out.clone();
    let (events, end, _) = read_all(&good, 3);
    assert_eq!(end, Ok(()));
    assert_eq!(
        events,
        [
            Err(PcapError::UnknownInterface { interface: 3 }),
            Err(PcapError::BadId { raw: 0x1234 }),
            Err(PcapError::SocketCanTooShort { captured: 3 }),
            Err(PcapError::SocketCanTooShort { captured: 9 }),
            Ok(PcapEvent::Frame(PcapFrame {
                timestamp: Some(Timestamp::from_micros(5)),
                interface: 0,
                frame: CanFrame::standard(0x18A, &[1]).unwrap(),
            })),
        ]
    );
    // A trailing length that is not the block's: fatal, and kept.
    let mut bad = good.clone();
    let last = bad.len() - 4;
    bad[last] ^= 4;
    let (events, end, _) = read_all(&bad, 4096);
    assert!(matches!(
        events.last(),
        Some(Err(PcapError::TrailingLength { .. }))
    ));
    assert!(matches!(end, Err(PcapError::TrailingLength { .. })));
    // Cut anywhere inside a block: truncated.
    for cut in [good.len() - 1, good.len() - 20, 30] {
        let (_, end, _) = read_all(&good[..cut], 4096);
        assert_eq!(end, Err(PcapError::Truncated("a block")), "cut {cut}");
    }
    assert_eq!(read_all(&[], 1).1, Err(PcapError::NotPcap));
    assert_eq!(
        read_all(b"(1.0) can0 18A#01\n", 4).0,
        [Err(PcapError::NotPcap)]
    );
    // A block length that is no block's.
    let mut w = W::new(false);
    shb(&mut w);
    w.u32(6).u32(10).u32(0);
    let (events, _, _) = read_all(&w.out, 4096);
    assert!(matches!(
        events.last(),
        Some(Err(PcapError::BlockLength { length: 10, .. }))
    ));
    // A pcap record of a corrupt length.
    let mut file = pcap_file(false, false, 227, &[]);
    file.extend_from_slice(&[0; 8]);
    file.extend_from_slice(&u32::MAX.to_le_bytes());
    file.extend_from_slice(&[0; 4]);
    let (events, _, _) = read_all(&file, 4096);
    assert_eq!(events, [Err(PcapError::RecordLength { length: u32::MAX })]);
}

#[test]
fn resolutions_convert_to_the_nearest_microsecond() {
    let at = |units, resolution, offset| {
        block_time(
            units,
            Interface {
                resolution,
                offset,
                ..NO_INTERFACE
            },
        )
        .map(Timestamp::as_micros)
    };
    assert_eq!(at(7, 6, 0), Some(7));
    assert_eq!(at(7, 3, 0), Some(7000));
    assert_eq!(at(7, 0, 2), Some(9_000_000));
    assert_eq!(at(1499, 9, 0), Some(1));
    assert_eq!(at(1500, 9, 0), Some(2));
    assert_eq!(at(1, 0x80 | 1, 0), Some(500_000));
    assert_eq!(at(3, 0x80 | 20, 0), Some(3));
    assert_eq!(at(u64::MAX, 0x7F, 0), Some(0));
    assert_eq!(at(u64::MAX, 0xFF, 0), Some(0));
    assert_eq!(at(u64::MAX, 0, 0), None);
    assert_eq!(at(5, 6, -1), None);
    assert_eq!(at(5, 6, i64::MIN), None);
}

#[test]
fn hostile_bytes_end_in_events_or_errors_never_a_panic() {
    let mut w = W::new(false);
    shb(&mut w);
    idb(&mut w, 227, &[(9, &[9])]);
    for i in 0..4u8 {
        epb(
            &mut w,
            0,
            u64::from(i),
            &can(0x180 + u32::from(i), &[i], 0, 16),
        );
    }
    let seeds = [
        w.out,
        pcap_file(true, true, 227, &[(1, 2, can(0x70A, &[0x7F], 0, 16))]),
    ];
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    for seed in &seeds {
        for _ in 0..2000 {
            let mut f = seed.clone();
            for _ in 0..4 {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let at = (x as usize) % f.len();
                f[at] = (x >> 32) as u8;
            }
            let (events, end, _) = read_all(&f, 1 + (x as usize >> 40) % 64);
            // No more events than bytes: every event consumed some.
            assert!(events.len() <= f.len());
            // Whole packets read where they lie give what reading byte
            // by byte gives.
            let (bytewise, bytewise_end, _) = read_all(&f, 1);
            let (whole, whole_end, _) = read_all(&f, f.len());
            assert_eq!((&whole, whole_end), (&bytewise, bytewise_end));
            assert_eq!((events, end), (bytewise, bytewise_end));
        }
    }
}
