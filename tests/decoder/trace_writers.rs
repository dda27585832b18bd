//! CAN frames written in every trace format the decoder reads, as their
//! writers write them (can-utils candump, PEAK PCAN-View, Vector, python-can):
//! every row of the README's "Trace formats" table, with timed lines
//! (candump screen `-t a`, `-t z` and `-t d`; `.trc` 1.0 to 2.1 with and
//! without a start time). For tests that check a program reads each format
//! as it reads the candump log.
#![allow(dead_code)]

use canopen_codec::trace::candump::parse_line;
use canopen_codec::{CanFrame, CanId};

/// A recording's frames: (microseconds since its first frame, frame).
pub fn frames_of(log: &str) -> Vec<(u64, CanFrame)> {
    let lines: Vec<_> = log.lines().map(|l| parse_line(l).unwrap()).collect();
    let first = lines[0].timestamp.unwrap().as_micros();
    lines
        .iter()
        .map(|l| (l.timestamp.unwrap().as_micros() - first, l.frame))
        .collect()
}

/// The UNIX time the written traces start at (where a format has one).
const UNIX_START_US: u64 = 1_763_800_000_000_000;
/// The same start as a PCAN `$STARTTIME` (days since 1899-12-30) and as a
/// BLF SYSTEMTIME (2025-11-22 08:26:40.000, a Saturday).
const TRC_START: &str = "45983.35185185185";
pub const BLF_START: [u16; 8] = [2025, 11, 6, 22, 8, 26, 40, 0];

/// `(seconds, microseconds)` of `us`.
fn sec(us: u64) -> (u64, u64) {
    (us / 1_000_000, us % 1_000_000)
}

/// The data bytes as two hex digits each, spaced.
fn spaced(f: &CanFrame) -> String {
    f.data()
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The 11-bit identifier of a data frame (what the writers below write).
fn std_id(f: &CanFrame) -> u16 {
    match f.id() {
        CanId::Standard(id) if !f.is_remote() => id,
        _ => panic!("the line writers here write 11-bit data frames only: {f}"),
    }
}

/// Standard base64 with padding (RFC 4648), as python-can's CSV has it.
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// `frames` written in one format: `(name, --format to give or None, bytes)`.
/// Every format as its writer writes it, the candump log first.
pub fn every_format(
    frames: &[(u64, CanFrame)],
) -> Vec<(&'static str, Option<&'static str>, Vec<u8>)> {
    let lines = |head: &str, line: &dyn Fn(usize, u64, &CanFrame) -> String, tail: &str| {
        let mut text = head.to_string();
        for (n, (us, f)) in frames.iter().enumerate() {
            text.push_str(&line(n + 1, *us, f));
            text.push('\n');
        }
        text.push_str(tail);
        text.into_bytes()
    };
    let ms = |us: u64| us as f64 / 1000.0;
    let screen = |ts: String, f: &CanFrame| {
        format!(
            "{ts}  can0  {:03X}   [{}]  {}",
            std_id(f),
            f.dlc(),
            spaced(f)
        )
    };
    let deltas = std::cell::Cell::new(0u64);
    let mut out = vec![
        (
            "candump log",
            None,
            lines(
                "",
                &|_, us, f| {
                    let (s, u) = sec(UNIX_START_US + us);
                    format!("({s}.{u:06}) can0 {f}")
                },
                "",
            ),
        ),
        (
            "candump screen -t a",
            None,
            lines(
                "",
                &|_, us, f| {
                    let (s, u) = sec(UNIX_START_US + us);
                    screen(format!("({s}.{u:06})"), f)
                },
                "",
            ),
        ),
        (
            "candump screen -t z",
            None,
            lines(
                "",
                &|_, us, f| {
                    let (s, u) = sec(us);
                    screen(format!("({s:03}.{u:06})"), f)
                },
                "",
            ),
        ),
        (
            "candump screen -t d",
            Some("candump-screen-delta"),
            lines(
                "",
                &|_, us, f| {
                    let (s, u) = sec(us - deltas.replace(us));
                    screen(format!("({s:03}.{u:06})"), f)
                },
                "",
            ),
        ),
        (
            "PCAN .trc 1.0",
            Some("trc"),
            lines(
                "",
                &|n, us, f| {
                    assert_eq!(us % 1000, 0, "PCAN 1.0 offsets are whole ms");
                    format!(
                        "{n:>6})  {:>10}  {:04X}  {}  {}",
                        us / 1000,
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "",
            ),
        ),
        (
            "PCAN .trc 1.1",
            None,
            lines(
                &format!(";$FILEVERSION=1.1\n;$STARTTIME={TRC_START}\n;   comment\n"),
                &|n, us, f| {
                    format!(
                        "{n:>6})  {:>12.1}  Rx         {:04X}  {}  {}",
                        ms(us),
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "",
            ),
        ),
        (
            "PCAN .trc 1.2",
            None,
            lines(
                ";$FILEVERSION=1.2\n",
                &|n, us, f| {
                    format!(
                        "{n:>6})  {:>12.3} 1  Rx         {:04X}  {}  {}",
                        ms(us),
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "",
            ),
        ),
        (
            "PCAN .trc 1.3",
            None,
            lines(
                ";$FILEVERSION=1.3\n",
                &|n, us, f| {
                    format!(
                        "{n:>6})  {:>12.3} 1  Rx         {:04X} -  {}  {}",
                        ms(us),
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "",
            ),
        ),
        (
            "PCAN .trc 2.0",
            None,
            lines(
                ";$FILEVERSION=2.0\n;$COLUMNS=N,O,T,I,d,l,D\n",
                &|n, us, f| {
                    format!(
                        "{n:>7} {:>13.3} DT     {:04X} Rx {}  {}",
                        ms(us),
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "",
            ),
        ),
        (
            "PCAN .trc 2.1",
            None,
            lines(
                &format!(
                    ";$FILEVERSION=2.1\n;$STARTTIME={TRC_START}\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n"
                ),
                &|n, us, f| {
                    format!(
                        "{n:>7} {:>13.3} DT 1      {:04X} Rx -  {}    {}",
                        ms(us),
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "",
            ),
        ),
        (
            "Vector ASC",
            None,
            lines(
                "date Sat Nov 22 08:26:40.000 2025\nbase hex  timestamps absolute\n\
                 internal events logged\nBegin Triggerblock Sat Nov 22 08:26:40.000 2025\n\
                 \x20  0.000000 Start of measurement\n",
                &|_, us, f| {
                    let (s, u) = sec(us);
                    format!(
                        "{s:>4}.{u:06} 1  {:<15X} Rx   d {} {}",
                        std_id(f),
                        f.dlc(),
                        spaced(f)
                    )
                },
                "End TriggerBlock\n",
            ),
        ),
        (
            "python-can CSV",
            None,
            lines(
                "timestamp,arbitration_id,extended,remote,error,dlc,data\n",
                &|_, us, f| {
                    let (s, u) = sec(UNIX_START_US + us);
                    format!(
                        "{s}.{u:06},{:#x},0,0,0,{},{}",
                        std_id(f),
                        f.dlc(),
                        base64(f.data())
                    )
                },
                "",
            ),
        ),
    ];
    out.push((
        "Vector BLF",
        None,
        crate::blf_support::file(
            BLF_START,
            &crate::blf_support::can_objects(frames),
            4096,
            true,
        ),
    ));
    out
}
