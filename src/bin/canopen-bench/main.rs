//! `canopen-bench`, the charge test bench: `canopen-bench run FILE` runs a
//! scenario file (docs/SCENARIOS.md: the charger's mode, the battery, the
//! bus, timed actions, `[expect]`) through the library's simulated session
//! of the Delta-Q charger and the battery module, and prints what happens.
//! `--json` prints one object per line (states, alarms, a sample a
//! simulated minute, the end); `--log FILE` writes the bus as candump
//! lines, `--report FILE.html` the decoder's HTML report of it. Exit 0, 4
//! when `[expect]` fails, 2 on a bad file.

mod toml_tree;

use std::io::{self, Write};
use std::process::ExitCode;

use canopen_codec::log::{run as decode, Options};
use canopen_codec::sim::bench::Script;
use canopen_codec::sim::Session;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "canopen-bench",
    version,
    about = "Runs charge scenario files on a simulated CAN bus"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Runs one scenario file.
    Run {
        /// The scenario file (TOML, see docs/SCENARIOS.md).
        file: String,
        /// One JSON object per line instead of words.
        #[arg(long)]
        json: bool,
        /// Writes the bus as candump log lines to this file.
        #[arg(long, value_name = "FILE")]
        log: Option<String>,
        /// Writes the HTML report of the bus to this file.
        #[arg(long, value_name = "FILE.html")]
        report: Option<String>,
    },
}

fn main() -> ExitCode {
    let Command::Run {
        file,
        json,
        log,
        report,
    } = Cli::parse().command;
    let script = std::fs::read_to_string(&file)
        .map_err(|e| e.to_string())
        .and_then(|text| toml_tree::read(&text).map_err(|e| e.to_string()))
        .and_then(|root| Script::from_document(&root).map_err(|e| e.to_string()));
    let script = match script {
        Ok(s) => s,
        Err(e) => return fail(&format!("{file}: {e}"), 2),
    };
    let mut out = io::stdout().lock();
    let ran = script.run(|e| {
        let line = if json { Some(e.json()) } else { e.words() };
        if let Some(line) = line {
            let _ = writeln!(out, "{line}");
        }
    });
    let (session, summary) = match ran {
        Ok(r) => r,
        Err(e) => return fail(&format!("{file}: [battery]: {e}"), 2),
    };
    if let Err(e) = write_bus(&session, &file, log.as_deref(), report.as_deref()) {
        return fail(&e.to_string(), 1);
    }
    let failed = script.expect.check(&summary);
    for f in &failed {
        eprintln!("canopen-bench: {file}: expect: {f}");
    }
    ExitCode::from(if failed.is_empty() { 0 } else { 4 })
}

fn fail(message: &str, code: u8) -> ExitCode {
    eprintln!("canopen-bench: {message}");
    ExitCode::from(code)
}

/// `--log` and `--report`: the session's bus as candump lines, and the
/// decoder's report of those lines.
fn write_bus(s: &Session, file: &str, log: Option<&str>, report: Option<&str>) -> io::Result<()> {
    if log.is_none() && report.is_none() {
        return Ok(());
    }
    let mut lines = Vec::new();
    for line in s.candump("can0") {
        writeln!(lines, "{line}")?;
    }
    if let Some(path) = log {
        std::fs::write(path, &lines)
            .map_err(|e| io::Error::new(e.kind(), format!("--log {path}: {e}")))?;
    }
    if let Some(path) = report {
        let opts = Options {
            frames: false,
            report: Some(path.to_string()),
            file: Some(file.to_string()),
            ..Options::default()
        };
        decode(&lines[..], &mut io::sink(), &mut io::sink(), &opts)?;
    }
    Ok(())
}
