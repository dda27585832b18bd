//! The pcap / pcapng reader under arbitrary bytes in arbitrary chunk
//! sizes. Invariants: no panic; every event takes input (the number of
//! events is bounded by the bytes fed); the frames are the same whatever
//! the chunks; a frame has at most 8 data bytes; after a fatal error the
//! reader gives it again.
#![no_main]

use canopen_codec::trace::pcap::{PcapError, PcapEvent, PcapReader};
use libfuzzer_sys::fuzz_target;

/// The events (as text) and the end of reading `bytes` in chunks of the
/// sizes `sizes` gives in turn.
fn read(bytes: &[u8], sizes: &[u8]) -> (Vec<String>, Result<(), PcapError>) {
    let mut r = PcapReader::new();
    let mut seen = Vec::new();
    let mut rest = bytes;
    let mut k = 0;
    while !rest.is_empty() {
        let n = usize::from(sizes.get(k % sizes.len().max(1)).copied().unwrap_or(255)).max(1);
        k += 1;
        let (mut chunk, tail) = rest.split_at(n.min(rest.len()));
        rest = tail;
        loop {
            match r.read(&mut chunk) {
                Ok(None) => break,
                Ok(Some(PcapEvent::Frame(f))) => {
                    assert!(f.frame.data().len() <= 8);
                    seen.push(format!("{:?} {} {}", f.timestamp, f.frame, f.interface));
                }
                Ok(Some(e)) => seen.push(format!("{e:?}")),
                Err(e) if e.is_fatal() => {
                    assert_eq!(r.read(&mut &b"\x0A\x0D\x0D\x0A"[..]), Err(e));
                    assert_eq!(r.finish(), Err(e));
                    return (seen, Err(e));
                }
                Err(e) => seen.push(format!("{e:?}")),
            }
            // Every packet is at least 8 bytes of the file.
            assert!(seen.len() <= bytes.len() / 8 + 1, "events without input");
        }
    }
    (seen, r.finish())
}

/// A little-endian Section Header Block and an Interface Description
/// Block of link type 227 with nanosecond times.
const PCAPNG_HEAD: [u8; 48] = [
    0x0A, 0x0D, 0x0D, 0x0A, 28, 0, 0, 0, 0x4D, 0x3C, 0x2B, 0x1A, 1, 0, 0, 0, 0xFF, 0xFF, 0xFF,
    0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 28, 0, 0, 0, // SHB
    1, 0, 0, 0, 20, 0, 0, 0, 227, 0, 0, 0, 0, 0, 0, 0, 20, 0, 0, 0, // IDB
];

/// A little-endian pcap header: microseconds, link type 227.
const PCAP_HEAD: [u8; 24] = [
    0xD4, 0xC3, 0xB2, 0xA1, 2, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF, 0, 0, 227, 0, 0, 0,
];

// The input: a byte of chunk size (0: chunks of 1 to 8 bytes in turn), a
// flag byte (bit 0: a valid pcapng head before the rest; else bit 1: a
// valid pcap header), then the file's bytes (fuzz/seeds/pcap has
// real-shaped files in this layout).
fuzz_target!(|input: &[u8]| {
    let [size, flags, body @ ..] = input else {
        return;
    };
    let sizes: Vec<u8> = if *size == 0 {
        (1..=8).collect()
    } else {
        vec![*size]
    };
    let mut bytes = Vec::new();
    if flags & 1 != 0 {
        bytes.extend_from_slice(&PCAPNG_HEAD);
    } else if flags & 2 != 0 {
        bytes.extend_from_slice(&PCAP_HEAD);
    }
    bytes.extend_from_slice(body);
    let chunked = read(&bytes, &sizes);
    let whole = read(&bytes, &[255]);
    assert_eq!(chunked, whole);
});
