use super::*;

fn count(input: &[u8], how: How) -> (Vec<Timed>, Totals) {
    let f = frames(input, how, &mut NoInflate).unwrap();
    (f.frames, f.totals)
}

#[test]
fn every_line_format_is_detected_and_counted() {
    let cases: [(&str, Format); 5] = [
        ("(1.5) can0 18A#01\n", Format::CandumpLog),
        ("  can0  18A   [1]  01\n", Format::CandumpScreen),
        (
            ";$FILEVERSION=1.1\n     1)      1841.6  Rx         018A  1  01\n",
            Format::PcanTrc,
        ),
        (
            "   1.500000 1  18A             Rx   d 1 01\n",
            Format::VectorAsc,
        ),
        (
            "timestamp,arbitration_id,extended,remote,error,dlc,data\n1.5,0x18A,0,0,0,1,AQ==\n",
            Format::PythonCanCsv,
        ),
    ];
    for (text, format) in cases {
        let (got, totals) = count(text.as_bytes(), How::default());
        assert_eq!(got.len(), 1, "{text}");
        assert_eq!(got[0].frame.to_string(), "18A#01", "{text}");
        assert_eq!(totals.bad, 0, "{text}");
        assert!(
            matches!(totals.kind, Kind::Lines { format: Some(f), .. } if f == format),
            "{text}: {totals:?}"
        );
    }
}

#[test]
fn delta_times_are_summed_only_when_asked() {
    let text = b" (000.100000)  can0  18A   [1]  01\n (000.200000)  can0  18A   [1]  02\n";
    let t = |how| -> Vec<u64> {
        count(text, how)
            .0
            .iter()
            .map(|f| f.timestamp.unwrap().as_micros())
            .collect()
    };
    assert_eq!(t(How::default()), [100_000, 200_000]);
    assert_eq!(
        t(How::format(Some(Format::CandumpScreen)).with_delta_times()),
        [100_000, 300_000]
    );
}

#[test]
fn bad_lines_are_items_with_their_place_and_reason() {
    let f = frames(
        &b"(1.0) can0 18A#01\nnonsense\n\xFF\n"[..],
        How::default(),
        &mut NoInflate,
    )
    .unwrap();
    assert_eq!(f.frames.len(), 1);
    assert_eq!(f.totals.bad, 2);
    assert_eq!(
        f.first_bad.as_deref(),
        Some("line 2: no ID#DATA field: nonsense")
    );
}

#[test]
fn a_file_signed_logg_is_blf_unless_a_line_format_is_given() {
    let mut file = b"LOGG".to_vec();
    file.extend([0u8; 140]);
    let (_, totals) = count(&file, How::default());
    let blf = |kind| {
        matches!(
            kind,
            Kind::Binary {
                binary: Binary::Blf,
                ..
            }
        )
    };
    assert!(blf(totals.kind), "{totals:?}");
    let (_, totals) = count(&file, How::format(Some(Format::CandumpLog)));
    assert!(matches!(totals.kind, Kind::Lines { .. }), "{totals:?}");
    let (_, totals) = count(b"", How::binary(Binary::Blf));
    assert!(blf(totals.kind), "{totals:?}");
    assert_eq!(totals.kind.to_string(), "read as blf");
}

/// A little-endian pcap of link type 227 with the frames `(seconds,
/// identifier, data)`.
fn pcap(frames: &[(u32, u8, &[u8])]) -> Vec<u8> {
    let mut f = 0xA1B2_C3D4u32.to_le_bytes().to_vec();
    f.extend([
        2, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF, 0, 0, 227, 0, 0, 0,
    ]);
    for (s, id, data) in frames {
        f.extend(s.to_le_bytes());
        f.extend([0, 0, 0, 0, 16, 0, 0, 0, 16, 0, 0, 0]);
        f.extend([0, 0, 0, *id, data.len() as u8, 0, 0, 0]);
        f.extend(data.iter().copied().chain([0; 8]).take(8));
    }
    f
}

#[test]
fn a_pcap_is_told_by_its_magic_and_its_packets_are_numbered() {
    let file = pcap(&[(1, 0x70, &[5]), (2, 0x71, &[1, 2])]);
    let f = frames(&file[..file.len() - 3], How::default(), &mut NoInflate).unwrap();
    let got: Vec<_> = f
        .frames
        .iter()
        .map(|t| (t.at, t.frame.to_string()))
        .collect();
    assert_eq!(got, [(At::Packet(1), "070#05".to_string())]);
    assert_eq!(f.totals.kind.to_string(), "read as pcap");
    assert_eq!(f.totals.kind.units(), "packet(s)");
    assert_eq!(
        f.first_bad.as_deref(),
        Some("after packet 1: the file ends inside a packet record: the rest is not read")
    );
    // Asked for as pcapng, the magic number still tells.
    let (got, totals) = count(&file, How::named("pcapng").unwrap());
    assert_eq!(got.len(), 2);
    assert!(matches!(
        totals.kind,
        Kind::Binary {
            binary: Binary::Pcap,
            objects: 2,
            ..
        }
    ));
    // A text file asked for as pcap: not a capture.
    let f = frames(
        &b"(1.0) can0 18A#01\n"[..],
        How::binary(Binary::Pcap),
        &mut NoInflate,
    )
    .unwrap();
    assert_eq!(
        f.first_bad.as_deref(),
        Some("after packet 0: not a pcap or pcapng file (no magic number): the rest is not read")
    );
}

#[cfg(feature = "zlib")]
#[test]
fn gzip_input_of_any_format_is_decompressed_member_by_member() {
    use std::io::Write;
    let gz = |parts: &[&[u8]]| {
        let mut out = Vec::new();
        for p in parts {
            let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
            e.write_all(p).unwrap();
            out.extend(e.finish().unwrap());
        }
        out
    };
    let text = gz(&[b"(1.0) can0 18A#01\n(2.0) can0", b" 18A#02\n"]);
    for how in [How::default(), How::named("candump").unwrap()] {
        let (got, totals) = count(&text, how);
        let got: Vec<_> = got.iter().map(|t| t.frame.to_string()).collect();
        assert_eq!(got, ["18A#01", "18A#02"]);
        assert_eq!(totals.kind.to_string(), "read as candump");
    }
    let (got, totals) = count(&gz(&[&pcap(&[(1, 0x70, &[5])])]), How::default());
    assert_eq!(
        (got.len(), totals.kind.to_string().as_str()),
        (1, "read as pcap")
    );
    let e = frames(&text[..text.len() - 9], How::default(), &mut NoInflate).unwrap_err();
    assert!(e.to_string().starts_with("gzip-compressed input: "), "{e}");
}

/// The items of a reading, in words, and its totals.
fn items_of(
    read: impl FnOnce(&mut dyn FnMut(Item<'_>) -> io::Result<()>) -> io::Result<Totals>,
) -> (Vec<String>, Totals) {
    let mut items = Vec::new();
    let totals = read(&mut |item| {
        items.push(format!("{item:?}"));
        Ok(())
    })
    .unwrap();
    (items, totals)
}

#[test]
fn a_seekable_file_reads_as_a_stream_an_mf4_in_place() {
    let mf4: &[u8] = include_bytes!("../../../tests/data/python-can-mf4writer.mf4");
    let mut truncated = mf4.to_vec();
    truncated.truncate(mf4.len() - 100);
    let candump = b"(1.5) can0 18A#01\n(1.6) can0 701#05\n";
    for (file, how) in [
        (mf4, How::default()),
        (mf4, How::binary(Binary::Mf4)),
        (&truncated[..], How::default()),
        (&candump[..], How::default()),
        // Read as lines when a line format is given, as `read` does.
        (mf4, How::format(Some(Format::CandumpLog))),
    ] {
        let zlib = &mut crate::trace::inflate::Zlib::default();
        let streamed = items_of(|each| read(file, how, zlib, each));
        let in_place = items_of(|each| read_seekable(io::Cursor::new(file), how, zlib, each));
        assert_eq!(in_place, streamed, "{how:?}");
        assert!(streamed.1.frames > 0 || streamed.1.bad > 0);
    }
}

/// A file whose reads fail after the first few.
struct Failing(io::Cursor<Vec<u8>>, usize);

impl Read for Failing {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.1 = self.1.checked_sub(1).ok_or(io::Error::other("disk gone"))?;
        self.0.read(buf)
    }
}

impl io::Seek for Failing {
    fn seek(&mut self, to: io::SeekFrom) -> io::Result<u64> {
        self.0.seek(to)
    }
}

#[test]
fn an_error_reading_an_mf4_in_place_is_returned() {
    let mf4 = include_bytes!("../../../tests/data/python-can-mf4writer.mf4").to_vec();
    // The first read tells the format; the MF4 reader's first fails.
    let file = Failing(io::Cursor::new(mf4), 1);
    let e = read_seekable(file, How::default(), &mut NoInflate, |_| Ok(())).unwrap_err();
    assert_eq!(e.to_string(), "disk gone");
}

/// A pipe: no seek, and a few bytes at a time.
struct Pipe<'a>(&'a [u8]);

impl Read for Pipe<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = buf.len().min(self.0.len()).min(7);
        let (now, rest) = self.0.split_at(n);
        buf[..n].copy_from_slice(now);
        self.0 = rest;
        Ok(n)
    }
}

/// A folder of the system's temporary folder of its own, for `name`.
fn folder(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[cfg(feature = "zlib")]
#[test]
fn an_mf4_from_a_pipe_or_gzip_reads_as_the_file_in_place() {
    use std::io::Write;
    let mf4: &[u8] = include_bytes!("../../../tests/data/python-can-mf4writer.mf4");
    let zlib = &mut crate::trace::inflate::Zlib::default();
    let in_place = items_of(|each| read_seekable(io::Cursor::new(mf4), How::default(), zlib, each));
    assert_eq!(in_place.1.frames, 8);
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(mf4).unwrap();
    let gz = gz.finish().unwrap();
    // In memory (the file is below IN_MEMORY), from a pipe and gzip'd,
    // through `read` and through `read_seekable` (which takes a gzip'd
    // file as a stream).
    assert!(mf4.len() < mf4::IN_MEMORY);
    for input in [mf4, &gz[..]] {
        let piped = items_of(|each| read(Pipe(input), How::default(), zlib, each));
        assert_eq!(piped, in_place);
        let file =
            items_of(|each| read_seekable(io::Cursor::new(input), How::default(), zlib, each));
        assert_eq!(file, in_place);
    }
    // Spilled to a temporary file (nothing held in memory): on Unix its
    // name is gone while it is read, elsewhere when the reading ends.
    let dir = folder("mf4-spill");
    let spilled = items_of(|each| {
        let mut each = |item: Item<'_>| {
            let named = std::fs::read_dir(&dir)?.count();
            assert_eq!(named, usize::from(cfg!(not(unix))));
            each(item)
        };
        counting(&mut each, |counted| {
            mf4::read_spilling(Pipe(mf4), 0, &dir, zlib, counted)
        })
    });
    assert_eq!(spilled, in_place);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir(&dir).unwrap();
}

#[test]
fn an_mf4_that_cannot_be_spilled_says_where_and_why() {
    let mf4: &[u8] = include_bytes!("../../../tests/data/python-can-mf4writer.mf4");
    let gone = folder("mf4-spill-gone");
    std::fs::remove_dir(&gone).unwrap();
    let mut each = |_: Item<'_>| Ok(());
    let e = counting(&mut each, |counted| {
        mf4::read_spilling(Pipe(mf4), 1000, &gone, &mut NoInflate, counted)
    })
    .unwrap_err();
    let e = e.to_string();
    assert!(e.contains("is copied to a temporary file"), "{e}");
    assert!(e.contains(&gone.display().to_string()), "{e}");
    assert!(e.contains("set TMPDIR to a writable folder"), "{e}");
    // Held in memory, it needs no folder.
    let e = counting(&mut each, |counted| {
        mf4::read_spilling(Pipe(mf4), mf4.len(), &gone, &mut NoInflate, counted)
    });
    assert!(e.is_ok());
}
