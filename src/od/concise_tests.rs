//! Byte vectors of the concise DCF (CiA 302-3 section 4), built by hand
//! from the format, read and written both ways; every malformed shape; and
//! the emit-then-parse round trip as a property.

use super::*;

/// Two entries: 1017h sub 0 = 500 (UNSIGNED16), 1800h sub 1 = 4000_0185h
/// (UNSIGNED32), written out field by field.
const TWO: [u8; 4 + 9 + 11] = [
    0x02, 0x00, 0x00, 0x00, // count 2
    0x17, 0x10, 0x00, // 1017h sub 0
    0x02, 0x00, 0x00, 0x00, // size 2
    0xF4, 0x01, // 500
    0x00, 0x18, 0x01, // 1800h sub 1
    0x04, 0x00, 0x00, 0x00, // size 4
    0x85, 0x01, 0x00, 0x40, // 4000_0185h
];

fn two_entries() -> [ConciseEntry<'static>; 2] {
    [
        ConciseEntry::new(Address::new(0x1017, 0), &[0xF4, 0x01]),
        ConciseEntry::new(Address::new(0x1800, 1), &[0x85, 0x01, 0x00, 0x40]),
    ]
}

#[test]
fn hand_built_vector_reads_and_writes_both_ways() {
    let dcf = ConciseDcf::new_checked(&TWO).unwrap();
    assert_eq!(dcf.len(), 2);
    assert!(!dcf.is_empty());
    assert_eq!(dcf.buffer_len(), TWO.len());
    let read: std::vec::Vec<_> = dcf.iter().collect();
    assert_eq!(read, two_entries());
    assert_eq!(dcf.iter().len(), 2);

    let mut buf = [0xAAu8; 40];
    let len = ConciseDcf::encode(two_entries(), &mut buf).unwrap();
    assert_eq!(&buf[..len], &TWO[..]);
    #[cfg(feature = "alloc")]
    assert_eq!(ConciseDcf::encode_vec(two_entries()).unwrap(), TWO.to_vec());
}

#[test]
fn empty_concise_dcf_is_its_count_alone() {
    let dcf = ConciseDcf::new_checked(&[0, 0, 0, 0]).unwrap();
    assert!(dcf.is_empty());
    assert_eq!(dcf.iter().next(), None);
    let mut buf = [0xAAu8; 4];
    assert_eq!(ConciseDcf::encode([], &mut buf), Ok(4));
    assert_eq!(buf, [0, 0, 0, 0]);
}

#[test]
fn zero_size_entry_carries_no_data() {
    let bytes = [1, 0, 0, 0, 0x50, 0x1F, 0x01, 0, 0, 0, 0];
    let dcf = ConciseDcf::new_checked(&bytes).unwrap();
    let e = dcf.iter().next().unwrap();
    assert_eq!(e.addr, Address::new(0x1F50, 1));
    assert!(e.data.is_empty());
}

#[test]
fn malformed_shapes_are_typed_errors() {
    assert_eq!(
        ConciseDcf::new_checked(&[2, 0, 0]),
        Err(ConciseDcfError::NoCount { got: 3 })
    );
    // The count says 3, two entries follow.
    let mut three = TWO;
    three[0] = 3;
    assert_eq!(
        ConciseDcf::new_checked(&three),
        Err(ConciseDcfError::MissingEntries { count: 3, found: 2 })
    );
    // A huge count over no data: refused at once.
    assert_eq!(
        ConciseDcf::new_checked(&[0xFF, 0xFF, 0xFF, 0xFF]),
        Err(ConciseDcfError::MissingEntries {
            count: u32::MAX,
            found: 0
        })
    );
    // The second header cut after 5 bytes.
    assert_eq!(
        ConciseDcf::new_checked(&TWO[..4 + 9 + 5]),
        Err(ConciseDcfError::EntryHeaderTruncated { entry: 1, got: 5 })
    );
    // The second entry's data cut after 3 of its 4 bytes.
    assert_eq!(
        ConciseDcf::new_checked(&TWO[..TWO.len() - 1]),
        Err(ConciseDcfError::SizePastEnd {
            entry: 1,
            size: 4,
            remaining: 3
        })
    );
    // A size of 4 GiB.
    let mut huge = TWO;
    huge[7..11].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_eq!(
        ConciseDcf::new_checked(&huge),
        Err(ConciseDcfError::SizePastEnd {
            entry: 0,
            size: u32::MAX,
            remaining: 13
        })
    );
    // One byte after the last entry, and a count of 1 over two entries.
    let mut long = TWO.to_vec();
    long.push(0);
    assert_eq!(
        ConciseDcf::new_checked(&long),
        Err(ConciseDcfError::TrailingBytes { count: 2, extra: 1 })
    );
    let mut one = TWO;
    one[0] = 1;
    assert_eq!(
        ConciseDcf::new_checked(&one),
        Err(ConciseDcfError::TrailingBytes {
            count: 1,
            extra: 11
        })
    );
}

#[test]
fn writer_refuses_what_does_not_fit_and_keeps_what_did() {
    assert_eq!(
        ConciseWriter::new(&mut [0u8; 3]).map(|w| w.count()),
        Err(ConciseDcfError::NoCount { got: 3 })
    );
    let mut buf = [0u8; 4 + 9 + 10];
    let mut w = ConciseWriter::new(&mut buf).unwrap();
    let [a, b] = two_entries();
    w.push(a).unwrap();
    assert_eq!(
        w.push(b),
        Err(ConciseDcfError::BufferTooSmall { need: 11, got: 10 })
    );
    assert_eq!(w.count(), 1);
    let len = w.finish();
    assert_eq!(len, 13);
    let dcf = ConciseDcf::new_checked(&buf[..len]).unwrap();
    assert_eq!(dcf.iter().collect::<std::vec::Vec<_>>(), [a]);
    // A data slice that fits a header but not its data.
    let mut small = [0u8; 8];
    assert_eq!(
        b.emit(&mut small),
        Err(ConciseDcfError::BufferTooSmall { need: 11, got: 8 })
    );
}

proptest::proptest! {
    #![proptest_config(crate::testing::proptest_config("tests/proptest-regressions/src-od-concise.txt"))]

    /// Whatever entries are written read back the same, in order, and the
    /// buffer and Vec writers agree byte for byte.
    #[test]
    fn emit_then_parse_round_trips(
        entries in proptest::collection::vec(
            (proptest::prelude::any::<u16>(), proptest::prelude::any::<u8>(),
             proptest::collection::vec(proptest::prelude::any::<u8>(), 0..20)),
            0..12,
        )
    ) {
        let list: std::vec::Vec<ConciseEntry<'_>> = entries
            .iter()
            .map(|(i, s, d)| ConciseEntry::new(Address::new(*i, *s), d))
            .collect();
        let need = COUNT_LEN + list.iter().map(ConciseEntry::buffer_len).sum::<usize>();
        let mut bytes = std::vec![0u8; need];
        proptest::prop_assert_eq!(ConciseDcf::encode(list.iter().copied(), &mut bytes), Ok(need));
        #[cfg(feature = "alloc")]
        proptest::prop_assert_eq!(&ConciseDcf::encode_vec(list.iter().copied()).unwrap(), &bytes);
        let dcf = ConciseDcf::new_checked(&bytes).unwrap();
        proptest::prop_assert_eq!(usize::try_from(dcf.len()).unwrap(), list.len());
        proptest::prop_assert_eq!(dcf.iter().collect::<std::vec::Vec<_>>(), list);
        // One byte less is never a concise DCF.
        if let Some(short) = bytes.get(..need - 1) {
            proptest::prop_assert!(ConciseDcf::new_checked(short).is_err());
        }
    }
}
