//! The `sdo` bench's 1000-byte upload and download, run a given number of
//! times without a timer: a harness for callgrind, whose instruction
//! counts are stable on a loaded machine where wall-clock figures are not.
//!
//! ```text
//! cargo bench --bench sdo_count --no-run
//! valgrind --tool=callgrind --toggle-collect='sdo_count::sdo_pair::upload' \
//!     target/release/deps/sdo_count-HASH upload 200
//! ```
//!
//! Instructions per segment = collected / (transfers x 143).
//! Without arguments (as `cargo bench` runs it) it does one transfer each way.

mod common;
use common::sdo_pair;

use sdo_pair::{download, pair, upload, SEGMENTS};

fn main() {
    let mut args = std::env::args().skip(1).filter(|a| !a.starts_with("--"));
    let which = args.next().unwrap_or_default();
    let n: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut p = pair();
    for _ in 0..n {
        match which.as_str() {
            "upload" => upload(&mut p),
            "download" => download(&mut p),
            _ => {
                upload(&mut p);
                download(&mut p);
            }
        }
    }
    println!("{which}: {n} transfers x {SEGMENTS} segments");
}
