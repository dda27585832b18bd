//! `canopen-boot`: the CiA 302-2 network manager's program. `dcf` writes
//! the DCF of a configured device from its EDS (CiA 306); `concise` turns a
//! DCF into the concise DCF (CiA 302-3 section 4, the value of 1F22h) a
//! configuration manager downloads. See docs/BOOT.md.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use canopen_codec::eds::{self, parse_int};
use canopen_codec::od::{Address, ConciseDcf};
use canopen_codec::NodeId;
use clap::{Parser, Subcommand};

const EXIT_CODES: &str = "Exit status: 0 done; 1 the DCF is not one this program can \
convert (a value that does not encode in its data type, $NODEID without a node id); \
2 usage error (bad option, unreadable DCF, unwritable output).";

/// The CiA 302-2 network manager's program: a node's configuration as a
/// DCF (CiA 306) and as the concise DCF a manager downloads.
#[derive(Parser)]
#[command(name = "canopen-boot", after_help = EXIT_CODES)]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Writes the DCF of a device configured as node --node-id: DEVICE.eds
    /// with a DeviceComissioning section and a ParameterValue per --set.
    Dcf {
        /// The device's EDS.
        eds: PathBuf,
        /// Where the DCF goes.
        out: PathBuf,
        /// The node id (1..=127, decimal or 0x hex).
        #[arg(long, value_parser = node)]
        node_id: NodeId,
        /// A configured value, INDEX:SUB=VALUE or INDEX=VALUE (sub 0), index
        /// and sub-index in hex as in an EDS (`1017=500`,
        /// `1800:1=$NODEID+0x180`); repeatable.
        #[arg(long = "set", value_parser = setting)]
        values: Vec<(Address, String)>,
    },
    /// Writes the concise DCF of FILE.dcf to OUT.bin: each writable value
    /// the DCF configures (a ParameterValue; never a ro or const one), in
    /// index order, each PDO by the CiA 301 procedure (disable, map, enable).
    Concise {
        /// The DCF (or an EDS with ParameterValues).
        dcf: PathBuf,
        /// Where the concise DCF goes.
        out: PathBuf,
        /// The node id `$NODEID` stands for (1..=127, decimal or 0x hex);
        /// default: the NodeID of the DCF's DeviceComissioning section.
        #[arg(long, value_parser = node)]
        node_id: Option<NodeId>,
    },
}

/// A node id, 1..=127.
fn node(s: &str) -> Result<NodeId, String> {
    parse_int(s)
        .and_then(|n| u8::try_from(n).ok())
        .and_then(NodeId::new)
        .ok_or(format!("'{s}' is not a node id 1..=127"))
}

/// `INDEX[:SUB]=VALUE`, index and sub-index in hex (an `h` after either
/// allowed).
fn setting(s: &str) -> Result<(Address, String), String> {
    let bad = || format!("'{s}' is not INDEX[:SUB]=VALUE (hex index and sub-index)");
    let (addr, value) = s.split_once('=').ok_or_else(bad)?;
    let (index, sub) = addr.split_once(':').unwrap_or((addr, "0"));
    let hex = |t: &str| t.trim().trim_end_matches(['h', 'H']).to_string();
    let index = u16::from_str_radix(&hex(index), 16).map_err(|_| bad())?;
    let sub = u8::from_str_radix(&hex(sub), 16).map_err(|_| bad())?;
    Ok((Address::new(index, sub), value.to_string()))
}

/// A failure and its exit status.
struct Failure(u8, String);

fn main() -> ExitCode {
    let args = match Args::try_parse() {
        Ok(a) => a,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let result = match args.command {
        Command::Dcf {
            eds,
            out,
            node_id,
            values,
        } => dcf(&eds, &out, node_id, &values),
        Command::Concise { dcf, out, node_id } => concise(&dcf, &out, node_id),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(code, message)) => {
            eprintln!("canopen-boot: {message}");
            ExitCode::from(code)
        }
    }
}

/// Reads a device description, its warnings on stderr.
fn read(path: &Path) -> Result<eds::Eds, Failure> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| Failure(2, format!("{name}: {e}")))?;
    let description = eds::parse_bytes(&bytes).map_err(|e| Failure(1, format!("{name}: {e}")))?;
    for w in &description.warnings {
        eprintln!("canopen-boot: {name}: warning: {w}");
    }
    Ok(description)
}

/// `dcf`: read the EDS, configure, write the DCF.
fn dcf(path: &Path, out: &Path, node: NodeId, values: &[(Address, String)]) -> Result<(), Failure> {
    let dcf = read(path)?
        .to_dcf(node, values.iter().map(|(a, v)| (*a, v.as_str())))
        .map_err(|e| Failure(1, format!("{}: {e}", path.display())))?;
    std::fs::write(out, eds::write(&dcf)).map_err(|e| Failure(2, format!("{}: {e}", out.display())))
}

/// `concise`: read, convert, write, and say what was written on stderr.
fn concise(dcf: &Path, out: &Path, node_id: Option<NodeId>) -> Result<(), Failure> {
    let name = dcf.display();
    let mut description = read(dcf)?;
    if let Some(node) = node_id {
        description = description
            .to_dcf(node, [])
            .map_err(|e| Failure(1, format!("{name}: {e}")))?;
    }
    let concise = description
        .to_concise_dcf()
        .map_err(|e| Failure(1, format!("{name}: {e}")))?;
    std::fs::write(out, &concise).map_err(|e| Failure(2, format!("{}: {e}", out.display())))?;
    let entries = ConciseDcf::new_checked(&concise).map_or(0, |c| c.len());
    eprintln!(
        "canopen-boot: {}: {entries} entries, {} bytes",
        out.display(),
        concise.len()
    );
    Ok(())
}
