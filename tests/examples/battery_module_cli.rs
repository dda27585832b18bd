//! The `battery_module` example run as a program: candump scripts with
//! explicit timestamps in, the exact frames (and their times, in the input's
//! time base) out.

use crate::common;

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn run(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(common::example("battery_module"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = child.stdin.take().unwrap();
    pipe.write_all(stdin.as_bytes()).unwrap();
    drop(pipe);
    child.wait_with_output().unwrap()
}

/// stdout lines; the first (the boot-up, stamped with the system clock
/// before any input) is checked and returned without its timestamp.
fn lines(o: &Output) -> (String, Vec<String>) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout.clone()).unwrap();
    let mut it = out.lines().map(str::to_string);
    let boot = it.next().expect("no boot-up line");
    let frame = boot.rsplit(' ').next().unwrap().to_string();
    (frame, it.collect())
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// NMT start, an SDO upload of 1000h, then a foreign frame that only moves
/// the clock: TPDO 0 at the start and every 200 ms, the heartbeat one
/// period after the first timestamped line, all in the input's time base.
/// (Lines are >= 100 ms apart: a line handled later than its time on the
/// live clock would be handled at the clock's time instead.)
const SCRIPT: &str = "\
(100.000000) can0 000#0101
(100.500000) can0 601#4000100000000000
(101.250000) can0 70A#05
";

#[test]
fn nmt_start_sdo_upload_and_timers_in_the_input_time_base() {
    let o = run(&["--node-id", "1", "--linger-ms", "0"], SCRIPT);
    let (boot, rest) = lines(&o);
    assert_eq!(boot, "701#00");
    let tpdo = "181#C80001"; // 6010h 25.0 degC (C8 00), 6000h ready to charge
    let want = [
        format!("(100.000000) can0 {tpdo}"),
        format!("(100.200000) can0 {tpdo}"),
        format!("(100.400000) can0 {tpdo}"),
        "(100.500000) can0 581#43001000A2010000".to_string(),
        format!("(100.600000) can0 {tpdo}"),
        format!("(100.800000) can0 {tpdo}"),
        "(101.000000) can0 701#05".to_string(),
        format!("(101.000000) can0 {tpdo}"),
        format!("(101.200000) can0 {tpdo}"),
    ];
    assert_eq!(rest, want, "stderr: {}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("event: NMT boot-up -> pre-operational"),
        "{err}"
    );
    assert!(
        err.contains("event: NMT pre-operational -> operational"),
        "{err}"
    );
}

#[test]
fn options_set_the_objects_and_the_optional_pdos() {
    let script = "\
(5.000000) can0 601#4030600100000000
(5.500000) can0 601#4020600100000000
(6.000000) can0 000#0101
(6.100000) can0 70A#05
";
    let o = run(
        &[
            "--node-id",
            "1",
            "--linger-ms",
            "0",
            "--serial",
            "ABCD12",
            "--battery-type",
            "li-ion",
            "--voltage",
            "51.5",
            "--temperature",
            "-10.5",
            "--device-type",
            "40000",
            "--heartbeat-ms",
            "0",
        ],
        script,
    );
    let (boot, rest) = lines(&o);
    assert_eq!(boot, "701#00");
    // 51.5 V = 52736 / 1024 V = 0000CE00h; -10.5 degC = -84 = FFACh.
    assert_eq!(
        rest,
        [
            "(5.000000) can0 581#4330600141424344",
            "(5.500000) can0 581#4F206001A0000000",
            "(6.000000) can0 181#ACFF01",
            "(6.000000) can0 281#ACFF0100CE0000",
        ],
        "stderr: {}",
        stderr(&o)
    );
}

#[test]
fn tpdos_stay_not_valid_without_enable_and_heartbeat_period_is_an_option() {
    let script = "\
(0.000000) can0 000#0101
(1.000000) can0 70A#05
";
    let o = run(
        &[
            "--no-enable-tpdos",
            "--heartbeat-ms",
            "300",
            "--linger-ms",
            "0",
        ],
        script,
    );
    let (boot, rest) = lines(&o);
    assert_eq!(boot, "701#00");
    assert_eq!(
        rest,
        [
            "(0.300000) can0 701#05",
            "(0.600000) can0 701#05",
            "(0.900000) can0 701#05",
        ]
    );
}

#[test]
fn help_and_bad_options() {
    let o = run(&["--help"], "");
    assert!(o.status.success());
    let help = String::from_utf8(o.stdout).unwrap();
    for opt in [
        "--node-id",
        "--serial",
        "--battery-type",
        "--capacity-ah",
        "--cells",
        "--voltage",
        "--temperature",
        "--soc",
        "--device-type",
        "--heartbeat-ms",
        "--no-enable-tpdos",
        "--simulate",
        "--linger-ms",
    ] {
        assert!(help.contains(opt), "{opt} missing from --help");
    }
    for bad in [
        &["--node-id", "0"][..],
        &["--battery-type", "lava"],
        &["--device-type", "191"],
        &["--serial", "ELEVENCHARS"],
        &["--frobnicate"],
    ] {
        let o = run(bad, "");
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
    }
}
