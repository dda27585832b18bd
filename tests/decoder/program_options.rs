//! Every numeric option of the programs is checked by their argument
//! parser: a hostile value (NaN, infinities, negatives, 1e-300, 1e300,
//! `u64::MAX`, `u64::MAX / 1000 + 1`, empty, garbage) is a usage error,
//! exit 2, with a message naming the option; never a panic (exit 101) and
//! never a value that wraps later.
//!
//! - `canopen-replay` and `canopen-decode`: each value is checked against
//!   the option's rule written here (the documented ranges:
//!   docs/REPLAY.md "Options", docs/DECODER.md), by a property test over
//!   generated values and by the named hostile values. A value the rule
//!   accepts must pass the parser: the run then stops at the missing
//!   trace file, which is what it says.
//! - The examples' programs (`charger`, `battery_module`,
//!   `charge_session`, `sdo_node`): the named hostile values exit 2, never
//!   101.

use crate::common;

use std::process::Command;

use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence};

/// What an option accepts.
#[derive(Clone, Copy, Debug)]
enum Rule {
    /// `canopen-decode`'s node ids: 1 to 127, decimal.
    Node,
    /// `canopen-replay --play`: comma-separated node ids 1 to 127, decimal
    /// or `0x` hex.
    Nodes,
    /// `--speed`: 0, or 0.001 to 1000.
    Speed,
    /// `--period-tolerance`: 0 to 1000 percent.
    Percent,
    /// The `*-ms` options: 0 to 2^32 - 1.
    Ms,
    /// `--tolerance`: any u64.
    U64,
}

fn finite(v: &str) -> Option<f64> {
    v.trim().parse::<f64>().ok().filter(|x| x.is_finite())
}

fn replay_node(v: &str) -> bool {
    let t = v.trim();
    let n = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(h) => u8::from_str_radix(h, 16).ok(),
        None => t.parse::<u8>().ok(),
    };
    n.is_some_and(|n| (1..=127).contains(&n))
}

impl Rule {
    fn accepts(self, v: &str) -> bool {
        match self {
            Rule::Node => v.parse::<u8>().is_ok_and(|n| (1..=127).contains(&n)),
            Rule::Nodes => v.split(',').all(replay_node),
            Rule::Speed => finite(v).is_some_and(|s| s == 0.0 || (0.001..=1000.0).contains(&s)),
            Rule::Percent => finite(v).is_some_and(|p| (0.0..=1000.0).contains(&p)),
            Rule::Ms => v.parse::<u64>().is_ok_and(|ms| ms <= u64::from(u32::MAX)),
            Rule::U64 => v.parse::<u64>().is_ok(),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Program {
    Replay,
    Decode,
}

/// An option: its program, its name, its rule and how a value is written
/// into the argument (`{}` is the value).
#[derive(Clone, Copy, Debug)]
struct Opt {
    program: Program,
    name: &'static str,
    rule: Rule,
    form: &'static str,
}

const fn opt(program: Program, name: &'static str, rule: Rule) -> Opt {
    Opt {
        program,
        name,
        rule,
        form: "{}",
    }
}

const OPTIONS: [Opt; 12] = [
    opt(Program::Replay, "--play", Rule::Nodes),
    opt(Program::Replay, "--speed", Rule::Speed),
    opt(Program::Replay, "--tolerance", Rule::U64),
    opt(Program::Replay, "--period-tolerance", Rule::Percent),
    opt(Program::Replay, "--time-tolerance-ms", Rule::Ms),
    opt(Program::Replay, "--sdo-timeout-ms", Rule::Ms),
    opt(Program::Replay, "--tail-limit-ms", Rule::Ms),
    opt(Program::Decode, "--charger-node", Rule::Node),
    opt(Program::Decode, "--battery-node", Rule::Node),
    // The node of `--sdo NODE=RXID,TXID` and `--eds NODE=FILE`.
    Opt {
        form: "{}=601,581",
        ..opt(Program::Decode, "--sdo", Rule::Node)
    },
    Opt {
        form: "{}=node.eds",
        ..opt(Program::Decode, "--eds", Rule::Node)
    },
    // The COB-IDs of `--sdo`: hex, 11 or 29 bits.
    Opt {
        form: "5=601,{}",
        ..opt(Program::Decode, "--sdo", Rule::Node)
    },
];

/// The named hostile values (and a few good ones beside them).
const HOSTILE: [&str; 24] = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "infinity",
    "-1",
    "-0.5",
    "1e-300",
    "1e300",
    "18446744073709551615", // u64::MAX
    "18446744073709552",    // u64::MAX / 1000 + 1
    "18446744073709551616", // u64::MAX + 1
    "4294967296",           // 2^32
    "",
    "garbage",
    "0x",
    "1.5",
    "--json",
    " 5",
    "0",
    "1",
    "127",
    "128",
    "0x7F",
];

/// A trace that does not exist: a run whose options all pass stops there.
fn missing_trace() -> String {
    let p = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such-trace.log");
    let _ = std::fs::remove_file(&p);
    p.display().to_string()
}

/// Runs the option's program with `value` (as `--opt=value` when
/// `joined`, else as two arguments): exit status and stderr.
fn run(o: &Opt, value: &str, joined: bool) -> (Option<i32>, String) {
    let trace = missing_trace();
    let value = o.form.replace("{}", value);
    let mut args: Vec<String> = Vec::new();
    let exe = match o.program {
        Program::Replay => {
            args.push(trace);
            if o.name != "--play" {
                args.extend(["--play".into(), "1".into()]);
            }
            env!("CARGO_BIN_EXE_canopen-replay")
        }
        Program::Decode => env!("CARGO_BIN_EXE_canopen-decode"),
    };
    if joined {
        args.push(format!("{}={value}", o.name));
    } else {
        args.extend([o.name.to_string(), value]);
    }
    if o.program == Program::Decode {
        args.push(missing_trace());
    }
    let out = Command::new(exe).args(&args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A COB-ID of `--sdo`: hex, 11 or 29 bits.
fn cob_id(v: &str) -> bool {
    let digits = v.trim_start_matches("0x").trim_start_matches("0X");
    u32::from_str_radix(digits, 16).is_ok_and(|id| id < 1 << 29)
}

/// The rule's verdict on `value` for `o`: for `--sdo NODE=RXID,TXID` and
/// `--eds NODE=FILE` on the whole argument (the node is what comes before
/// its first `=`).
fn accepted(o: &Opt, value: &str) -> bool {
    let full = o.form.replace("{}", value);
    match o.name {
        "--eds" => full
            .split_once('=')
            .is_some_and(|(node, _)| Rule::Node.accepts(node)),
        "--sdo" => full.split_once('=').is_some_and(|(node, ids)| {
            Rule::Node.accepts(node)
                && ids
                    .split_once(',')
                    .is_some_and(|(rx, tx)| cob_id(rx) && cob_id(tx))
        }),
        _ => o.rule.accepts(value),
    }
}

/// The property: a refused value exits 2 naming the option; an accepted
/// one passes the parser (the run stops at the missing trace, exit 2).
fn check(o: &Opt, value: &str, joined: bool) -> Result<(), String> {
    let (code, err) = run(o, value, joined);
    let say = |what: &str| format!("{} {value:?} (joined: {joined}): {what}: {err}", o.name);
    if err.contains("panicked") || code == Some(101) {
        return Err(say("panicked"));
    }
    if code != Some(2) {
        return Err(say(&format!("exit {code:?}, not 2")));
    }
    if accepted(o, value) {
        if !err.contains("no-such-trace.log") || err.contains("invalid value") {
            return Err(say("accepted by the rule, refused by the program"));
        }
    } else if !err.contains(&format!("'{}", o.name)) || !err.contains("invalid value") {
        return Err(say("refused without naming the option"));
    }
    Ok(())
}

#[test]
fn every_named_hostile_value_is_refused_by_its_option() {
    let mut failures = Vec::new();
    for o in &OPTIONS {
        for v in HOSTILE {
            // In two arguments a value that begins with `-` still goes to
            // the option (the parsers allow hyphen values).
            for joined in [true, false] {
                if let Err(e) = check(o, v, joined) {
                    failures.push(e);
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Values around and far beyond each rule's edges, and any text.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(HOSTILE.to_vec()).prop_map(String::from),
        any::<f64>().prop_map(|f| f.to_string()),
        any::<f64>().prop_map(|f| format!("{f:e}")),
        (-2000.0f64..2000.0).prop_map(|f| f.to_string()),
        (0.0f64..0.002).prop_map(|f| f.to_string()),
        any::<i128>().prop_map(|i| i.to_string()),
        (4_294_967_290u64..4_294_967_300).prop_map(|i| i.to_string()),
        (0u16..300).prop_map(|i| i.to_string()),
        (0u8..=255).prop_map(|i| format!("0x{i:X}")),
        "[0-9a-fx.,eE+-]{0,12}",
        "[ -~]{0,16}",
    ]
}

proptest! {
    #![proptest_config(Config {
        cases: 32,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "tests/proptest-regressions/program_options.txt",
        ))),
        ..Config::default()
    })]

    /// Any value of any numeric option: exit 2 naming the option when its
    /// rule refuses it, through the parser when the rule accepts it; never
    /// a panic.
    #[test]
    fn any_value_of_any_numeric_option_is_judged_by_its_rule(
        o in prop::sample::select(OPTIONS.to_vec()),
        v in value(),
        joined in any::<bool>(),
    ) {
        // `--` alone ends the options (it is no value); `-NAME` in two
        // arguments is taken as a value of the option, so it is judged
        // like any other.
        prop_assume!(joined || o.form.replace("{}", &v) != "--");
        if let Err(e) = check(&o, &v, joined) {
            return Err(TestCaseError::fail(e));
        }
    }
}

/// An example program with `args` and no input: exit status and stderr.
fn example(name: &str, args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(common::example(name))
        .args(args)
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The examples' numeric options, each with values it must refuse: exit
/// 2 with a message naming the option, never a panic.
#[test]
fn the_examples_refuse_hostile_numbers() {
    let numbers = [
        "nan",
        "inf",
        "-1",
        "1e-300",
        "1e300",
        "18446744073709551616",
        "",
        "x",
    ];
    let ms = [
        "65536",
        "18446744073709551615",
        "18446744073709552",
        "nan",
        "-1",
        "",
        "1.5",
    ];
    let cases: Vec<(&str, &str, Vec<&str>)> = vec![
        ("charger", "--node-id", vec!["0", "128", "-1", "nan", ""]),
        (
            "charger",
            "--battery-node",
            vec!["0", "128", "-1", "nan", ""],
        ),
        ("charger", "--heartbeat-ms", ms.to_vec()),
        ("charger", "--battery-timeout-ms", ms.to_vec()),
        ("charger", "--linger-ms", ms.to_vec()),
        (
            "charger",
            "--tpdo-ms",
            vec!["1,2,3", "1,2,3,nan", "-1,0,0,0", "65536,0,0,0", ""],
        ),
        (
            "charger",
            "--current",
            numbers
                .iter()
                .filter(|v| **v != "1e-300")
                .copied()
                .collect(),
        ),
        (
            "charger",
            "--voltage",
            vec!["nan", "inf", "-1", "1e300", "300", ""],
        ),
        (
            "charger",
            "--pack-cells",
            vec!["0", "-1", "65536", "nan", ""],
        ),
        (
            "charger",
            "--pack-ah",
            vec!["0", "-1", "nan", "inf", "1e300", ""],
        ),
        (
            "charger",
            "--pack-soc",
            vec!["-1", "101", "nan", "inf", "1e300", ""],
        ),
        ("charger", "--algorithm", vec!["-1", "65536", "nan", ""]),
        (
            "charger",
            "--speed",
            vec!["0", "-1", "nan", "inf", "1e-300", "0.0009", "1e300", ""],
        ),
        (
            "battery_module",
            "--node-id",
            vec!["0", "128", "-1", "nan", ""],
        ),
        (
            "battery_module",
            "--capacity-ah",
            vec!["-1", "65536", "nan", "1.5", ""],
        ),
        (
            "battery_module",
            "--max-current-a",
            vec!["-1", "65536", "nan", ""],
        ),
        ("battery_module", "--cells", vec!["-1", "65536", "nan", ""]),
        (
            "battery_module",
            "--voltage",
            numbers
                .iter()
                .filter(|v| **v != "1e-300")
                .copied()
                .collect(),
        ),
        (
            "battery_module",
            "--temperature",
            vec!["nan", "inf", "-inf", "1e300", "5000", ""],
        ),
        (
            "battery_module",
            "--soc",
            vec!["-1", "101", "nan", "1e300", ""],
        ),
        (
            "battery_module",
            "--battery-status",
            vec!["1FF", "-1", "nan", ""],
        ),
        ("battery_module", "--heartbeat-ms", ms.to_vec()),
        (
            "battery_module",
            "--linger-ms",
            vec!["-1", "nan", "1e300", "18446744073709551616", ""],
        ),
        (
            "battery_module",
            "--speed",
            vec!["0", "-1", "nan", "inf", "1e-300", "0.0009", "1e300", ""],
        ),
        (
            "battery_module",
            "--identity",
            vec!["1,2,3", "1,2,3,x", "1,2,3,100000000"],
        ),
        (
            "battery_module",
            "--device-type",
            vec!["nan", "-1", "100000000", ""],
        ),
        (
            "charge_session",
            "--soc",
            vec!["-1", "101", "nan", "inf", "1e300", ""],
        ),
        (
            "charge_session",
            "--ah",
            vec!["0", "-1", "nan", "inf", "1e-300", "1e300", ""],
        ),
    ];
    let mut failures = Vec::new();
    for (program, option, values) in &cases {
        for v in values {
            let (code, err) = example(program, &[option, v]);
            if code != Some(2) || err.contains("panicked") || !err.contains(option) {
                failures.push(format!("{program} {option} {v:?}: exit {code:?}: {err}"));
            }
        }
    }
    // sdo_node: --node-id must be a node id, --timeout-ms 1 to 2^32-1 ms.
    for v in ["0", "128", "-1", "nan", ""] {
        let (code, err) = example("sdo_node", &["--client", "--node-id", v, "read:1000:00"]);
        if code != Some(2) || err.contains("panicked") || !err.contains("--node-id") {
            failures.push(format!("sdo_node --node-id {v:?}: exit {code:?}: {err}"));
        }
    }
    for v in [
        "0",
        "-1",
        "nan",
        "1e3",
        "",
        "4294967296",
        "18446744073709551615",
    ] {
        let args = [
            "--client",
            "--node-id",
            "2",
            "--timeout-ms",
            v,
            "read:1000:00",
        ];
        let (code, err) = example("sdo_node", &args);
        if code != Some(2) || err.contains("panicked") || !err.contains("--timeout-ms") {
            failures.push(format!("sdo_node --timeout-ms {v:?}: exit {code:?}: {err}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
