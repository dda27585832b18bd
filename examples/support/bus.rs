//! Pipe IO shared by the node examples: candump log lines on stdin (read on
//! a thread so the main loop can wait with a deadline) and on stdout (one
//! line per frame, flushed), with a monotonic clock.
#![allow(dead_code)]

use std::io::{BufRead, Write};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use canopen_codec::trace::candump::{parse_line, LogLineDisplay};
use canopen_codec::{CanFrame, Timestamp};

/// What the input gave.
pub enum Input {
    /// A frame, with the line's timestamp if it had one.
    Frame(CanFrame, Option<Timestamp>),
    /// The deadline passed.
    Timeout,
    /// stdin closed.
    Closed,
}

pub struct PipeBus {
    lines: Receiver<String>,
    start: Instant,
    interface: String,
}

impl PipeBus {
    /// Starts reading stdin on a thread.
    pub fn stdin(interface: &str) -> Self {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        PipeBus {
            lines: rx,
            start: Instant::now(),
            interface: interface.to_string(),
        }
    }

    /// Microseconds since start on the monotonic clock.
    pub fn now(&self) -> Timestamp {
        Timestamp::from_micros(u64::try_from(self.start.elapsed().as_micros()).unwrap_or(u64::MAX))
    }

    /// Waits for the next frame until `deadline` (forever if None).
    /// Malformed lines are reported on stderr and skipped.
    pub fn recv(&self, deadline: Option<Timestamp>) -> Input {
        loop {
            let line = match deadline {
                None => match self.lines.recv() {
                    Ok(l) => l,
                    Err(_) => return Input::Closed,
                },
                Some(d) => {
                    let wait = d.saturating_micros_since(self.now());
                    match self.lines.recv_timeout(Duration::from_micros(wait)) {
                        Ok(l) => l,
                        Err(RecvTimeoutError::Timeout) => return Input::Timeout,
                        Err(RecvTimeoutError::Disconnected) => return Input::Closed,
                    }
                }
            };
            if line.trim().is_empty() {
                continue;
            }
            match parse_line(&line) {
                Ok(l) => return Input::Frame(l.frame, l.timestamp),
                Err(e) => eprintln!("input: {e}: {line}"),
            }
        }
    }

    /// Writes one frame as a candump log line and flushes.
    pub fn send(&self, frame: &CanFrame) {
        self.send_at(frame, self.now());
    }

    /// Writes one frame as a candump log line stamped `timestamp` (a time
    /// base of the caller's choosing) and flushes.
    pub fn send_at(&self, frame: &CanFrame, timestamp: Timestamp) {
        let line = LogLineDisplay {
            timestamp,
            interface: &self.interface,
            frame,
        };
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "{line}");
        let _ = out.flush();
    }
}
