//! The `canopen-decode` program's whole pipeline (`canopen_codec::log::run`,
//! what `main` calls) under arbitrary bytes, in every output and with every
//! trace format forced or detected. Invariants: no panic, no I/O error
//! into a sink, and every JSON output line is valid JSON (the frame objects
//! are written by hand). The first byte picks the options.
#![no_main]

use std::sync::OnceLock;

use canopen_codec::log::input::Zlib;
use canopen_codec::log::{run, Options, Roles};
use canopen_codec::sdo::SdoChannel;
use canopen_codec::trace::Format;
use canopen_codec::{CanId, NodeId};
use libfuzzer_sys::fuzz_target;

/// The option sets, each as the program's options (in a comment) would
/// make it.
fn options() -> &'static [Options] {
    static OPTIONS: OnceLock<Vec<Options>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let base = || Options {
            // flate2's inflater, as the programs pass it (BLF zlib containers).
            inflater: Some(|| Box::<Zlib>::default()),
            ..Options::default()
        };
        let roles = Roles {
            charger: NodeId::new(10),
            battery: NodeId::new(1),
            deltaq: NodeId::new(10),
        };
        let format = |f| Options {
            format: Some(f),
            json: true,
            ..base()
        };
        let mut sets = vec![
            // (none)
            base(),
            // --json --summary
            Options {
                json: true,
                summary: true,
                ..base()
            },
            // --output csv --strict
            Options {
                csv: true,
                strict: true,
                ..base()
            },
            // --charger-node 10 --battery-node 1 --summary
            Options {
                roles,
                summary: true,
                ..base()
            },
            // --charger-node 10 --battery-node 1 --json --no-cache
            Options {
                roles,
                json: true,
                no_cache: true,
                ..base()
            },
            // --format candump-screen --summary-only --check --json
            Options {
                summary: true,
                frames: false,
                check: true,
                ..format(Format::CandumpScreen)
            },
            // --format candump-screen-delta --json
            Options {
                delta_times: true,
                ..format(Format::CandumpScreen)
            },
            // --format trc --json --sdo 65=241,1C1
            Options {
                sdo_channels: NodeId::new(65)
                    .zip(CanId::standard(0x241))
                    .zip(CanId::standard(0x1C1))
                    .map(|((node, request), response)| SdoChannel {
                        node,
                        request,
                        response,
                    })
                    .into_iter()
                    .collect(),
                ..format(Format::PcanTrc)
            },
            // --format asc --json --pdo 18A=2002:0:16,2101:0:16,6:0:16
            format(Format::VectorAsc),
            // --format csv --json --pdo-capture-mapping
            Options {
                roles,
                ..format(Format::PythonCanCsv)
            },
        ];
        if let Some(asc) = sets.get_mut(8) {
            asc.pdos
                .add("18A=2002:0:16,2101:0:16,6:0:16")
                .expect("a valid mapping");
        }
        if let Some(capture) = sets.last_mut() {
            capture.pdos.add_capture().expect("the capture's mapping");
        }
        sets
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
