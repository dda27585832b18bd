//! The candump-line pipe: stdin read on a thread (so the loop can wait for
//! the manager's next deadline), stdout one line per frame, the wall clock
//! (`Instant`) as the manager's time.

use std::io::{BufRead, Write};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use canopen_codec::log::boot::BootRun;
use canopen_codec::trace::candump::{parse_line, LogLineDisplay};
use canopen_codec::{CanFrame, Timestamp};

/// Runs the manager until stdin closes; true if a boot ended in an error.
pub fn run(boot: &mut BootRun<'_>) -> bool {
    let (tx, lines) = mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::stdin().lock().lines() {
            if line.map(|l| tx.send(l)).is_err() {
                break;
            }
        }
    });
    let start = Instant::now();
    let now =
        || Timestamp::from_micros(u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX));
    let send = |f: CanFrame| {
        let line = LogLineDisplay {
            timestamp: now(),
            interface: "can0",
            frame: &f,
        };
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "{line}");
        let _ = out.flush();
    };
    let report = |line: String| eprintln!("{line}");
    boot.start(now(), send);
    loop {
        let wait = boot.deadline().map_or(Duration::from_secs(3600), |d| {
            Duration::from_micros(d.saturating_micros_since(now()))
        });
        let frame = match lines.recv_timeout(wait) {
            Ok(line) => match parse_line(&line) {
                Ok(l) => Some(l.frame),
                Err(e) if !line.trim().is_empty() => {
                    eprintln!("canopen-boot: input: {e}: {line}");
                    None
                }
                Err(_) => None,
            },
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => break,
        };
        boot.step(now(), frame.as_ref(), send, report);
    }
    boot.failed()
}
