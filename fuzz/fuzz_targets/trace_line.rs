//! Every trace format's line parser under arbitrary text. Invariants: no
//! panic; a frame has at most 8 data bytes and a valid identifier; a frame
//! read from a candump log line writes back to a line that reads the same.
#![no_main]

use canopen_codec::trace::candump::{parse_line, LogLineDisplay};
use canopen_codec::trace::{Format, LineParser, Record};
use canopen_codec::Timestamp;
use libfuzzer_sys::fuzz_target;

const FORMATS: [Option<Format>; 6] = [
    None,
    Some(Format::CandumpLog),
    Some(Format::CandumpScreen),
    Some(Format::PcanTrc),
    Some(Format::VectorAsc),
    Some(Format::PythonCanCsv),
];

fuzz_target!(|input: (u8, bool, &[u8])| {
    let (sel, delta, bytes) = input;
    let format = FORMATS[usize::from(sel) % FORMATS.len()];
    let mut p = format.map_or_else(LineParser::auto, LineParser::new);
    if delta {
        p = p.with_delta_times();
    }
    let text = String::from_utf8_lossy(bytes);
    for line in text.split('\n').take(200) {
        if let Ok(Record::Frame(f)) = p.parse(line) {
            assert!(f.frame.data().len() <= 8);
            if p.format() == Some(Format::CandumpLog) {
                let again = LogLineDisplay {
                    timestamp: f.timestamp.unwrap_or(Timestamp::ZERO),
                    interface: f.channel.unwrap_or("can0"),
                    frame: &f.frame,
                }
                .to_string();
                assert_eq!(parse_line(&again).map(|l| l.frame), Ok(f.frame), "{again}");
            }
        }
    }
});
