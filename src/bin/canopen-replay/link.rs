//! The link to the device under test: candump log lines both ways, either
//! over the pipes of a program the replay starts or over the replay's own
//! stdin (what the device sends) and stdout (what the replay sends), and
//! the wall clock the library's [`Player`] plays on.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use canopen_codec::log::replay::player::{Heard, Options, Played, Player};
use canopen_codec::log::replay::Recording;
use canopen_codec::trace::candump::{parse_line, LogLineDisplay};
use canopen_codec::{CanFrame, Timestamp};

/// What waiting on the device gave.
pub enum Next {
    Frame(Heard),
    Timeout,
    /// The device closed its output.
    Closed,
}

/// The time since `origin` on the replay's clock.
fn since(origin: Instant) -> Timestamp {
    Timestamp::from_micros(u64::try_from(origin.elapsed().as_micros()).unwrap_or(u64::MAX))
}

pub struct Link {
    origin: Instant,
    out: Box<dyn Write>,
    lines: Receiver<Heard>,
    child: Option<Child>,
}

fn reader(input: impl Read + Send + 'static, origin: Instant) -> Receiver<Heard> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(input).lines() {
            let Ok(line) = line else { break };
            if line.trim().is_empty() {
                continue;
            }
            match parse_line(&line) {
                Ok(l) => {
                    let heard = Heard {
                        arrived: since(origin),
                        stamp: l.timestamp,
                        frame: l.frame,
                    };
                    if tx.send(heard).is_err() {
                        break;
                    }
                }
                Err(e) => eprintln!("canopen-replay: device line not read ({e}): {line}"),
            }
        }
    });
    rx
}

impl Link {
    /// Starts `program` with `args` on a candump pipe.
    pub fn spawn(program: &str, args: &[String]) -> Result<Link, String> {
        let mut child = Command::new(program)
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start '{program}': {e}"))?;
        let (Some(stdin), Some(stdout)) = (child.stdin.take(), child.stdout.take()) else {
            return Err(format!("'{program}' has no pipes"));
        };
        let origin = Instant::now();
        Ok(Link {
            origin,
            out: Box::new(stdin),
            lines: reader(stdout, origin),
            child: Some(child),
        })
    }

    /// The device on the replay's own stdin and stdout.
    pub fn stdio() -> Link {
        let origin = Instant::now();
        Link {
            origin,
            out: Box::new(std::io::stdout()),
            lines: reader(std::io::stdin(), origin),
            child: None,
        }
    }

    /// Sends one frame stamped `stamp`; false when the device is gone.
    pub fn send(&mut self, frame: &CanFrame, stamp: Timestamp) -> bool {
        let line = LogLineDisplay {
            timestamp: stamp,
            interface: "can0",
            frame,
        };
        writeln!(self.out, "{line}")
            .and_then(|()| self.out.flush())
            .is_ok()
    }

    /// The next frame from the device, waiting at most `wait`.
    pub fn next(&self, wait: Duration) -> Next {
        match self.lines.recv_timeout(wait) {
            Ok(h) => Next::Frame(h),
            Err(RecvTimeoutError::Timeout) => Next::Timeout,
            Err(RecvTimeoutError::Disconnected) => Next::Closed,
        }
    }

    /// Whether a started program has exited, and how (`Some(Err)` when it
    /// failed).
    pub fn exited(&mut self) -> Option<Result<(), String>> {
        let child = self.child.as_mut()?;
        match child.try_wait() {
            Ok(Some(status)) if status.success() => Some(Ok(())),
            Ok(Some(status)) => Some(Err(format!("the device exited: {status}"))),
            Ok(None) => None,
            Err(e) => Some(Err(format!("the device cannot be watched: {e}"))),
        }
    }

    /// Ends the link: closes the device's input, gives a started program
    /// `grace` to exit, then stops it.
    pub fn close(mut self, grace: Duration) {
        drop(std::mem::replace(&mut self.out, Box::new(std::io::sink())));
        if let Some(mut child) = self.child.take() {
            let end = Instant::now() + grace;
            while Instant::now() < end {
                if let Ok(Some(_)) = child.try_wait() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Why the device is gone, if it has exited.
fn gone(link: &mut Link) -> Option<String> {
    match link.exited() {
        Some(Err(e)) => Some(e),
        Some(Ok(())) => Some("the device exited before the recording ended".into()),
        None => None,
    }
}

/// Feeds the player what the device sends within `wait`; whether a frame
/// came. An error when the device closed its output.
fn hear(link: &mut Link, player: &mut Player, wait: Duration) -> Result<bool, String> {
    match link.next(wait) {
        Next::Frame(h) => {
            player.handle_heard(&h);
            Ok(true)
        }
        Next::Timeout => Ok(false),
        Next::Closed => Err(gone(link).unwrap_or("the device closed its output".into())),
    }
}

/// Plays `rec` into the device on `link` on the wall clock; `Err` when the
/// device stopped or died before the recording ended.
pub fn play(rec: &Recording, link: &mut Link, options: &Options) -> Result<Played, String> {
    let mut player = Player::new(rec, options, since(link.origin));
    loop {
        // Whatever the device has said by now belongs before what is sent now.
        while hear(link, &mut player, Duration::ZERO)? {}
        player.handle_timeout(since(link.origin));
        while let Some(p) = player.poll_transmit() {
            if !link.send(&p.frame, Timestamp::from_micros(p.t)) {
                return Err(gone(link).unwrap_or("the device closed its input".into()));
            }
        }
        if player.is_playing() {
            if let Some(e) = gone(link) {
                return Err(e);
            }
        }
        let Some(deadline) = player.poll_timeout() else {
            return Ok(player.finish());
        };
        hear(
            link,
            &mut player,
            deadline.saturating_duration_since(since(link.origin)),
        )?;
    }
}
