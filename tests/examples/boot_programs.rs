//! Our own node programs booted by `canopen-boot` (issue 36, item 4), as a
//! user runs them: `examples/battery_module` and `examples/charger` (its
//! start-up configuration left to the manager: `--no-configure`) each print
//! their EDS, `canopen-boot dcf` turns each into a DCF (the module's 1017h
//! producer heartbeat time at 250 ms; the charger's heartbeat, its consumer
//! of the module's heartbeat, 1016h, and its PDOs paired with the module's,
//! CiA 419 section 7.2), and the three programs run on one candump-line
//! bus made by the test (every line one writes goes to the other two,
//! stamped in the bus's time base). The
//! manager reports both nodes operational (CiA 302-2), the bus shows the
//! SDO downloads, the NMT start and the module's heartbeat at its new
//! period; the module's process killed, the manager reports error E.

use crate::common;

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread;
use std::time::{Duration, Instant};

use canopen_codec::cia419::PDO_PAIRS;
use canopen_codec::eds::{eval_int, parse_bytes, Eds};

const MODULE: u8 = 1;
const CHARGER: u8 = 10;
/// How long any one stage may take, generous for a loaded machine.
const PATIENCE: Duration = Duration::from_secs(30);

/// The running programs and their files: killed, waited for and removed on
/// drop, also when an assertion fails.
struct Programs {
    children: Vec<Child>,
    dir: PathBuf,
}

impl Drop for Programs {
    fn drop(&mut self) {
        for child in &mut self.children {
            let _ = child.kill();
            let _ = child.wait();
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// What the bus and the programs said: each bus line with the index of
/// its sender, and each program's stderr lines.
#[derive(Default)]
struct Heard {
    bus: Vec<(usize, String)>,
    stderr: Vec<Vec<String>>,
}

/// Frame `ID#DATA` and the sender's time stamp (seconds) of a candump line.
fn frame(line: &str) -> Option<(f64, &str)> {
    let mut words = line.split_whitespace();
    let time = words.next()?.strip_prefix('(')?.strip_suffix(')')?;
    Some((time.parse().ok()?, words.nth(1)?))
}

/// The value an EDS gives `index`/`sub` for `node`, as a number.
fn value_of(eds: &Eds, index: u16, sub: u8, node: u8) -> u32 {
    let text = eds.entry(index, sub).unwrap().value().unwrap();
    u32::try_from(eval_int(text, Some(node)).unwrap()).unwrap()
}

/// `program ARGS --print-eds`, written to `dir/NAME.eds`.
fn print_eds(dir: &Path, program: &str, args: &[&str]) -> (PathBuf, Eds) {
    let o = Command::new(common::example(program))
        .args(args)
        .arg("--print-eds")
        .output()
        .unwrap();
    assert!(o.status.success(), "{program} --print-eds: {o:?}");
    let path = dir.join(format!("{program}.eds"));
    std::fs::write(&path, &o.stdout).unwrap();
    (path, parse_bytes(&o.stdout).unwrap())
}

/// `canopen-boot dcf EDS OUT --node-id N --set ...`.
fn dcf(eds: &Path, out: &Path, node: u8, values: &[String]) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_canopen-boot"));
    c.arg("dcf").arg(eds).arg(out);
    c.args(["--node-id", &node.to_string()]);
    for v in values {
        c.args(["--set", v]);
    }
    let o = c.output().unwrap();
    assert!(o.status.success(), "canopen-boot dcf: {o:?}");
}

/// Spawns `program` on the bus as member `me` of `stdins`.
fn spawn(
    program: &str,
    args: &[&str],
    me: usize,
    heard: &Arc<Mutex<Heard>>,
    stdins: &Arc<Mutex<Vec<Option<ChildStdin>>>>,
    start: Instant,
) -> Child {
    let mut child = Command::new(program)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    stdins.lock().unwrap_or_else(PoisonError::into_inner)[me] = child.stdin.take();
    let (out, err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let (h, s) = (Arc::clone(heard), Arc::clone(stdins));
    thread::spawn(move || {
        for line in BufReader::new(out).lines() {
            let Ok(line) = line else { break };
            // One lock for the log and the writes: every member hears the
            // lines in the order of the log.
            let mut stdins = s.lock().unwrap_or_else(PoisonError::into_inner);
            // Stamped in the bus's one time base as the other two receive
            // it (each program stamps its lines in its own clock, and a
            // node's clock follows the time stamps it reads).
            let at = start.elapsed().as_secs_f64();
            let heard_as =
                frame(&line).map_or(line.clone(), |(_, f)| format!("({at:.6}) can0 {f}"));
            h.lock()
                .unwrap_or_else(PoisonError::into_inner)
                .bus
                .push((me, line.clone()));
            for (i, to) in stdins.iter_mut().enumerate() {
                if i == me {
                    continue;
                }
                if let Some(pipe) = to {
                    if writeln!(pipe, "{heard_as}")
                        .and_then(|()| pipe.flush())
                        .is_err()
                    {
                        *to = None;
                    }
                }
            }
        }
    });
    let h = Arc::clone(heard);
    thread::spawn(move || {
        for line in BufReader::new(err).lines() {
            let Ok(line) = line else { break };
            h.lock().unwrap_or_else(PoisonError::into_inner).stderr[me].push(line);
        }
    });
    child
}

/// Waits until `done` holds for what was heard, or fails with all of it.
fn wait_for(heard: &Arc<Mutex<Heard>>, what: &str, done: impl Fn(&Heard) -> bool) {
    let start = Instant::now();
    loop {
        {
            let h = heard.lock().unwrap_or_else(PoisonError::into_inner);
            if done(&h) {
                return;
            }
            if start.elapsed() > PATIENCE {
                let bus: Vec<&str> = h.bus.iter().map(|(_, l)| l.as_str()).collect();
                panic!(
                    "no {what} within {PATIENCE:?}\nmodule:\n{}\ncharger:\n{}\ncanopen-boot:\n{}\nbus:\n{}",
                    h.stderr[0].join("\n"),
                    h.stderr[1].join("\n"),
                    h.stderr[2].join("\n"),
                    bus.join("\n")
                );
            }
        }
        thread::sleep(Duration::from_millis(20));
    }
}

/// Whether canopen-boot reported a JSON line for `node` with `key: value`
/// (and `code`, if given).
fn reported(h: &Heard, node: u8, key: &str, value: &str, code: Option<&str>) -> bool {
    h.stderr[2].iter().any(|line| {
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            return false;
        };
        v["node"] == u64::from(node) && v[key] == value && code.is_none_or(|c| v["code"] == c)
    })
}

#[test]
fn canopen_boot_boots_the_battery_module_and_charger_programs() {
    let dir = std::env::temp_dir().join(format!("canopen-boot-programs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut programs = Programs {
        children: Vec::new(),
        dir: dir.clone(),
    };

    // The DCFs of the programs' own EDS.
    let (module_eds_path, module_eds) = print_eds(&dir, "battery_module", &[]);
    let (charger_eds_path, charger_eds) = print_eds(&dir, "charger", &["--no-configure"]);
    let module_dcf = dir.join("module.dcf");
    dcf(&module_eds_path, &module_dcf, MODULE, &["1017=250".into()]);
    // The charger: heartbeat every 500 ms, the module's heartbeat consumed
    // within 1500 ms (node 1 in bits 16-23, the time in ms), and each PDO
    // paired with the module's on the module's identifier.
    let mut values = vec!["1017=500".to_string(), "1016:1=0x000105DC".to_string()];
    let mut paired = 0;
    for pair in PDO_PAIRS {
        let own = pair.charger_direction.comm_index(pair.charger_pdo);
        if module_eds.entry(pair.module_comm_index, 1).is_none()
            || charger_eds.entry(own, 1).is_none()
        {
            continue;
        }
        let id = value_of(&module_eds, pair.module_comm_index, 1, MODULE) & 0x7FF;
        values.push(format!("{own:X}:1=0x{id:X}"));
        paired += 1;
    }
    assert!(paired >= 2, "{values:?}");
    let charger_dcf = dir.join("charger.dcf");
    dcf(&charger_eds_path, &charger_dcf, CHARGER, &values);

    // The three programs on one bus: the module (0), the charger (1) and
    // the manager (2) of both, mandatory.
    let heard = Arc::new(Mutex::new(Heard {
        bus: Vec::new(),
        stderr: vec![Vec::new(); 3],
    }));
    let stdins = Arc::new(Mutex::new(vec![None, None, None]));
    let start = Instant::now();
    let module = common::example("battery_module");
    let charger = common::example("charger");
    let linger = ["--linger-ms", "0"];
    programs
        .children
        .push(spawn(&module, &linger, 0, &heard, &stdins, start));
    let charger_args = ["--no-configure", "--linger-ms", "0"];
    programs
        .children
        .push(spawn(&charger, &charger_args, 1, &heard, &stdins, start));
    // The manager joins once both nodes are up (its reset of their
    // communication then answered by the one boot-up each that follows).
    wait_for(&heard, "boot-ups", |h| {
        ["701#00", "70A#00"]
            .iter()
            .all(|b| h.bus.iter().any(|(_, l)| l.ends_with(b)))
    });
    let nodes = [
        format!("{MODULE}={}", module_dcf.display()),
        format!("{CHARGER}={}", charger_dcf.display()),
    ];
    let boot_args = [
        "--node",
        &nodes[0],
        "--node",
        &nodes[1],
        "--mandatory",
        "1,10",
    ];
    programs.children.push(spawn(
        env!("CARGO_BIN_EXE_canopen-boot"),
        &boot_args,
        2,
        &heard,
        &stdins,
        start,
    ));

    // Both booted, and four heartbeats of the module since.
    wait_for(&heard, "operational nodes", |h| {
        reported(h, MODULE, "result", "operational", None)
            && reported(h, CHARGER, "result", "operational", None)
    });
    let seen = heard
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .bus
        .len();
    wait_for(&heard, "module heartbeats", |h| {
        h.bus[seen..]
            .iter()
            .filter(|(_, l)| l.ends_with(" 701#05"))
            .count()
            >= 5
    });
    let h = heard.lock().unwrap_or_else(PoisonError::into_inner);
    assert!(
        h.stderr[2].iter().all(|l| !l.contains("\"error\"")),
        "{:?}",
        h.stderr[2]
    );
    let frames: Vec<(usize, f64, &str)> = h
        .bus
        .iter()
        .filter_map(|(from, l)| frame(l).map(|(t, f)| (*from, t, f)))
        .collect();
    let position = |from: usize, f: &str| {
        frames
            .iter()
            .position(|(who, _, g)| *who == from && *g == f)
            .unwrap_or_else(|| panic!("no {f} from {from}: {:?}", h.bus))
    };
    // The configuration written by expedited SDO downloads (CiA 301 section
    // 7.2.4.3.3) and confirmed: the module's 1017h = 250 (00FAh), the
    // charger's 1017h = 500 (01F4h) and 1016h sub 1.
    let module_written = position(2, "601#2B171000FA000000");
    let module_confirmed = position(0, "581#6017100000000000");
    position(2, "60A#2B171000F4010000");
    position(1, "58A#6017100000000000");
    position(2, "60A#23161001DC050100");
    position(1, "58A#6016100100000000");
    assert!(module_written < module_confirmed);
    // Each node started by the manager (NMT start, CiA 301 section 7.2.8.3.2.1).
    let started = position(2, "000#0101");
    position(2, "000#010A");
    assert!(module_confirmed < started);
    // The module's heartbeat since it was started: operational (05h), at
    // the configured 250 ms (its own time stamps; the median interval).
    let beats: Vec<f64> = frames[started..]
        .iter()
        .filter(|(who, _, f)| *who == 0 && *f == "701#05")
        .map(|(_, t, _)| *t)
        .collect();
    let mut periods: Vec<f64> = beats.windows(2).map(|w| w[1] - w[0]).collect();
    periods.sort_by(f64::total_cmp);
    let median = periods[periods.len() / 2];
    assert!(
        (0.2..0.3).contains(&median),
        "module heartbeat every {median} s: {beats:?}"
    );
    // The charger operational too.
    assert!(frames[started..]
        .iter()
        .any(|(who, _, f)| *who == 1 && *f == "70A#05"));
    drop(h);

    // The module's process goes away: heartbeat event E for its node.
    let _ = programs.children[0].kill();
    wait_for(&heard, "heartbeat event E", |h| {
        reported(h, MODULE, "event", "heartbeat", Some("E"))
    });
    assert!(!reported(
        &heard.lock().unwrap_or_else(PoisonError::into_inner),
        CHARGER,
        "event",
        "heartbeat",
        None
    ));
}
