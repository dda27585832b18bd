//! The BLF reader under arbitrary bytes in arbitrary chunk sizes, a zlib
//! container's pieces handed back as if they were the inflated bytes.
//! Invariants: no panic; every event takes input (the number of events is
//! bounded by the bytes fed); the frames are the same whatever the chunks;
//! a frame has at most 8 data bytes; after a fatal error the reader gives
//! it again.
#![no_main]

use canopen_codec::trace::blf::{BlfError, BlfEvent, BlfReader};
use libfuzzer_sys::fuzz_target;

/// The frames (as text) and the end of reading `bytes` in chunks of the
/// sizes `sizes` gives in turn.
fn read(bytes: &[u8], sizes: &[u8]) -> (Vec<String>, Result<(), BlfError>) {
    let mut r = BlfReader::new();
    let mut frames = Vec::new();
    let mut events = 0usize;
    let mut rest = bytes;
    let mut k = 0;
    let note = |e: &BlfEvent<'_>, frames: &mut Vec<String>| {
        if let BlfEvent::Frame(f) = e {
            assert!(f.frame.data().len() <= 8);
            frames.push(format!("{:?} {} {:?}", f.timestamp, f.frame, f.direction));
        }
    };
    while !rest.is_empty() {
        let n = usize::from(sizes.get(k % sizes.len().max(1)).copied().unwrap_or(255)).max(1);
        k += 1;
        let (mut chunk, tail) = rest.split_at(n.min(rest.len()));
        rest = tail;
        loop {
            let r1 = r.read(&mut chunk);
            if !matches!(r1, Ok(None)) {
                events += 1;
                assert!(events <= 2 * bytes.len() + 4, "events without input");
            }
            match r1 {
                Ok(None) => break,
                Ok(Some(BlfEvent::Compressed(mut z))) => loop {
                    let r2 = r.read_inflated(&mut z);
                    if !matches!(r2, Ok(None)) {
                        events += 1;
                        assert!(events <= 2 * bytes.len() + 4, "events without input");
                    }
                    match r2 {
                        Ok(None) => break,
                        Ok(Some(e)) => note(&e, &mut frames),
                        Err(e) if e.is_fatal() => {
                            assert_eq!(r.read(&mut &b"LOBJ"[..]), Err(e));
                            return (frames, Err(e));
                        }
                        Err(_) => {}
                    }
                },
                Ok(Some(e)) => note(&e, &mut frames),
                Err(e) if e.is_fatal() => {
                    assert_eq!(r.read(&mut &b"LOBJ"[..]), Err(e));
                    return (frames, Err(e));
                }
                Err(_) => {}
            }
        }
    }
    (frames, r.finish())
}

// The input: a byte of chunk size (0: chunks of 1 to 8 bytes in turn), a
// flag byte (bit 0: put a valid file header before the rest), then the
// file's bytes (fuzz/seeds/blf has real-shaped files in this layout).
fuzz_target!(|input: &[u8]| {
    let [size, flags, body @ ..] = input else {
        return;
    };
    let sizes: Vec<u8> = if *size == 0 {
        (1..=8).collect()
    } else {
        vec![*size]
    };
    let with_header = flags & 1 != 0;
    // Half the inputs get a valid file header, so the objects are reached.
    let mut bytes = Vec::new();
    if with_header {
        bytes.extend_from_slice(b"LOGG");
        bytes.extend_from_slice(&144u32.to_le_bytes());
        bytes.resize(144, 0);
    }
    bytes.extend_from_slice(body);
    let chunked = read(&bytes, &sizes);
    let whole = read(&bytes, &[255]);
    // Fatal errors stop at different events by chunk, so compare the
    // frames up to the shorter list, and the ends when both read to the end.
    let n = chunked.0.len().min(whole.0.len());
    assert_eq!(chunked.0.get(..n), whole.0.get(..n));
    if chunked.1.is_ok() || whole.1.is_ok() {
        assert_eq!(chunked, whole);
    }
});
