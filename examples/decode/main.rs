//! CANopen log decoder: reads candump log lines and prints every frame in
//! words or as JSON lines.
//!
//! ```text
//! cargo run --example decode -- [--json] [--charger-node N] [--battery-node N] [FILE]
//! ```
//!
//! With no FILE it reads stdin; with no FILE and a terminal on stdin it
//! decodes the bundled real Delta-Q capture so a new user sees it work.
//! Malformed lines (and frames that do not fit their CANopen object) are
//! reported on stderr with their line number; the run goes on. Exit status:
//! 0 all lines good, 1 some line bad, 2 usage or I/O error.

mod json;
mod words;

use std::io::{self, BufRead, BufWriter, IsTerminal, Write};
use std::process::ExitCode;

use canopen_codec::candump::parse_line;
use canopen_codec::{Message, NodeId};

const BUNDLED: &str = include_str!("../../tests/data/deltaq-icl1500-startup.log");
const BUNDLED_NAME: &str = "tests/data/deltaq-icl1500-startup.log (bundled real capture)";

/// Which node is which, for naming Delta-Q codes and roles.
#[derive(Clone, Copy)]
pub struct Roles {
    pub charger: NodeId,
    pub battery: NodeId,
}

impl Roles {
    pub fn role(&self, node: Option<NodeId>) -> Option<&'static str> {
        match node {
            Some(n) if n == self.charger => Some("charger"),
            Some(n) if n == self.battery => Some("battery"),
            _ => None,
        }
    }
}

struct Options {
    json: bool,
    roles: Roles,
    file: Option<String>,
}

const USAGE: &str = "usage: decode [--json] [--charger-node N] [--battery-node N] [FILE]";

fn parse_node(v: Option<String>, what: &str) -> Result<NodeId, String> {
    let v = v.ok_or(format!("{what} needs a value"))?;
    v.parse::<u8>()
        .ok()
        .and_then(NodeId::new)
        .ok_or(format!("{what}: '{v}' is not a node id 1..=127"))
}

fn parse_args() -> Result<Options, String> {
    let mut opts = Options {
        json: false,
        roles: Roles {
            charger: NodeId::new(10).ok_or("default charger")?,
            battery: NodeId::new(1).ok_or("default battery")?,
        },
        file: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--json" => opts.json = true,
            "--charger-node" => opts.roles.charger = parse_node(args.next(), "--charger-node")?,
            "--battery-node" => opts.roles.battery = parse_node(args.next(), "--battery-node")?,
            "-h" | "--help" => return Err(String::new()),
            s if s.starts_with('-') && s != "-" => return Err(format!("unknown option {s}")),
            _ if opts.file.is_some() => return Err("more than one FILE".into()),
            _ => opts.file = Some(a),
        }
    }
    Ok(opts)
}

fn main() -> ExitCode {
    let opts = match parse_args() {
        Ok(o) => o,
        Err(e) => {
            if !e.is_empty() {
                eprintln!("decode: {e}");
            }
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    let input: Box<dyn BufRead> = match opts.file.as_deref() {
        Some("-") => Box::new(io::stdin().lock()),
        Some(path) => match std::fs::File::open(path) {
            Ok(f) => Box::new(io::BufReader::new(f)),
            Err(e) => {
                eprintln!("decode: {path}: {e}");
                return ExitCode::from(2);
            }
        },
        None if io::stdin().is_terminal() => {
            eprintln!("decode: no input given; decoding {BUNDLED_NAME}");
            Box::new(BUNDLED.as_bytes())
        }
        None => Box::new(io::stdin().lock()),
    };
    match run(input, &opts) {
        Ok(0) => ExitCode::SUCCESS,
        Ok(bad) => {
            eprintln!("decode: {bad} bad line(s)");
            ExitCode::from(1)
        }
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("decode: {e}");
            ExitCode::from(2)
        }
    }
}

/// Decodes every line; returns the number of bad lines.
fn run(input: Box<dyn BufRead>, opts: &Options) -> io::Result<usize> {
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let mut bad = 0;
    let mut text = String::new();
    for (i, line) in input.lines().enumerate() {
        let line = line?;
        let lineno = i + 1;
        if line.trim().is_empty() {
            continue;
        }
        let parsed = match parse_line(&line) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("line {lineno}: {e}: {line}");
                bad += 1;
                continue;
            }
        };
        let decoded = Message::decode(&parsed.frame);
        if let Err(e) = &decoded {
            eprintln!("line {lineno}: frame {} does not decode: {e}", parsed.frame);
            bad += 1;
        }
        text.clear();
        if opts.json {
            json::line(&mut text, &parsed, &decoded, &opts.roles);
        } else {
            words::line(&mut text, &parsed, &decoded, &opts.roles);
        }
        writeln!(out, "{text}")?;
    }
    out.flush()?;
    Ok(bad)
}
