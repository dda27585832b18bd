//! Fuzz the concise DCF codec (CiA 302-3 section 4, the value of 1F22h).
//!
//! Input: any bytes, read as a concise DCF.
//!
//! Invariants: checking never panics; whatever checks yields exactly the
//! count's entries, each within the input, and writing them again (into a
//! buffer and into a Vec) gives the input byte for byte; whatever is refused
//! is not refused for a reason the bytes contradict (a `NoCount` input is
//! shorter than 4 bytes).
#![no_main]

use canopen_codec::od::{ConciseDcf, ConciseDcfError};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match ConciseDcf::new_checked(data) {
        Ok(dcf) => {
            assert_eq!(dcf.buffer_len(), data.len());
            let entries: Vec<_> = dcf.iter().collect();
            assert_eq!(entries.len(), dcf.len() as usize);
            assert_eq!(dcf.iter().len(), entries.len());
            let mut out = vec![0u8; data.len()];
            assert_eq!(ConciseDcf::encode(entries.iter().copied(), &mut out), Ok(data.len()));
            assert_eq!(out, data);
            assert_eq!(ConciseDcf::encode_vec(entries).as_deref(), Ok(data));
            if let Some(short) = data.len().checked_sub(1) {
                let mut small = vec![0u8; short];
                assert!(ConciseDcf::encode(dcf.iter(), &mut small).is_err());
            }
        }
        Err(ConciseDcfError::NoCount { got }) => {
            assert!(data.len() < 4);
            assert_eq!(got, data.len());
        }
        Err(_) => assert!(data.len() >= 4),
    }
});
