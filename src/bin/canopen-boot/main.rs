//! `canopen-boot`: the CiA 302-2 network manager's program. With `--node
//! N=FILE.dcf ...` it is the NMT master on a candump-line pipe (stdin in,
//! stdout out): it boots each node from its DCF and reports each boot's end
//! and later events as JSON lines on stderr (`log::boot`). `dcf` writes the
//! DCF of a configured device from its EDS (CiA 306); `concise` turns a DCF
//! into the concise DCF (CiA 302-3 section 4, the value of 1F22h) a
//! configuration manager downloads. See docs/BOOT.md.

mod pipe;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use canopen_codec::eds::{self, parse_int};
use canopen_codec::log::boot::{apply_settings, BootNode, BootRun, NodeSetting};
use canopen_codec::manager::{ManagerConfig, NmtStartup};
use canopen_codec::od::{Address, ConciseDcf};
use canopen_codec::NodeId;
use clap::{Parser, Subcommand};

const EXIT_CODES: &str = "Exit status: 0 done (as the manager: every node operational \
when stdin closed); 1 a node's boot ended in an error, or the DCF is not one this \
program can convert (a value that does not encode in its data type, $NODEID without \
a node id); 2 usage error (bad option, unreadable DCF, unwritable output).";

/// The CiA 302-2 network manager's program: the NMT master that boots the
/// nodes of their DCFs (CiA 306) on a candump-line pipe, or a node's
/// configuration as a DCF and as the concise DCF a manager downloads.
#[derive(Parser)]
#[command(
    name = "canopen-boot",
    after_help = EXIT_CODES,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct Args {
    #[command(subcommand)]
    command: Option<Command>,
    /// A node to boot and its DCF, N=FILE.dcf (repeat for each node): its
    /// 1000h and 1018h are checked, its configured values written.
    #[arg(long = "node", value_name = "N=FILE.dcf", value_parser = node_dcf, required = true)]
    nodes: Vec<(NodeId, PathBuf)>,
    /// The mandatory nodes, N,N,...: the network starts once they booted.
    #[arg(long, value_delimiter = ',', value_parser = node)]
    mandatory: Vec<NodeId>,
    /// Start the nodes with one NMT command to all (1F80h bit 1).
    #[arg(long)]
    start_all: bool,
    /// The keep-alive nodes, N,N,...: not reset at the start (1F81h bit
    /// 4); one found operational by its heartbeat is reported with L and
    /// left running.
    #[arg(long, value_delimiter = ',', value_parser = node)]
    keep_alive: Vec<NodeId>,
    /// A node's expected program software identification, N=ID (1F55h,
    /// compared with its 1F56h sub 1; 1F81h bit 5); repeatable.
    #[arg(long, value_name = "N=ID", value_parser = node_u32)]
    software_id: Vec<(NodeId, u32)>,
    /// A node's expected application software date, N=DAYS since 1
    /// January 1984 (1F53h, compared with its 1F52h sub 1; 1F81h bit 5).
    #[arg(long, value_name = "N=DAYS", value_parser = node_u32)]
    software_date: Vec<(NodeId, u32)>,
    /// A node's expected application software time, N=MS after midnight
    /// (1F54h, compared with its 1F52h sub 2 with the date).
    #[arg(long, value_name = "N=MS", value_parser = node_u32)]
    software_time: Vec<(NodeId, u32)>,
    /// The boot time, in ms (1F89h): when it has passed with the network
    /// not started, each mandatory node not booted is reported (0: none).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=3_600_000))]
    boot_time_ms: u64,
    /// How long after error B (no answer to 1000h) a node's boot starts
    /// again by itself, in ms (0: only at its boot-up message).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=3_600_000))]
    retry_interval_ms: u64,
    /// How many times an unanswered read of 1000h is tried again before B.
    #[arg(long, default_value_t = 2)]
    sdo_retries: u8,
    /// The SDO timeout, in ms.
    #[arg(long, default_value_t = 500, value_parser = clap::value_parser!(u64).range(1..=60_000))]
    sdo_timeout_ms: u64,
}

impl Args {
    /// The per-node settings of the options.
    fn settings(&self) -> Vec<(NodeId, NodeSetting)> {
        let mut out = Vec::new();
        out.extend(self.mandatory.iter().map(|n| (*n, NodeSetting::Mandatory)));
        out.extend(self.keep_alive.iter().map(|n| (*n, NodeSetting::KeepAlive)));
        let values = [
            (
                &self.software_id,
                NodeSetting::SoftwareId as fn(u32) -> NodeSetting,
            ),
            (&self.software_date, NodeSetting::SoftwareDate),
            (&self.software_time, NodeSetting::SoftwareTime),
        ];
        for (pairs, setting) in values {
            out.extend(pairs.iter().map(|(n, v)| (*n, setting(*v))));
        }
        out
    }

    /// The manager's configuration (1F80h, 1F89h, the SDO times).
    fn config(&self) -> ManagerConfig {
        let mut startup = NmtStartup::MASTER;
        startup.set(NmtStartup::START_ALL, self.start_all);
        ManagerConfig {
            startup,
            sdo_timeout: Duration::from_millis(self.sdo_timeout_ms),
            retries: self.sdo_retries,
            boot_time: Duration::from_millis(self.boot_time_ms),
            retry_interval: Duration::from_millis(self.retry_interval_ms),
            ..ManagerConfig::default()
        }
    }
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

/// `N=VALUE`, the value decimal or 0x hex, at most 32 bits.
fn node_u32(s: &str) -> Result<(NodeId, u32), String> {
    let bad = || format!("'{s}' is not N=VALUE (a node id, then a 32-bit number)");
    let (n, v) = s.split_once('=').ok_or_else(bad)?;
    let v = parse_int(v).and_then(|v| u32::try_from(v).ok());
    Ok((node(n)?, v.ok_or_else(bad)?))
}

/// `N=FILE.dcf`.
fn node_dcf(s: &str) -> Result<(NodeId, PathBuf), String> {
    let (n, file) = s
        .split_once('=')
        .ok_or(format!("'{s}' is not N=FILE.dcf"))?;
    Ok((node(n)?, PathBuf::from(file)))
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
        Some(Command::Dcf {
            eds,
            out,
            node_id,
            values,
        }) => dcf(&eds, &out, node_id, &values),
        Some(Command::Concise { dcf, out, node_id }) => concise(&dcf, &out, node_id),
        None => manage(&args),
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
    let noun = if entries == 1 { "entry" } else { "entries" };
    eprintln!(
        "canopen-boot: {}: {entries} {noun}, {} bytes",
        out.display(),
        concise.len()
    );
    Ok(())
}

/// The manager: the nodes from their DCFs and the options, then the run
/// until stdin closes.
fn manage(args: &Args) -> Result<(), Failure> {
    let mut boot = Vec::new();
    for (node, path) in &args.nodes {
        let name = path.display();
        let text = std::fs::read(path).map_err(|e| Failure(2, format!("{name}: {e}")))?;
        let n = BootNode::from_dcf(*node, &text).map_err(|e| Failure(1, format!("{name}: {e}")))?;
        boot.push(n);
    }
    apply_settings(&mut boot, args.settings()).map_err(|e| Failure(2, e))?;
    let mut run = BootRun::new(args.config(), &boot).map_err(|e| Failure(2, e))?;
    if pipe::run(&mut run) {
        return Err(Failure(1, "a node's boot ended in an error".into()));
    }
    Ok(())
}
