//! `canopen-boot --node N=FILE.dcf` as the NMT master on its candump-line
//! pipe: a node played by the test answers as its DCF says and is
//! configured, started and then lost (its JSON lines on stderr); an absent
//! node ends in error status B after the retries; the options beyond the
//! DCF: keep alive (L), the software checks (1F55h, 1F53h, 1F54h: H), the
//! SDO retries, the retry interval and the boot time (1F89h).

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::Stdio;
use std::time::{Duration, Instant};

use crate::decoder_support::{canopen_boot, scratch};

/// Node 5's DCF: device type 0x00010191, vendor-ID 0x2A, heartbeat 100 ms.
const DCF: &str = "\
[DeviceComissioning]
NodeID=5

[1000]
ParameterName=Device type
DataType=0x0007
AccessType=ro
DefaultValue=0x00010191

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
DefaultValue=0
ParameterValue=100

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=2

[1018sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=1

[1018sub1]
ParameterName=Vendor-ID
DataType=0x0007
AccessType=ro
DefaultValue=0x2A
";

fn dcf_file(test: &str) -> PathBuf {
    let path = scratch(test).join("node5.dcf");
    std::fs::write(&path, DCF).unwrap();
    path
}

/// The frame of a candump log line, as `ID#DATA`.
fn frame_of(line: &str) -> &str {
    line.rsplit(' ').next().unwrap_or_default()
}

/// Runs the manager of node 5 (SDO timeout 50 ms, then `options`) with
/// `answer` playing the bus: it gets each frame the manager sends and
/// returns the frames to send back; the manager's stdin closes at `until`.
/// Returns the exit status, the frames the manager sent and its stderr
/// lines.
fn run(
    test: &str,
    options: &[&str],
    until: Duration,
    mut answer: impl FnMut(&str) -> Vec<String>,
) -> (i32, Vec<String>, Vec<String>) {
    let dcf = dcf_file(test);
    let node = format!("5={}", dcf.display());
    let mut args = vec!["--node", &node, "--sdo-timeout-ms", "50"];
    args.extend_from_slice(options);
    let mut child = canopen_boot(&args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = child.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines() {
            let Ok(line) = line else { break };
            if tx.send(frame_of(&line).to_string()).is_err() {
                break;
            }
        }
    });
    let mut stdin = child.stdin.take().unwrap();
    let start = Instant::now();
    let mut sent = Vec::new();
    while let Some(left) = until.checked_sub(start.elapsed()) {
        let Ok(frame) = rx.recv_timeout(left) else {
            break;
        };
        for reply in answer(&frame) {
            writeln!(stdin, "(0.000000) can0 {reply}").unwrap();
        }
        sent.push(frame);
    }
    drop(stdin);
    let o = child.wait_with_output().unwrap();
    let _ = std::fs::remove_file(dcf);
    let err = String::from_utf8(o.stderr).unwrap();
    (
        o.status.code().unwrap(),
        sent,
        err.lines().map(String::from).collect(),
    )
}

#[test]
fn a_node_is_configured_started_and_then_lost() {
    let (code, sent, err) = run("lost", &[], Duration::from_millis(1500), |frame| {
        let reply = match frame {
            "000#8205" => "705#00",
            "605#4000100000000000" => "585#4300100091010100",
            "605#4018100100000000" => "585#431810012A000000",
            // 1017h = 100 ms: acknowledged, then one heartbeat and silence.
            "605#2B17100064000000" => "585#6017100000000000\n(0.000000) can0 705#7F",
            _ => return vec![],
        };
        vec![reply.to_string()]
    });
    assert_eq!(
        sent,
        [
            "000#8205",
            "605#4000100000000000",
            "605#4018100100000000",
            "605#2B17100064000000",
            "000#0105"
        ]
    );
    assert_eq!(
        err,
        [
            r#"{"node": 5, "result": "operational"}"#,
            r#"{"node": 5, "event": "heartbeat", "code": "E"}"#
        ]
    );
    assert_eq!(code, 0);
}

#[test]
fn an_absent_node_is_b() {
    let (code, sent, err) = run("absent", &[], Duration::from_millis(1400), |_| vec![]);
    // The reset, then three reads of 1000h (after the 1 s boot-up wait),
    // each ended by an abort 05040000h.
    let read = "605#4000100000000000";
    let timeout = "605#8000100000000405";
    assert_eq!(
        sent,
        ["000#8205", read, timeout, read, timeout, read, timeout]
    );
    assert_eq!(err.len(), 2, "{err:?}");
    assert_eq!(err[1], "canopen-boot: a node's boot ended in an error");
    assert!(
        err[0].starts_with(r#"{"node": 5, "result": "error", "code": "B", "reason": "#),
        "{}",
        err[0]
    );
    assert_eq!(code, 1);
}

/// The read of 1000h and of 1018h sub 1, and their answers.
const READ_1000: &str = "605#4000100000000000";
const READ_1018: &str = "605#4018100100000000";
const ANSWER_1000: &str = "585#4300100091010100";
const ANSWER_1018: &str = "585#431810012A000000";

#[test]
fn the_help_names_every_option_with_its_object() {
    let o = canopen_boot(&["--help"]).output().unwrap();
    let help = String::from_utf8(o.stdout).unwrap();
    for (option, object) in [
        ("--keep-alive", "1F81h bit 4"),
        ("--software-id", "1F55h"),
        ("--software-date", "1F53h"),
        ("--software-time", "1F54h"),
        ("--boot-time-ms", "1F89h"),
        ("--retry-interval-ms", "error B"),
        ("--sdo-retries", "before B"),
    ] {
        let line = help.find(option).map(|at| &help[at..]);
        let text = line.unwrap_or_else(|| panic!("{option} missing: {help}"));
        let described = text.split("\n  -").next().unwrap_or_default();
        assert!(described.contains(object), "{option}: {described}");
    }
}

#[test]
fn a_keep_alive_node_running_already_is_l_and_is_not_reset() {
    let (code, sent, err) = run(
        "keep-alive",
        &["--keep-alive", "5"],
        Duration::from_millis(600),
        |frame| match frame {
            READ_1000 => vec![ANSWER_1000.into()],
            // Its identity, then its heartbeat: operational (05h).
            READ_1018 => vec![ANSWER_1018.into(), "705#05".into()],
            _ => vec![],
        },
    );
    // Neither reset nor configured nor started: it runs already.
    assert_eq!(sent, [READ_1000, READ_1018]);
    assert_eq!(
        err,
        [
            r#"{"node": 5, "event": "initially operational", "code": "L"}"#,
            r#"{"node": 5, "result": "operational"}"#,
            r#"{"node": 5, "event": "heartbeat", "code": "E"}"#
        ]
    );
    assert_eq!(code, 0);
}

#[test]
fn the_software_options_check_1f56h_then_1f52h_and_refuse_with_h() {
    // 1F56h:01 = 0x1234 and 1F52h:01 = 15340 match; 1F52h:02 is one ms
    // later than 1F54h.
    let options = [
        "--software-id",
        "5=0x1234",
        "--software-date",
        "5=15340",
        "--software-time",
        "5=43200000",
    ];
    let (code, sent, err) = run("software", &options, Duration::from_millis(600), |frame| {
        let reply = match frame {
            "000#8205" => "705#00",
            READ_1000 => ANSWER_1000,
            READ_1018 => ANSWER_1018,
            "605#40561F0100000000" => "585#43561F0134120000",
            "605#40521F0100000000" => "585#43521F01EC3B0000",
            "605#40521F0200000000" => "585#43521F02012E9302",
            _ => return vec![],
        };
        vec![reply.to_string()]
    });
    assert_eq!(
        sent,
        [
            "000#8205",
            READ_1000,
            READ_1018,
            "605#40561F0100000000",
            "605#40521F0100000000",
            "605#40521F0200000000"
        ]
    );
    assert!(
        err[0].starts_with(r#"{"node": 5, "result": "error", "code": "H", "reason": "#)
            && err[0].contains("1F52h:02 differs from 1F54h"),
        "{err:?}"
    );
    assert_eq!(code, 1);
}

#[test]
fn sdo_retries_retry_interval_and_boot_time_shape_an_absent_mandatory_node() {
    let options = [
        "--mandatory",
        "5",
        "--sdo-retries",
        "0",
        "--retry-interval-ms",
        "300",
        "--boot-time-ms",
        "300",
    ];
    let (code, sent, err) = run("retries", &options, Duration::from_millis(1550), |_| vec![]);
    // One read per boot (no retries) at 1000 ms, its boot started again
    // 300 ms after its B (50 ms later), the next would be at 1700 ms.
    let timeout = "605#8000100000000405";
    assert_eq!(sent, ["000#8205", READ_1000, timeout, READ_1000, timeout]);
    // 1F89h passes (300 ms) before the first read (after the 1 s boot-up
    // wait).
    assert_eq!(err[0], r#"{"node": 5, "event": "boot time elapsed"}"#);
    let b = err.iter().filter(|l| l.contains(r#""code": "B""#)).count();
    assert_eq!(b, 2, "{err:?}");
    assert_eq!(code, 1);
}

#[test]
fn an_option_for_a_node_not_booted_is_a_usage_error() {
    let dcf = dcf_file("unlisted");
    let node = format!("5={}", dcf.display());
    let o = canopen_boot(&["--node", &node, "--keep-alive", "6"])
        .output()
        .unwrap();
    let err = String::from_utf8(o.stderr).unwrap();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("node 6 is not one of the --node options"),
        "{err}"
    );
}
