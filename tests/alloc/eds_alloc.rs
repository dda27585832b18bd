//! The EDS reader allocates in proportion to the file: parsing a file twice
//! as long (the Delta-Q charger's EDS, 115 KB, and the same objects again
//! under other indexes) takes about twice the memory, and the peak stays a
//! small multiple of the file's size. Allocations are counted on the test's
//! thread by the binary's counting allocator (`counting`). The real file is read from the shared data folder beside the
//! checkout (or `$CANOPEN_EDS_DIR`); without it the test fails under
//! `CI=true` and elsewhere says it skipped and passes.

use canopen_codec::eds::parse_bytes;

use crate::{common, counting};

/// (peak bytes above the start, allocation calls) of parsing `bytes`.
fn measure(bytes: &[u8]) -> (usize, usize) {
    counting::reset_peak();
    let base = counting::live_bytes();
    let calls = counting::allocations();
    let eds = parse_bytes(bytes).expect("parses");
    let peak = usize::try_from(counting::peak_bytes() - base).unwrap();
    let n = usize::try_from(counting::allocations() - calls).unwrap();
    drop(eds);
    (peak, n)
}

#[test]
fn allocation_is_proportional_to_the_file() {
    let Some(path) = common::captures::eds_path("deltaq-iq3k3-charger.eds") else {
        return;
    };
    let one = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // The same objects again under indexes 8000h higher: twice the file.
    let text = String::from_utf8_lossy(&one).into_owned();
    let shifted: String = text
        .lines()
        .map(|l| match l.strip_prefix('[') {
            Some(rest)
                if rest.len() >= 5 && rest.as_bytes()[..4].iter().all(u8::is_ascii_hexdigit) =>
            {
                let index = u16::from_str_radix(&rest[..4], 16).unwrap();
                format!("[{:04X}{}\n", index | 0x8000, &rest[4..])
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let two = [one.as_slice(), b"\n", shifted.as_bytes()].concat();
    let (peak1, calls1) = measure(&one);
    let (peak2, calls2) = measure(&two);
    println!(
        "{} bytes: peak {peak1} bytes, {calls1} allocations; {} bytes: peak {peak2} bytes, {calls2} allocations",
        one.len(),
        two.len()
    );
    assert!(
        peak1 < 16 * one.len(),
        "peak {peak1} for {} bytes",
        one.len()
    );
    let ratio = peak2 as f64 / peak1 as f64;
    assert!(
        (1.5..2.6).contains(&ratio),
        "twice the file: {ratio:.2}x the memory"
    );
    let calls = calls2 as f64 / calls1 as f64;
    assert!(
        (1.5..2.6).contains(&calls),
        "twice the file: {calls:.2}x the allocations"
    );
}
