use super::*;
use crate::log::frame_bits::CRC15_POLY;
use crate::trace::{FdFrame, OnBus};
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
    /// The last bit sent is a stuff bit.
    ended_with_stuff: bool,
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
        self.ended_with_stuff = self.run == 5;
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
                nominal: Counts {
                    unstuffed,
                    stuffed,
                    worst_case
                },
                data: Counts::default(),
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
        assert_eq!(FrameBits::of(&f).total().stuffed, canoe, "{data}");
    }
}

#[test]
fn a_remote_frame_counts_its_dlc_bits_but_no_data() {
    let r = FrameBits::of(&frame("123#R8")).total();
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
    let b181 = FrameBits::of(&frame("181#0000000000000000"))
        .total()
        .stuffed;
    let peak = l.peak().unwrap();
    assert_eq!((peak.index, peak.frames), (0, 10));
    // Classic frames only: a bit is as many ticks as the data rate.
    let data_rate = u64::from(l.data_bitrate().0);
    assert_eq!(peak.time.stuffed, 10 * u64::from(b181) * data_rate);
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
    assert_eq!(
        ids.iter().map(|i| i.1.time).sum::<u64>(),
        l.time_on_bus().stuffed
    );
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
        let b = FrameBits::of(&f).total();
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
            want += l.time(&b).stuffed;
        }
        prop_assert_eq!(l.time_on_bus().stuffed, want);
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

/// A CAN FD frame from candump's `ID##F` text.
fn fd(text: &str) -> FdFrame {
    match crate::trace::candump::parse_on_bus(text) {
        Ok((_, OnBus::Fd(f))) => f,
        other => std::panic!("{text}: {other:?}"),
    }
}

/// Bits at the nominal and at the data rate: (unstuffed, exact, worst
/// case) each.
fn split(b: FrameBits) -> ((u32, u32, u32), (u32, u32, u32)) {
    let c = |c: Counts| (c.unstuffed, c.stuffed, c.worst_case);
    (c(b.nominal), c(b.data))
}

#[test]
fn fd_base_8_bytes_without_brs() {
    // 123##0 + 8 zero bytes, all at the nominal rate:
    // SOF 0 | ID 001 0010 0011 | RRS 0 | IDE 0 | FDF 1 | res 0 | BRS 0
    //   = 17 bits, runs 3 1 2 1 3 2 2 1 2 (no stuff bit)
    // ESI 0 | DLC 1000 | data 64 zeros = 69 bits: the DLC's three zeros
    //   and the data's 64 are one run of 67 (res, BRS and ESI are 3 zeros
    //   before the DLC's 1): floor(67 / 5) = 13 stuff bits, the last run
    //   of 2 ending the data (no stuff bit due there)
    // stuff count 4 | CRC-17 | fixed stuff bits 6 = 27
    // CRC delimiter 1 | ACK 1 | ACK delimiter 1 | EOF 7 | IFS 3 = 13
    // unstuffed 17 + 69 + 27 + 13 = 126; exact 126 + 13 = 139;
    // worst case: g = 86 bits from SOF to the data's end, floor(85 / 4) = 21.
    let b = FrameBits::of_fd(&fd("123##00000000000000000"));
    assert_eq!(split(b), ((126, 139, 147), (0, 0, 0)));
}

#[test]
fn fd_base_64_bytes_with_brs() {
    // 123##1 + 64 bytes FFh.
    // Nominal: SOF 0 | ID 001 0010 0011 | RRS 0 | IDE 0 | FDF 1 | res 0 |
    //   BRS 1 = 17 bits (runs 3 1 2 1 3 2 2 1 1 1: no stuff bit), and the
    //   tail CRC delimiter 1, ACK 1, ACK delimiter 1, EOF 7, IFS 3 = 13:
    //   30 bits; worst case floor((17 - 1) / 4) = 4 more.
    // Data: ESI 0 | DLC 1111 | data 512 ones = 517 bits, the DLC's ones
    //   and the data's one run of 516: floor(516 / 5) = 103 stuff bits;
    //   stuff count 4 | CRC-21 | fixed stuff bits 7 = 32: 549 bits.
    //   Worst case: g = 17 + 517 = 534, floor(533 / 4) = 133 stuff bits,
    //   4 of them in the arbitration phase: 549 + 129 = 678.
    let b = FrameBits::of_fd(&fd(&format!("123##1{}", "FF".repeat(64))));
    assert_eq!(split(b), ((30, 30, 34), (549, 652, 678)));
}

#[test]
fn fd_extended_12_bytes_with_brs() {
    // 12345678##1 + 12 zero bytes: identifier 048Dh (11 bits) and 05678h
    // (18 bits).
    // Nominal: SOF 0 | ID 100 1000 1101 | SRR 1 | IDE 1 |
    //   ID 00 0101 0110 0111 1000 | RRS 0 | FDF 1 | res 0 | BRS 1 = 36 bits,
    //   runs 1 1 2 1 3 2 1 3 3 1 1 1 1 2 2 4 4 1 1 1 (none of 5); tail 13:
    //   49 bits; worst case floor(35 / 4) = 8 more.
    // Data: ESI 0 | DLC 1001 (12 bytes) | data 96 zeros = 101 bits, the
    //   data one run of 96: 19 stuff bits; stuff count 4 | CRC-17 | fixed
    //   stuff bits 6 = 27: 128 bits. Worst case: g = 36 + 101 = 137,
    //   floor(136 / 4) = 34, 8 in the arbitration phase: 128 + 26 = 154.
    let b = FrameBits::of_fd(&fd(&format!("12345678##1{}", "00".repeat(12))));
    assert_eq!(split(b), ((49, 49, 57), (128, 147, 154)));
}

#[test]
fn fd_crc_17_up_to_16_bytes_crc_21_above() {
    // 123##1 + AAh bytes: ESI 0, DLC 1010 (16) or 1011 (20), then
    // 1010 1010...: no run of 5 after BRS (20 bytes: the DLC's 11 and the
    // data's first 1 make a run of 3).
    // 16 bytes: 5 + 128 + (4 + 17 + 6) = 160 at the data rate;
    // 20 bytes: 5 + 160 + (4 + 21 + 7) = 197.
    for (n, data) in [(16, 160), (20, 197)] {
        let b = FrameBits::of_fd(&fd(&format!("123##1{}", "AA".repeat(n))));
        assert_eq!(
            (b.nominal.stuffed, b.data.unstuffed, b.data.stuffed),
            (30, data, data),
            "{n} bytes"
        );
    }
}

#[test]
fn the_first_fixed_stuff_bit_takes_the_place_of_a_dynamic_one() {
    // 123##1 + 1Fh: ... FDF 1 | res 0 | BRS 1 | ESI 0 | DLC 0001 |
    // 0001 1111: the data ends with a run of 5 ones, whose stuff bit the
    // CRC field's first fixed stuff bit replaces: no dynamic stuff bit.
    // 62 + 8 = 70 bits, 17 + 13 nominal and 5 + 8 + 27 data. Worst case:
    // g = 30, floor(29 / 4) = 7 stuff bits, 4 in the arbitration phase.
    let b = FrameBits::of_fd(&fd("123##11F"));
    assert_eq!(split(b), ((30, 30, 34), (40, 40, 43)));
    assert_eq!(b.total().stuffed, 70);
}

#[test]
fn an_error_frame_is_17_to_23_bits() {
    let b = FrameBits::error_frame();
    assert_eq!(split(b), ((17, 17, 23), (0, 0, 0)));
}

/// The reference for CAN FD: the bits fed one at a time, a stuff bit after
/// every five equal bits from start of frame to the end of the data, none
/// due after the last data bit (the fixed stuff bit takes its place), and
/// the stuff bits counted until BRS kept apart.
fn fd_stuff_bit_by_bit(f: &FdFrame) -> (u32, u32) {
    let mut s = Stuffing {
        crc_done: true,
        ..Stuffing::default()
    };
    s.field(0, 1);
    match f.id() {
        CanId::Standard(id) => {
            s.field(u32::from(id), 11);
            s.field(0, 2);
        }
        CanId::Extended(id) => {
            s.field(id >> 18, 11);
            s.field(0b11, 2);
            s.field(id & 0x3_FFFF, 18);
            s.field(0, 1);
        }
    }
    s.field(0b10, 2);
    s.field(u32::from(f.brs()), 1);
    let arbitration = s.stuff;
    s.field(u32::from(f.esi()), 1);
    s.field(u32::from(f.dlc()), 4);
    for &byte in f.data() {
        s.field(u32::from(byte), 8);
    }
    // A stuff bit due after the last data bit: its run is 1, of the value
    // opposite to the last bit's, after exactly 5 (counted in `stuff`).
    let ended = s.run == 1 && s.ended_with_stuff;
    (arbitration, s.stuff - u32::from(ended))
}

fn any_fd_frame() -> impl Strategy<Value = FdFrame> {
    (
        any::<bool>(),
        0u32..=0x1FFF_FFFF,
        proptest::collection::vec(
            prop_oneof![Just(0u8), Just(0xFF), Just(0x0F), Just(0xF0), any::<u8>()],
            0..=64,
        ),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(ext, raw, data, brs, esi)| {
            let id = if ext {
                CanId::Extended(raw)
            } else {
                CanId::Standard((raw & 0x7FF) as u16)
            };
            FdFrame::new(id, &data, brs, esi).unwrap()
        })
}

proptest! {
    #[test]
    fn fd_stuffing_agrees_with_the_bit_by_bit_count(f in any_fd_frame()) {
        let b = FrameBits::of_fd(&f);
        let (arbitration, all) = fd_stuff_bit_by_bit(&f);
        prop_assert_eq!(b.total().stuffed - b.total().unstuffed, all, "{}", f);
        if f.brs() {
            prop_assert_eq!(b.nominal.stuffed - b.nominal.unstuffed, arbitration, "{}", f);
        }
        let t = b.total();
        prop_assert!(t.unstuffed <= t.stuffed && t.stuffed <= t.worst_case, "{f}: {b:?}");
    }

    #[test]
    fn fd_time_lies_between_its_bounds(f in any_fd_frame(), ratio in 1u32..=16) {
        let l = BusLoad::new(Some(500_000)).with_data_bitrate(Some(500_000 * ratio));
        let t = l.time(&FrameBits::of_fd(&f));
        prop_assert!(t.unstuffed <= t.stuffed && t.stuffed <= t.worst_case, "{f}: {t:?}");
    }
}

#[test]
fn fd_and_error_frames_in_the_load() {
    // 500 kbit/s nominal, 2 Mbit/s data: a nominal bit is 2 000 000 ticks,
    // a data bit 500 000.
    let mut l = BusLoad::new(Some(500_000)).with_data_bitrate(Some(2_000_000));
    assert_eq!(l.data_bitrate(), (2_000_000, false));
    let big = fd(&format!("123##1{}", "FF".repeat(64)));
    l.fd_frame(Some(Timestamp::from_micros(1_000_000)), &big);
    l.on_bus(Some(Timestamp::from_micros(1_500_000)), &OnBus::ErrorFrame);
    l.frame(Some(Timestamp::from_micros(2_000_000)), &frame("000#"));
    l.fd_frame_not_read();
    // The FD frame: 30 bits at 500 kbit/s and 652 at 2 Mbit/s, 60 + 326 =
    // 386 µs; the error frame 17 bits, 34 µs (23: 46 µs); 000# 53 bits,
    // 106 µs.
    let us = |ticks: u64| ticks as f64 / 1e6;
    let t = l.time_on_bus();
    assert_eq!(us(t.stuffed), 386.0 + 34.0 + 106.0);
    assert_eq!(us(t.unstuffed), (30.0 * 2.0 + 549.0 * 0.5) + 34.0 + 94.0);
    assert_eq!(us(t.worst_case), (34.0 * 2.0 + 678.0 * 0.5) + 46.0 + 110.0);
    // The log: 1 s from the first to the last frame, plus the first's 386 µs.
    assert!((l.duration() - 1.000_386).abs() < 1e-12);
    let (lo, mid, hi) = l.mean_percent();
    assert!((mid - 0.000_526 / 1.000_386 * 100.0).abs() < 1e-9, "{mid}");
    assert!(lo < mid && mid < hi);
    assert_eq!(l.error_frames(), 1);
    assert_eq!(l.fd_frames(), (1, 1, 1));
    // The error frame is no node's and no COB-ID's: the COB-IDs share the
    // rest.
    let (ids, _) = l.cob_ids();
    assert_eq!(
        ids.iter().map(|i| i.1.time).sum::<u64>(),
        t.stuffed - 34_000_000
    );
    assert_eq!(
        ids.first().map(|i| (i.0, i.1.bits)),
        Some((CanId::Standard(0x123), 682))
    );
    let mut words = String::new();
    l.words(&mut words);
    assert!(
        words.contains(
            "error frames: 1 (6.46% of the bus time: 17 bits each, 23 with superposed error flags)"
        ),
        "{words}"
    );
    assert!(words.contains("CAN FD frames: 1 in the load (1 with BRS, their data phase at 2000000 bit/s); 1 more read without their identifier and data, not in the load"), "{words}");
    let mut json = String::new();
    l.json(&mut json);
    assert!(
        json.contains("\"data_bitrate\":2000000,\"data_bitrate_assumed\":false"),
        "{json}"
    );
    assert!(
        json.contains("\"error_frames\":1,\"error_frames_share_percent\":6.46"),
        "{json}"
    );
    assert!(
        json.contains("\"fd_frames\":1,\"fd_brs_frames\":1,\"fd_frames_not_in_load\":1"),
        "{json}"
    );
}

#[test]
fn the_data_rate_is_assumed_and_never_below_the_nominal() {
    let l = BusLoad::new(Some(500_000));
    assert_eq!(l.data_bitrate(), (DEFAULT_DATA_BITRATE, true));
    let l = BusLoad::new(Some(1_000_000)).with_data_bitrate(Some(250_000));
    assert_eq!(l.data_bitrate(), (1_000_000, false));
    let l = BusLoad::new(Some(5_000_000));
    assert_eq!(l.data_bitrate(), (5_000_000, true));
}
