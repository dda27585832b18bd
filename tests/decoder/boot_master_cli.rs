//! `canopen-boot --node N=FILE.dcf` as the NMT master on its candump-line
//! pipe: a node played by the test answers as its DCF says and is
//! configured, started and then lost (its JSON lines on stderr); an absent
//! node ends in error status B after the retries.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

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
    let path = std::env::temp_dir().join(format!("canopen-boot-{test}-{}.dcf", std::process::id()));
    std::fs::write(&path, DCF).unwrap();
    path
}

/// The frame of a candump log line, as `ID#DATA`.
fn frame_of(line: &str) -> &str {
    line.rsplit(' ').next().unwrap_or_default()
}

/// Runs the manager of node 5 with `answer` playing the bus: it gets each
/// frame the manager sends and returns the frames to send back; the
/// manager's stdin closes at `until`. Returns the exit status, the frames
/// the manager sent and its stderr lines.
fn run(
    test: &str,
    until: Duration,
    mut answer: impl FnMut(&str) -> Vec<String>,
) -> (i32, Vec<String>, Vec<String>) {
    let dcf = dcf_file(test);
    let node = format!("5={}", dcf.display());
    let mut child = Command::new(env!("CARGO_BIN_EXE_canopen-boot"))
        .args(["--node", &node, "--sdo-timeout-ms", "50"])
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
    let (code, sent, err) = run("lost", Duration::from_millis(1500), |frame| {
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
    let (code, sent, err) = run("absent", Duration::from_millis(1400), |_| vec![]);
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
