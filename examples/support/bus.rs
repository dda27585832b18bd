//! Pipe IO shared by the node examples: candump log lines on stdin (read on
//! a thread so the main loop can wait with a deadline) and on stdout (one
//! line per frame, flushed), with a monotonic clock that can run faster
//! than the wall clock ([`PipeBus::set_speed`]: the programs' `--speed`).
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
    /// How many microseconds of the node's time pass per wall microsecond.
    speed: f64,
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
            speed: 1.0,
        }
    }

    /// The node's clock runs `speed` times the wall clock from now on
    /// (`speed` above 0; call it before the node starts: the time since
    /// start is scaled as a whole). Every timer of the node (heartbeats,
    /// PDO event timers, SDO timeouts, a charge's hold-off) then comes that
    /// much sooner in wall time, so both ends of a pipe must run at the
    /// same speed, and the heartbeat consumer times must stay well above
    /// the scheduler's jitter times the speed.
    pub fn set_speed(&mut self, speed: f64) {
        if speed > 0.0 && speed.is_finite() {
            self.speed = speed;
        }
    }

    /// Microseconds since start on the monotonic clock, scaled by the speed.
    pub fn now(&self) -> Timestamp {
        let us = self.start.elapsed().as_secs_f64() * 1e6 * self.speed;
        Timestamp::from_micros(if us < u64::MAX as f64 {
            us as u64
        } else {
            u64::MAX
        })
    }

    /// The wall time to wait until `deadline` on [`Self::now`]'s clock.
    pub fn wait_until(&self, deadline: Timestamp) -> Duration {
        let node_us = deadline.saturating_micros_since(self.now());
        // Saturates: a deadline too far for a Duration is "never".
        Duration::try_from_secs_f64(node_us as f64 / 1e6 / self.speed).unwrap_or(Duration::MAX)
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
                Some(d) => match self.lines.recv_timeout(self.wait_until(d)) {
                    Ok(l) => l,
                    Err(RecvTimeoutError::Timeout) => return Input::Timeout,
                    Err(RecvTimeoutError::Disconnected) => return Input::Closed,
                },
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
