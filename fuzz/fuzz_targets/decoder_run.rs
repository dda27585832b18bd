//! The `canopen-decode` program's whole pipeline (`pipeline::run`, what
//! `main` calls) under arbitrary bytes, in every output and with every
//! trace format forced or detected. Invariants: no panic, no I/O error
//! into a sink, and every JSON output line is valid JSON (the frame objects
//! are written by hand). The first byte picks the options.
#![no_main]
// The program's modules are built here for their pipeline: what the target
// does not call, and their unit tests' imports, are unused.
#![allow(dead_code, unused_imports)]

#[path = "../../src/bin/canopen-decode/args.rs"]
mod args;
#[path = "../../src/bin/canopen-decode/calendar.rs"]
mod calendar;
#[path = "../../src/bin/canopen-decode/comm_objects.rs"]
mod comm_objects;
#[path = "../../src/bin/canopen-decode/csv.rs"]
mod csv;
#[path = "../../src/bin/canopen-decode/dbc.rs"]
mod dbc;
#[path = "../../src/bin/canopen-decode/decoding.rs"]
mod decoding;
#[path = "../../src/bin/canopen-decode/json.rs"]
mod json;
#[path = "../../src/bin/canopen-decode/line_cache.rs"]
mod line_cache;
#[path = "../../src/bin/canopen-decode/pdo_args.rs"]
mod pdo_args;
#[path = "../../src/bin/canopen-decode/pdo_learn.rs"]
mod pdo_learn;
#[path = "../../src/bin/common/pdo_syntax.rs"]
mod pdo_syntax;
#[path = "../../src/bin/canopen-decode/pipeline.rs"]
mod pipeline;
#[path = "../../src/bin/canopen-decode/report/mod.rs"]
mod report;
#[path = "../../src/bin/canopen-decode/sdo.rs"]
mod sdo;
#[path = "../../src/bin/canopen-decode/sdo_value.rs"]
mod sdo_value;
#[path = "../../src/bin/canopen-decode/signals.rs"]
mod signals;
#[path = "../../src/bin/canopen-decode/summary.rs"]
mod summary;
#[path = "../../src/bin/canopen-decode/time_column.rs"]
mod time_column;
#[path = "../../src/bin/canopen-decode/words.rs"]
mod words;
#[path = "../../src/bin/common/trace_input/mod.rs"]
mod trace_input;
pub use pipeline::*;

use std::sync::OnceLock;

use clap::Parser;
use libfuzzer_sys::fuzz_target;

/// The option sets, as command lines (after the program name).
const SETS: [&[&str]; 10] = [
    &[],
    &["--json", "--summary"],
    &["--output", "csv", "--strict"],
    &["--charger-node", "10", "--battery-node", "1", "--summary"],
    &[
        "--charger-node",
        "10",
        "--battery-node",
        "1",
        "--json",
        "--no-cache",
    ],
    &[
        "--format",
        "candump-screen",
        "--summary-only",
        "--check",
        "--json",
    ],
    &["--format", "candump-screen-delta", "--json"],
    &["--format", "trc", "--json", "--sdo", "65=241,1C1"],
    &[
        "--format",
        "asc",
        "--json",
        "--pdo",
        "18A=2002:0:16,2101:0:16,6:0:16",
    ],
    &["--format", "csv", "--json", "--pdo-capture-mapping"],
];

fn options() -> &'static [Options] {
    static OPTIONS: OnceLock<Vec<Options>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        SETS.iter()
            .map(|set| {
                let argv = std::iter::once(&"canopen-decode").chain(set.iter());
                args::Cli::parse_from(argv)
                    .options()
                    .expect("the fuzz target's options are valid")
            })
            .collect()
    })
}

fuzz_target!(|data: &[u8]| {
    let Some((&pick, input)) = data.split_first() else {
        return;
    };
    let all = options();
    let Some(opts) = all.get(usize::from(pick) % all.len()) else {
        return;
    };
    let mut out = Vec::new();
    run(input, &mut out, &mut std::io::sink(), opts).expect("a sink never fails");
    if opts.json {
        let text = String::from_utf8(out).expect("the output is UTF-8");
        for line in text.lines() {
            if let Err(e) = serde_json::from_str::<serde_json::Value>(line) {
                panic!("not JSON ({e}): {line}");
            }
        }
    }
});
