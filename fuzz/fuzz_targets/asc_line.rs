//! Vector ASC lines under arbitrary text, with the header lines that
//! change how later lines read (`base dec`, `timestamps relative`) among
//! them. Invariants: no panic; a frame has at most 8 data bytes and an
//! identifier in range; relative times never run backwards.
#![no_main]

use canopen_codec::trace::{Format, LineParser, Record};
use canopen_codec::CanId;
use libfuzzer_sys::fuzz_target;

const HEADERS: [&str; 4] = [
    "base hex  timestamps absolute",
    "base dec  timestamps absolute",
    "base hex  timestamps relative",
    "base dec  timestamps relative",
];

// The input: a byte choosing the `base` line, then the text
// (fuzz/seeds/asc_line has real-shaped logs in this layout).
fuzz_target!(|input: &[u8]| {
    let [header, bytes @ ..] = input else {
        return;
    };
    let mut p = LineParser::new(Format::VectorAsc);
    let head = HEADERS[usize::from(*header) % HEADERS.len()];
    let relative = head.ends_with("relative");
    assert!(matches!(p.parse(head), Ok(Record::Meta)));
    let text = String::from_utf8_lossy(bytes);
    // A later `base` line (its first word `base`, whatever whitespace
    // follows it: a carriage return too) may switch the times to absolute.
    let rebased = text
        .split('\n')
        .any(|l| l.split_whitespace().next() == Some("base"));
    let mut last = None;
    for line in text.split('\n').take(500) {
        if let Ok(Record::Frame(f)) = p.parse(line) {
            assert!(f.frame.data().len() <= 8);
            match f.frame.id() {
                CanId::Standard(id) => assert!(id <= 0x7FF),
                CanId::Extended(id) => assert!(id <= 0x1FFF_FFFF),
            }
            if relative && !rebased {
                if let (Some(a), Some(b)) = (last, f.timestamp) {
                    assert!(b >= a, "relative times run backwards");
                }
                last = f.timestamp;
            }
        }
    }
});
