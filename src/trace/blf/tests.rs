//! The BLF reader on hand-built files: a tiny writer of the layouts the
//! module docs give (file header, v1 / v2 object headers, stored
//! containers; the zlib protocol with the test as the inflater).

use super::*;
use crate::frame::CanId;
use std::string::String;
use std::vec::Vec;

const NS: u32 = 2;
const TEN_US: u32 = 1;

/// An object: base header, v1 or v2 fields, body, `size % 4` padding.
fn object(version: u16, object_type: u32, flags: u32, ticks: u64, body: &[u8]) -> Vec<u8> {
    let header = if version == 2 { 40 } else { 32 };
    let size = header + body.len();
    let mut o = Vec::new();
    o.extend_from_slice(b"LOBJ");
    o.extend_from_slice(&(header as u16).to_le_bytes());
    o.extend_from_slice(&version.to_le_bytes());
    o.extend_from_slice(&(size as u32).to_le_bytes());
    o.extend_from_slice(&object_type.to_le_bytes());
    o.extend_from_slice(&flags.to_le_bytes());
    o.extend_from_slice(&[0; 4]); // client index / timestamp status, object version
    o.extend_from_slice(&ticks.to_le_bytes());
    if version == 2 {
        o.extend_from_slice(&ticks.to_le_bytes()); // original timestamp
    }
    o.extend_from_slice(body);
    o.resize(size + size % 4, 0);
    o
}

/// A CAN_MESSAGE body.
fn can(channel: u16, flags: u8, dlc: u8, id: u32, data: [u8; 8]) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&channel.to_le_bytes());
    b.extend_from_slice(&[flags, dlc]);
    b.extend_from_slice(&id.to_le_bytes());
    b.extend_from_slice(&data);
    b
}

/// A CAN_MESSAGE2 body: a CAN_MESSAGE body, then the frame length and
/// bit count (8 bytes, not read).
fn can2(channel: u16, flags: u8, dlc: u8, id: u32, data: [u8; 8]) -> Vec<u8> {
    let mut b = can(channel, flags, dlc, id, data);
    b.extend_from_slice(&[0; 8]);
    b
}

/// A file of `objects` (concatenated) in one stored container, after a
/// header with or without a start time.
fn stored(start: bool, objects: &[Vec<u8>]) -> Vec<u8> {
    let payload = objects.concat();
    let mut f = header(start);
    f.extend(container(0, &payload, payload.len()));
    f
}

/// A container of `payload` with compression `method`, declaring `declared`.
fn container(method: u16, payload: &[u8], declared: usize) -> Vec<u8> {
    let size = 32 + payload.len();
    let mut o = Vec::new();
    o.extend_from_slice(b"LOBJ");
    o.extend_from_slice(&16u16.to_le_bytes());
    o.extend_from_slice(&1u16.to_le_bytes());
    o.extend_from_slice(&(size as u32).to_le_bytes());
    o.extend_from_slice(&10u32.to_le_bytes());
    o.extend_from_slice(&method.to_le_bytes());
    o.extend_from_slice(&[0; 6]);
    o.extend_from_slice(&(declared as u32).to_le_bytes());
    o.extend_from_slice(&[0; 4]);
    o.extend_from_slice(payload);
    o.resize(size + size % 4, 0);
    o
}

/// The 144-byte file header (start 2025-09-04 03:14:13.603 UTC, or none).
fn header(start: bool) -> Vec<u8> {
    let mut h = vec![0u8; 144];
    h[..4].copy_from_slice(b"LOGG");
    h[4..8].copy_from_slice(&144u32.to_le_bytes());
    h[8] = 5;
    h[32..36].copy_from_slice(&7u32.to_le_bytes());
    if start {
        for (i, v) in [2025u16, 9, 4, 4, 3, 14, 13, 603].iter().enumerate() {
            h[40 + 2 * i..42 + 2 * i].copy_from_slice(&v.to_le_bytes());
        }
    }
    h
}

const START_US: u64 = 1_756_955_653_603_000;

/// What came out of a file, the test inflating a zlib container's payload
/// by taking it as the inflated bytes (so "compressed" payloads here are
/// the objects themselves).
#[derive(Debug, PartialEq)]
struct Out {
    frames: Vec<BlfFrame>,
    others: Vec<BlfEvent<'static>>,
    errors: Vec<BlfError>,
    end: Result<(), BlfError>,
}

fn read(file: &[u8], chunk: usize) -> Out {
    let mut r = BlfReader::new();
    let mut out = Out {
        frames: Vec::new(),
        others: Vec::new(),
        errors: Vec::new(),
        end: Ok(()),
    };
    let mut steps = 0;
    let note = |out: &mut Out, e: BlfEvent<'_>| match e {
        BlfEvent::Frame(f) => out.frames.push(f),
        BlfEvent::Header(h) => out.others.push(BlfEvent::Header(h)),
        BlfEvent::ContainerStart {
            compression,
            uncompressed_size,
        } => out.others.push(BlfEvent::ContainerStart {
            compression,
            uncompressed_size,
        }),
        BlfEvent::Unsupported {
            what,
            object_type,
            timestamp,
        } => out.others.push(BlfEvent::Unsupported {
            what,
            object_type,
            timestamp,
        }),
        BlfEvent::Skipped { object_type } => out.others.push(BlfEvent::Skipped { object_type }),
        BlfEvent::Compressed(_) => {}
    };
    'file: for mut piece in file.chunks(chunk.max(1)) {
        loop {
            steps += 1;
            assert!(steps < 10 * file.len() + 10, "no progress");
            match r.read(&mut piece) {
                Ok(None) => break,
                Ok(Some(BlfEvent::Compressed(mut z))) => loop {
                    match r.read_inflated(&mut z) {
                        Ok(None) => break,
                        Ok(Some(e)) => note(&mut out, e),
                        Err(e) if e.is_fatal() => {
                            out.end = Err(e);
                            return out;
                        }
                        Err(e) => out.errors.push(e),
                    }
                },
                Ok(Some(e)) => note(&mut out, e),
                Err(e) if e.is_fatal() => {
                    out.end = Err(e);
                    break 'file;
                }
                Err(e) => out.errors.push(e),
            }
        }
    }
    if out.end.is_ok() {
        out.end = r.finish();
    }
    out
}

fn frame(id: CanId, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// Three frames in one stored container: v1 ns times, channel 2, Tx, a
/// 29-bit identifier, a remote frame, a DLC above 8.
fn three_frames() -> Vec<u8> {
    let extended = 0x8000_0000 | 0x1234_5678;
    stored(
        true,
        &[
            object(
                1,
                1,
                NS,
                1_500_000_000,
                &can(1, 0, 2, 0x18A, [0x74, 0x13, 9, 9, 9, 9, 9, 9]),
            ),
            object(
                1,
                86,
                NS,
                1_500_010_500,
                &can2(2, 1, 12, extended, [1, 2, 3, 4, 5, 6, 7, 8]),
            ),
            object(1, 1, NS, 2_000_000_000, &can(1, 0x80, 1, 0x70A, [0; 8])),
        ],
    )
}

#[test]
fn frames_of_a_stored_container_whatever_the_chunks() {
    let file = three_frames();
    let whole = read(&file, file.len());
    assert_eq!(whole.end, Ok(()));
    assert_eq!(whole.errors, []);
    // A frame `us` after the start, on `channel`.
    let at = |us: u64, channel: u16, direction: RxTx, frame: CanFrame| BlfFrame {
        timestamp: Some(Timestamp::from_micros(START_US + us)),
        channel,
        direction,
        frame,
    };
    let extended = frame(CanId::Extended(0x1234_5678), &[1, 2, 3, 4, 5, 6, 7, 8]);
    let remote = CanFrame::remote(CanId::Standard(0x70A), 1).unwrap();
    assert_eq!(
        whole.frames,
        [
            at(
                1_500_000,
                1,
                RxTx::Rx,
                frame(CanId::Standard(0x18A), &[0x74, 0x13])
            ),
            at(1_500_011, 2, RxTx::Tx, extended),
            at(2_000_000, 1, RxTx::Rx, remote),
        ]
    );
    assert_eq!(whole.frames[2].trace_frame().direction, Some(RxTx::Rx));
    match whole.others[0] {
        BlfEvent::Header(h) => {
            assert_eq!(
                (h.header_size, h.application_id, h.object_count),
                (144, 5, 7)
            );
            assert_eq!(h.start, Some(Timestamp::from_micros(START_US)));
        }
        ref e => panic!("{e:?}"),
    }
    for chunk in 1..file.len() {
        assert_eq!(read(&file, chunk), whole, "chunk {chunk}");
    }
}

#[test]
fn v2_headers_ten_microsecond_units_and_no_start() {
    let file = stored(
        false,
        &[
            object(
                2,
                1,
                TEN_US,
                123_456,
                &can(1, 0, 1, 0x70A, [5, 0, 0, 0, 0, 0, 0, 0]),
            ),
            object(2, 86, NS, 7_000, &can2(1, 0, 0, 0x080, [0; 8])),
            // Flags naming no unit: no time.
            object(1, 1, 0, 99, &can(1, 0, 0, 0x000, [0; 8])),
        ],
    );
    for chunk in [1, 5, 64, file.len()] {
        let out = read(&file, chunk);
        assert_eq!(out.end, Ok(()));
        let times: Vec<_> = out.frames.iter().map(|f| f.timestamp).collect();
        assert_eq!(
            times,
            [
                Some(Timestamp::from_micros(1_234_560)),
                Some(Timestamp::from_micros(7)),
                None
            ]
        );
        assert_eq!(out.frames[0].frame, frame(CanId::Standard(0x70A), &[5]));
    }
}

#[test]
fn objects_straddle_containers_and_top_level_objects_are_read() {
    let mut stream = Vec::new();
    for i in 0..5u8 {
        stream.extend(object(
            1,
            1,
            NS,
            u64::from(i) * 1000,
            &can(1, 0, 1, 0x181, [i, 0, 0, 0, 0, 0, 0, 0]),
        ));
    }
    let mut file = header(true);
    // Cut at 70 and 150: the second and fourth objects straddle.
    for part in [&stream[..70], &stream[70..150], &stream[150..]] {
        file.extend(container(0, part, part.len()));
    }
    // A CAN message outside any container (old writers).
    file.extend(object(
        1,
        1,
        NS,
        9000,
        &can(1, 0, 1, 0x181, [9, 0, 0, 0, 0, 0, 0, 0]),
    ));
    for chunk in [1, 3, 48, 1000] {
        let out = read(&file, chunk);
        assert_eq!(out.end, Ok(()), "chunk {chunk}");
        let data: Vec<u8> = out.frames.iter().map(|f| f.frame.data()[0]).collect();
        assert_eq!(data, [0, 1, 2, 3, 4, 9]);
        let starts = out
            .others
            .iter()
            .filter(|e| matches!(e, BlfEvent::ContainerStart { .. }));
        assert_eq!(starts.count(), 3);
    }
}

#[test]
fn unknown_error_and_fd_objects_are_skipped_by_their_size() {
    // A header version this reader does not know.
    let mut v3 = object(1, 1, NS, 6, &can(1, 0, 0, 0x123, [0; 8]));
    v3[6] = 3;
    // Padding to 4 instead of `size % 4` (33 + 32 = 65 bytes: 3, not 1).
    let mut odd = object(1, 96, NS, 7, &[0; 33]);
    odd.extend([0, 0]);
    let file = stored(
        true,
        &[
            object(1, 65, NS, 1, b"an application text of odd length"),
            object(1, 73, NS, 2, &[0; 32]),
            object(1, 2, NS, 3, &[0; 4]),
            object(1, 100, NS, 4, &[0; 84]),
            object(1, 101, NS, 5, &[0; 41]),
            v3,
            odd,
            object(1, 1, NS, 8, &can(1, 0, 0, 0x123, [0; 8])),
        ],
    );
    for chunk in [1, 7, file.len()] {
        let out = read(&file, chunk);
        assert_eq!(out.end, Ok(()));
        let kinds: Vec<String> = out
            .others
            .iter()
            .skip(2)
            .map(|e| match e {
                BlfEvent::Skipped { object_type } => format!("skip {object_type}"),
                BlfEvent::Unsupported {
                    what,
                    object_type,
                    timestamp,
                } => format!(
                    "{what:?} {object_type} {}",
                    timestamp.unwrap().as_micros() - START_US
                ),
                e => format!("{e:?}"),
            })
            .collect();
        assert_eq!(
            kinds,
            [
                "skip 65",
                "ErrorFrame 73 0",
                "ErrorFrame 2 0",
                "CanFd 100 0",
                "CanFd 101 0",
                "skip 1",
                "skip 96"
            ]
        );
        assert_eq!(out.frames.len(), 1);
    }
}

#[test]
fn zlib_containers_take_inflated_bytes_up_to_their_size() {
    let payload = [
        object(
            1,
            1,
            NS,
            1000,
            &can(1, 0, 1, 0x181, [1, 0, 0, 0, 0, 0, 0, 0]),
        ),
        object(
            1,
            1,
            NS,
            2000,
            &can(1, 0, 1, 0x181, [2, 0, 0, 0, 0, 0, 0, 0]),
        ),
    ]
    .concat();
    let mut file = header(true);
    file.extend(container(2, &payload[..60], 60));
    file.extend(container(2, &payload[60..], payload.len() - 60));
    for chunk in [1, 13, file.len()] {
        let out = read(&file, chunk);
        assert_eq!(out.end, Ok(()));
        assert_eq!(out.frames.len(), 2);
    }
    // Inflating to less than declared: found at the next container.
    let mut short = header(true);
    short.extend(container(2, &payload[..60], 61));
    short.extend(container(2, &payload[60..], payload.len() - 60));
    assert_eq!(
        read(&short, 1000).end,
        Err(BlfError::InflatedSizeMismatch {
            declared: 61,
            inflated: 60
        })
    );
    // ... or at the end of the file.
    let mut last = header(true);
    last.extend(container(2, &payload, payload.len() + 1));
    assert!(matches!(
        read(&last, 1000).end,
        Err(BlfError::InflatedSizeMismatch { .. })
    ));
    // More than declared: refused before it is read.
    let mut long = header(true);
    long.extend(container(2, &payload, 10));
    assert_eq!(
        read(&long, 1000).end,
        Err(BlfError::InflatedSizeMismatch {
            declared: 10,
            inflated: 96
        })
    );
    assert_eq!(read(&long, 1000).frames, []);
    // Inflated bytes with no zlib container open.
    let mut r = BlfReader::new();
    assert_eq!(
        r.read_inflated(&mut &b"LOBJ"[..]),
        Err(BlfError::NotInflating)
    );
    assert_eq!(r.read(&mut &header(true)[..]), Err(BlfError::NotInflating));
}

#[test]
fn truncated_files_are_errors_at_the_end() {
    let file = three_frames();
    let whole = read(&file, file.len()).frames;
    for cut in 0..file.len() {
        let out = read(&file[..cut], 9);
        assert!(whole.starts_with(&out.frames), "cut {cut}");
        match out.end {
            Err(BlfError::NotBlf) => assert_eq!(cut, 0),
            Err(BlfError::Truncated(_)) => {}
            // The file's end at an object boundary of the top level.
            Ok(()) => assert_eq!(cut, 144, "cut {cut}"),
            e => panic!("cut {cut}: {e:?}"),
        }
    }
}

#[test]
fn lying_sizes_are_typed_errors() {
    let message = object(1, 1, NS, 0, &can(1, 0, 0, 0x123, [0; 8]));
    let in_container = |o: &[u8]| stored(true, &[o.to_vec()]);
    let with = |at: usize, bytes: &[u8]| {
        let mut o = message.clone();
        o[at..at + bytes.len()].copy_from_slice(bytes);
        in_container(&o)
    };
    // A file of one container holding `payload`, declaring `declared`.
    let file_of = |method: u16, payload: &[u8], declared: usize| {
        let mut f = header(true);
        f.extend(container(method, payload, declared));
        f
    };
    let short_container = {
        let mut c = container(0, &[], 0);
        c[8..12].copy_from_slice(&20u32.to_le_bytes());
        let mut f = header(true);
        f.extend(c);
        f
    };
    let short_header = {
        let mut f = header(true);
        f[4..8].copy_from_slice(&71u32.to_le_bytes());
        f
    };
    // The errors that end the reading: (what, file, the end it reads to).
    let fatal = [
        (
            "object size below its header",
            with(8, &20u32.to_le_bytes()),
            BlfError::ObjectSmallerThanHeader {
                object_size: 20,
                header_size: 32,
            },
        ),
        (
            "object size below the base header",
            with(8, &3u32.to_le_bytes()),
            BlfError::ObjectSmallerThanHeader {
                object_size: 3,
                header_size: 32,
            },
        ),
        (
            "object size past its container and the file",
            with(8, &4000u32.to_le_bytes()),
            BlfError::Truncated("an object"),
        ),
        (
            "no LOBJ where an object begins",
            with(0, b"LOBX"),
            BlfError::BadSignature {
                offset: 3,
                in_container: true,
            },
        ),
        (
            "a stored size that is not the payload's",
            file_of(0, &message, 47),
            BlfError::StoredSizeMismatch {
                payload: 48,
                declared: 47,
            },
        ),
        (
            "an unknown compression method",
            file_of(1, &message, 48),
            BlfError::UnknownCompression { method: 1 },
        ),
        (
            "a container too short for its header",
            short_container,
            BlfError::ContainerTooShort { object_size: 20 },
        ),
        (
            "a file header size below its fields",
            short_header,
            BlfError::FileHeaderSize { header_size: 71 },
        ),
    ];
    for (what, file, end) in fatal {
        assert_eq!(read(&file, 99).end, Err(end), "{what}");
    }
    // Header size below its version's fields: the object is skipped.
    let out = read(&with(4, &20u16.to_le_bytes()), 99);
    assert_eq!(
        out.errors,
        [BlfError::HeaderSize {
            header_size: 20,
            version: 1
        }]
    );
    assert_eq!(out.end, Ok(()));
    // A CAN message too short for its fields: skipped, reading goes on.
    let mut short = object(1, 1, NS, 0, &[0; 8]);
    short.extend(message.clone());
    let out = read(&in_container(&short), 5);
    assert_eq!(
        out.errors,
        [BlfError::ObjectTooShort {
            object_type: 1,
            object_size: 40
        }]
    );
    assert_eq!(out.frames.len(), 1);
    // An 11-bit identifier above 7FFh: skipped, reading goes on.
    let out = read(&with(36, &0x800u32.to_le_bytes()), 5);
    assert_eq!(out.errors, [BlfError::BadId { raw: 0x800 }]);
    assert_eq!(read(b"LOGX and more", 2).end, Err(BlfError::NotBlf));
    assert_eq!(read(b"", 2).end, Err(BlfError::NotBlf));
    // A fatal error stays.
    let mut r = BlfReader::new();
    assert_eq!(r.read(&mut &b"PK\x03\x04"[..]), Err(BlfError::NotBlf));
    assert_eq!(r.read(&mut &header(true)[..]), Err(BlfError::NotBlf));
    assert_eq!(r.finish(), Err(BlfError::NotBlf));
}

#[test]
fn system_times_are_unix_times() {
    assert_eq!(system_time([1970, 1, 1, 0, 0, 0, 0]), Some(Timestamp::ZERO));
    assert_eq!(
        system_time([2025, 9, 4, 3, 14, 13, 603]),
        Some(Timestamp::from_micros(START_US))
    );
    assert_eq!(
        system_time([2024, 2, 29, 23, 59, 59, 999]).map(|t| t.as_micros()),
        Some(1_709_251_199_999_000)
    );
    assert_eq!(system_time([0, 0, 0, 0, 0, 0, 0]), None);
    assert_eq!(system_time([2025, 13, 1, 0, 0, 0, 0]), None);
    assert_eq!(
        system_time([9999, 12, 31, 23, 59, 59, 999]).map(|t| t.as_micros() > 0),
        Some(true)
    );
}

proptest::proptest! {
    #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-trace-blf-tests.txt"))]

    /// Any bytes after a file header, in any chunks: typed results, and
    /// every event takes input (no unbounded loop).
    #[test]
    fn any_bytes_read_totally(
        body in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..400),
        chunk in 1usize..64,
        lobj in proptest::prelude::any::<bool>(),
    ) {
        let mut file = header(true);
        if lobj {
            file.extend(three_frames().get(144..).unwrap_or(&[]));
        }
        file.extend(body);
        let out = read(&file, chunk);
        proptest::prop_assert!(out.frames.len() + out.others.len() <= file.len());
    }

    /// A file's frames read the same whatever its chunks.
    #[test]
    fn chunks_do_not_matter(chunk in 1usize..300) {
        let file = three_frames();
        proptest::prop_assert_eq!(read(&file, chunk), read(&file, file.len()));
    }
}
