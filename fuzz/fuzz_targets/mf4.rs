//! The MF4 reader under arbitrary bytes, its `##DZ` blocks inflated by
//! flate2's zlib (as the programs do) or handed back as they are (so the
//! fuzzer reaches the records of "compressed" blocks without writing
//! zlib). Invariants: no panic; a frame has at most 8 data bytes; reading
//! the same file twice gives the same events; after a fatal error the
//! reader gives it again.
#![no_main]

use canopen_codec::log::input::Zlib;
use canopen_codec::trace::inflate::{Inflate, Inflated};
use canopen_codec::trace::mf4::{Mf4Error, Mf4Event, Mf4Reader};
use libfuzzer_sys::fuzz_target;

/// An "inflater" that copies its input: a `##DZ` block's bytes are its
/// records.
struct Copy;

impl Inflate for Copy {
    fn reset(&mut self) {}

    fn inflate(&mut self, input: &[u8], output: &mut [u8]) -> Result<Inflated, String> {
        let n = input.len().min(output.len());
        output[..n].copy_from_slice(&input[..n]);
        Ok(Inflated {
            used: n,
            made: n,
            end: n == input.len(),
        })
    }
}

/// The most events read (a small deflated block may hold millions).
const MAX_EVENTS: usize = 100_000;

/// The events (as text) and the end of reading `file`.
fn read(file: &[u8], zlib: &mut dyn Inflate) -> (Vec<String>, Result<(), Mf4Error>) {
    let mut events = Vec::new();
    let mut r = match Mf4Reader::new(file) {
        Ok(r) => r,
        Err(e) => {
            assert!(e.is_fatal());
            return (events, Err(e));
        }
    };
    while events.len() < MAX_EVENTS {
        match r.next(zlib) {
            Ok(None) => return (events, Ok(())),
            Ok(Some(Mf4Event::Frame(f))) => {
                assert!(f.frame.data().len() <= 8);
                events.push(format!("{:?} {} {:?} {:?}", f.timestamp, f.frame, f.direction, f.channel));
            }
            Ok(Some(e)) => events.push(format!("{e:?}")),
            Err(e) if e.is_fatal() => {
                assert_eq!(r.next(zlib), Err(e));
                return (events, Err(e));
            }
            Err(e) => events.push(format!("bad {e}")),
        }
    }
    (events, Ok(()))
}

// The input: a flag byte (bit 0: flate2's zlib, else the copying
// inflater), then the file (fuzz/seeds/mf4 has files python-can and
// asammdf wrote, in this layout).
fuzz_target!(|input: &[u8]| {
    let [flags, file @ ..] = input else {
        return;
    };
    let once = |z: &mut dyn Inflate| read(file, z);
    let (first, second) = if flags & 1 != 0 {
        (once(&mut Zlib::default()), once(&mut Zlib::default()))
    } else {
        (once(&mut Copy), once(&mut Copy))
    };
    assert_eq!(first, second);
});
