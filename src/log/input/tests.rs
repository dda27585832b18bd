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
