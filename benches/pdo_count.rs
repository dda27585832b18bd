//! The `pdo` bench's Delta-Q TPDO 3 typed unpack, run a given number of
//! times without a timer: a harness for callgrind.
//!
//! ```text
//! cargo bench --bench pdo_count --no-run
//! valgrind --tool=callgrind --toggle-collect='pdo_count::decode_tpdo3' \
//!     target/release/deps/pdo_count-HASH 100000
//! ```
//!
//! Instructions per PDO = collected / runs. Without arguments (as `cargo
//! bench` runs it) it decodes once.

use std::hint::black_box;

use canopen_codec::pdo::PdoMapping;

mod common;
use common::tpdo3;

/// The `pdo` bench's decode, out of line so callgrind can count it alone.
#[inline(never)]
fn decode_tpdo3(m: &PdoMapping, payload: &[u8]) -> Option<tpdo3::Values> {
    tpdo3::decode(m, payload)
}

fn main() {
    let n: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(1);
    let m = tpdo3::mapping();
    let frame = tpdo3::FRAME;
    let mut some = 0u64;
    for _ in 0..n {
        some += u64::from(black_box(decode_tpdo3(black_box(&m), black_box(&frame))).is_some());
    }
    println!("{n} decodes, {some} with values");
}
