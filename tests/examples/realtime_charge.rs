//! The real-time programs charge: `examples/charger` and
//! `examples/battery_module --simulate` on a pipe pair (each one's stdout
//! the other's stdin, candump lines), both at `--speed 20`, as a user runs
//! them with a fifo. The charger's power stage and battery model and the
//! module's pack are the `sim` models; over a few seconds of wall time the
//! bus shows the module's request, the charger delivering it, 6052h rising
//! and the module's state of charge following.

use crate::common;

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::Duration;

/// One frame of the log: (time in the nodes' seconds, COB-ID, data).
fn frame(line: &str) -> Option<(f64, u32, Vec<u8>)> {
    let time = line.split_whitespace().next()?;
    let time = time.strip_prefix('(')?.strip_suffix(')')?.parse().ok()?;
    let text = line.split_whitespace().nth(2)?;
    let (id, data) = text.split_once('#')?;
    let id = u32::from_str_radix(id, 16).ok()?;
    let data = (0..data.len() / 2)
        .map(|i| u8::from_str_radix(&data[2 * i..2 * i + 2], 16))
        .collect::<Result<_, _>>()
        .ok()?;
    Some((time, id, data))
}

#[test]
fn charger_and_module_charge_on_a_pipe_pair() {
    let mut charger = Command::new(common::example("charger"))
        .args(["--mode", "remote", "--speed", "20", "--pack-ah", "20"])
        .args(["--pack-soc", "30", "--linger-ms", "0"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut module = Command::new(common::example("battery_module"))
        .args([
            "--simulate",
            "--nmt-start",
            "--speed",
            "20",
            "--capacity-ah",
            "20",
        ])
        .args(["--max-current-a", "25", "--soc", "30", "--linger-ms", "0"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let log = Arc::new(Mutex::new(Vec::<String>::new()));
    let mut pumps = Vec::new();
    for (from, to) in [
        (charger.stdout.take().unwrap(), module.stdin.take().unwrap()),
        (module.stdout.take().unwrap(), charger.stdin.take().unwrap()),
    ] {
        let log = Arc::clone(&log);
        pumps.push(thread::spawn(move || {
            let mut to = to;
            for line in BufReader::new(from).lines() {
                let Ok(line) = line else { break };
                log.lock().unwrap().push(line.clone());
                if writeln!(to, "{line}").and_then(|()| to.flush()).is_err() {
                    break;
                }
            }
        }));
    }
    // 10 s of wall time: 200 s of the nodes' time.
    thread::sleep(Duration::from_secs(10));
    let _ = charger.kill();
    let _ = module.kill();
    let charger_err =
        String::from_utf8_lossy(&charger.wait_with_output().unwrap().stderr).into_owned();
    let module_err =
        String::from_utf8_lossy(&module.wait_with_output().unwrap().stderr).into_owned();
    for p in pumps {
        let _ = p.join();
    }
    let log = log.lock().unwrap().clone();
    let frames: Vec<(f64, u32, Vec<u8>)> = log.iter().filter_map(|l| frame(l)).collect();
    let timed = |id: u32| -> Vec<(f64, &Vec<u8>)> {
        frames
            .iter()
            .filter(|(_, i, _)| *i == id)
            .map(|(t, _, d)| (*t, d))
            .collect()
    };
    let of = |id: u32| -> Vec<&Vec<u8>> { timed(id).into_iter().map(|(_, d)| d).collect() };
    let context = || format!("charger:\n{charger_err}\nmodule:\n{module_err}");

    assert!(
        charger_err.contains("charge phase idle -> remote"),
        "{}",
        context()
    );
    assert!(!charger_err.contains("heartbeat lost"), "{}", context());
    // The module asks (6070h in its TPDO 3 at 381h, 1/16 A); the charger
    // says it is charging (6001h bit 0 in its TPDO 0 at 201h) and returns
    // the charge (6052h in 1/8 Ah, in its TPDO 1 at 301h) at that rate.
    let asked = of(0x381);
    assert!(asked.len() > 20, "{}", context());
    let last = asked[asked.len() - 1];
    let asked_a = f64::from(u16::from_le_bytes([last[0], last[1]])) / 16.0;
    assert!(asked_a > 5.0, "asked {asked_a} A\n{}", context());
    assert_eq!(of(0x201).last().map(|d| d.as_slice()), Some(&[0x01][..]));
    let returned: Vec<(f64, u16)> = timed(0x301)
        .into_iter()
        .filter(|(_, d)| d.len() == 3 && d[1..] != [0xFF, 0xFF])
        .map(|(t, d)| (t, u16::from_le_bytes([d[1], d[2]])))
        .collect();
    assert!(
        returned.windows(2).all(|w| w[0].1 <= w[1].1),
        "{returned:?}"
    );
    // The rate between the first rise and the last one (not the last
    // frame, up to one 1/8 Ah step later: at 13 A a step is 35 s of the
    // 200 s).
    let last = returned.last().unwrap().1;
    let (&(t0, q0), &(t1, q1)) = (
        returned.iter().find(|r| r.1 > 0).expect("6052h rises"),
        returned.iter().find(|r| r.1 == last).unwrap(),
    );
    let ah = f64::from(q1) / 8.0;
    assert!(ah >= 0.5, "{ah} Ah returned\n{}", context());
    let rate_a = f64::from(q1 - q0) / 8.0 * 3600.0 / (t1 - t0);
    assert!(
        (rate_a - asked_a).abs() < asked_a * 0.1,
        "6052h rose at {rate_a:.2} A, {asked_a:.2} A asked\n{}",
        context()
    );
    let soc: Vec<u8> = asked.iter().map(|d| d[2]).collect();
    let (first, end) = (soc[0], soc[soc.len() - 1]);
    assert_eq!(first, 30);
    let expected = 30.0 + ah / 20.0 * 100.0;
    assert!(
        (f64::from(end) - expected).abs() <= 1.5,
        "6081h {first} -> {end} %, expected about {expected:.1} % for {ah} Ah"
    );
}

#[test]
fn help_names_the_model_options_and_bad_values_exit_2() {
    let help = Command::new(common::example("charger"))
        .arg("--help")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&help.stdout);
    for opt in [
        "--pack-chemistry",
        "--pack-cells",
        "--pack-ah",
        "--pack-soc",
        "--unplugged",
        "--no-ac",
        "--algorithm",
        "--speed",
    ] {
        assert!(text.contains(opt), "charger --help lacks {opt}");
    }
    let module_help = Command::new(common::example("battery_module"))
        .arg("--help")
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&module_help.stdout).contains("--speed"));
    for (program, bad) in [
        ("charger", &["--speed", "0"][..]),
        ("charger", &["--speed", "1001"]),
        ("charger", &["--pack-soc", "101"]),
        ("charger", &["--pack-ah", "0"]),
        ("charger", &["--pack-chemistry", "lava"]),
        ("charger", &["--pack-cells", "0"]),
        // A fixed power stage has no simulated battery to configure.
        ("charger", &["--current", "5", "--unplugged"]),
        ("charger", &["--pack-ah", "40", "--voltage", "48"]),
        ("battery_module", &["--speed", "-1"]),
        ("battery_module", &["--speed", "nan"]),
    ] {
        let o = Command::new(common::example(program))
            .args(bad)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{program} {bad:?}");
    }
}
