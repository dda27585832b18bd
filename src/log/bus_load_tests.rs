use super::*;
use proptest::prelude::*;

/// The reference: the frame's bits fed one at a time, the CRC shifted a
/// bit at a time, a stuff bit after every five equal bits (ISO 11898-1
/// section 10.5, as the rules say it).
fn stuff_bits_bit_by_bit(frame: &CanFrame) -> u32 {
    let mut s = Stuffing::default();
    s.field(0, 1);
    let rtr = u32::from(frame.is_remote());
    match frame.id() {
        CanId::Standard(id) => {
            s.field(u32::from(id), 11);
            s.field(rtr, 1);
            s.field(0, 2);
        }
        CanId::Extended(id) => {
            s.field(id >> 18, 11);
            s.field(0b11, 2);
            s.field(id & 0x3_FFFF, 18);
            s.field(rtr, 1);
            s.field(0, 2);
        }
    }
    s.field(u32::from(frame.dlc()), 4);
    if !frame.is_remote() {
        for &byte in frame.data() {
            s.field(u32::from(byte), 8);
        }
    }
    let crc = s.crc;
    s.crc_done = true;
    s.field(u32::from(crc), 15);
    s.stuff
}

/// The stuffing and the CRC over a frame's bits, fed most significant bit
/// first.
#[derive(Default)]
struct Stuffing {
    crc: u16,
    /// The CRC sequence is being sent: it is not its own input.
    crc_done: bool,
    /// The last bit sent (stuff bits included) and how many equal ones.
    last: bool,
    run: u8,
    stuff: u32,
}

impl Stuffing {
    /// The `n` low bits of `value`, most significant first.
    fn field(&mut self, value: u32, n: u32) {
        for i in (0..n).rev() {
            self.bit(value.checked_shr(i).unwrap_or(0) & 1 == 1);
        }
    }

    fn bit(&mut self, bit: bool) {
        if !self.crc_done {
            let top = self.crc & 0x4000 != 0;
            self.crc = (self.crc << 1) & 0x7FFF;
            if bit != top {
                self.crc ^= CRC15_POLY;
            }
        }
        if self.run > 0 && bit == self.last {
            self.run += 1;
        } else {
            self.last = bit;
            self.run = 1;
        }
        if self.run == 5 {
            // The stuff bit, of the opposite value, starts the next run.
            self.stuff += 1;
            self.last = !bit;
            self.run = 1;
        }
    }
}

fn frame(text: &str) -> CanFrame {
    crate::trace::candump::parse_frame(text).unwrap()
}

#[test]
fn the_hand_counted_frames() {
    // (frame, unstuffed, exact, worst case): the module's table.
    for (text, unstuffed, stuffed, worst_case) in [
        ("000#", 47, 53, 55),
        ("000#R", 47, 50, 55),
        ("6F8#FF000CFE00000000", 111, 124, 135),
        ("18EBFF00#01A00FA6603BD140", 131, 141, 160),
    ] {
        assert_eq!(
            FrameBits::of(&frame(text)),
            FrameBits {
                unstuffed,
                stuffed,
                worst_case
            },
            "{text}"
        );
    }
}

#[test]
fn canoe_bit_counts_of_python_cans_logfile_asc() {
    // The extended frames of python-can's test/data/logfile.asc with the
    // BitCount Vector CANoe wrote beside them (intermission included).
    for (data, canoe) in [
        ("01A00FA6603BD140", 141),
        ("021FDE8025DFC02B", 140),
        ("03E1004BFFFF3C0F", 146),
        ("04004BFFFFFFFFFF", 146),
    ] {
        let f = frame(&format!("18EBFF00#{data}"));
        assert_eq!(FrameBits::of(&f).stuffed, canoe, "{data}");
    }
}

#[test]
fn a_remote_frame_counts_its_dlc_bits_but_no_data() {
    let r = FrameBits::of(&frame("123#R8"));
    assert_eq!((r.unstuffed, r.worst_case), (47, 55));
    // The DLC's bits differ from DLC 0's, so may its stuffing.
    assert_ne!(stuff_bits(&frame("000#R8")), stuff_bits(&frame("000#R")));
}

#[test]
fn load_windows_and_shares() {
    let mut l = BusLoad::new(Some(125_000));
    // 10 frames of node 1's TPDO1 in the first second, one of node 2 in
    // the third, one NMT command.
    for i in 0..10u64 {
        l.frame(
            Some(Timestamp::from_micros(1_000_000 + i * 1000)),
            &frame("181#0000000000000000"),
        );
    }
    l.frame(Some(Timestamp::from_micros(3_500_000)), &frame("182#01"));
    l.frame(Some(Timestamp::from_micros(3_600_000)), &frame("000#0102"));
    assert_eq!(l.frames(), 12);
    let b181 = FrameBits::of(&frame("181#0000000000000000")).stuffed;
    let peak = l.peak().unwrap();
    assert_eq!((peak.index, peak.frames), (0, 10));
    assert_eq!(peak.bits.stuffed, 10 * u64::from(b181));
    let (_, mid, _) = l.window_percent(&peak);
    assert!((mid - f64::from(10 * b181) * 100.0 / 125_000.0).abs() < 1e-9);
    // Duration: 2.6 s plus the first frame's bits at 125 kbit/s.
    assert!((l.duration() - (2.6 + f64::from(b181) / 125_000.0)).abs() < 1e-9);
    let nodes = l.nodes();
    assert_eq!(nodes.first().map(|n| (n.0, n.1.frames)), Some((1, 10)));
    assert!(nodes.iter().any(|n| n.0 == 0 && n.1.frames == 1));
    let (ids, other) = l.cob_ids();
    assert_eq!(ids.len(), 3);
    assert_eq!(other, Share::default());
    assert_eq!(ids.iter().map(|i| i.1.bits).sum::<u64>(), l.bits().stuffed);
    let (assumed, given) = (BusLoad::default().bitrate(), l.bitrate());
    assert_eq!(assumed, (DEFAULT_BITRATE, true));
    assert_eq!(given, (125_000, false));
}

#[test]
fn hostile_times_do_not_loop_or_overflow() {
    let mut l = BusLoad::new(None);
    let f = frame("7FF#FFFFFFFFFFFFFFFF");
    l.frame(Some(Timestamp::from_micros(u64::MAX)), &f);
    l.frame(Some(Timestamp::ZERO), &f);
    l.frame(None, &f);
    l.frame(Some(Timestamp::from_micros(u64::MAX)), &f);
    assert_eq!(l.frames(), 4);
    assert!(l.mean_percent().1.is_finite());
    let mut text = String::new();
    l.words(&mut text);
    l.json(&mut text);
    assert!(text.contains("bus load at 250000 bit/s (assumed"));
}

fn any_frame() -> impl Strategy<Value = CanFrame> {
    (
        any::<bool>(),
        0u32..=0x1FFF_FFFF,
        any::<bool>(),
        proptest::collection::vec(any::<u8>(), 0..=8),
        0u8..=8,
    )
        .prop_map(|(ext, raw, remote, data, dlc)| {
            let id = if ext {
                CanId::Extended(raw)
            } else {
                CanId::Standard((raw & 0x7FF) as u16)
            };
            if remote {
                CanFrame::remote(id, dlc).unwrap()
            } else {
                CanFrame::new(id, &data).unwrap()
            }
        })
}

proptest! {
    #[test]
    fn the_table_and_run_count_agrees_with_the_bit_by_bit_count(f in any_frame()) {
        prop_assert_eq!(stuff_bits(&f), stuff_bits_bit_by_bit(&f), "{}", f);
    }

    #[test]
    fn the_exact_count_lies_between_the_bounds(f in any_frame()) {
        let b = FrameBits::of(&f);
        prop_assert!(b.unstuffed <= b.stuffed && b.stuffed <= b.worst_case, "{f}: {b:?}");
    }

    #[test]
    fn the_load_counts_each_frame_as_frame_bits_does(
        frames in proptest::collection::vec(any_frame(), 1..40),
        repeats in proptest::collection::vec(0usize..40, 0..200),
    ) {
        // Frames repeated (the cache's hits) and new ones.
        let mut l = BusLoad::new(None);
        let mut want = 0u64;
        for f in frames.iter().chain(repeats.iter().filter_map(|&i| frames.get(i))) {
            let b = l.frame(None, f);
            prop_assert_eq!(b, FrameBits::of(f));
            want += u64::from(b.stuffed);
        }
        prop_assert_eq!(l.bits().stuffed, want);
    }

    #[test]
    fn the_mean_load_lies_between_the_loads_of_the_bounds(
        frames in proptest::collection::vec((any_frame(), 0u64..5_000_000), 1..50)
    ) {
        let mut l = BusLoad::new(Some(500_000));
        let mut t = 0u64;
        for (f, gap) in &frames {
            t += gap;
            l.frame(Some(Timestamp::from_micros(t)), f);
        }
        let (lo, mid, hi) = l.mean_percent();
        prop_assert!(lo <= mid && mid <= hi, "{lo} {mid} {hi}");
        let p = l.peak().unwrap();
        let (lo, mid, hi) = l.window_percent(&p);
        prop_assert!(lo <= mid && mid <= hi);
    }
}

#[test]
fn long_runs_agree_with_the_bit_by_bit_count() {
    // Runs of equal bits across field borders, stuff bits ending runs.
    let ids = [
        CanId::Standard(0),
        CanId::Standard(0x7FF),
        CanId::Standard(0x41F),
        CanId::Extended(0),
        CanId::Extended(0x1FFF_FFFF),
        CanId::Extended(0x0783_E0F8),
    ];
    for id in ids {
        for len in 0..=8usize {
            for pattern in [0x00u8, 0xFF, 0x0F, 0xF0, 0x1F, 0x83, 0xE0] {
                let data = vec![pattern; len];
                let f = CanFrame::new(id, &data).unwrap();
                assert_eq!(stuff_bits(&f), stuff_bits_bit_by_bit(&f), "{f}");
            }
            let r = CanFrame::remote(id, len as u8).unwrap();
            assert_eq!(stuff_bits(&r), stuff_bits_bit_by_bit(&r), "{r}");
        }
    }
}
