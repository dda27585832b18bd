//! `canopen-decode`, the CANopen log decoder: reads a CAN trace and prints
//! every frame in words or as JSON lines. Install it with
//! `cargo install --path . --features cli`; in the repository `cargo decode`
//! runs it (an alias of `cargo run --features cli --bin canopen-decode --`).
//!
//! ```text
//! canopen-decode [--json] [--format F] [--charger-node N] [--battery-node N]
//!     [--pdo COBID=INDEX:SUB:BITS,...]... [--no-default-pdos] [--pdo-capture-mapping]
//!     [--sdo NODE=RXID,TXID]... [--signals PATH] [--dbc PATH] [FILE]...
//! ```
//!
//! `--signals PATH` writes the PDO fields as signals (CSV, or Parquet for a
//! `.parquet` path with feature `parquet`; several logs: one dataset
//! partitioned by log), `--dbc PATH` the PDO mappings in use as a DBC
//! (docs/DECODER.md, modules `signals`, `signals_parquet` and `dbc`).
//! With either (as with `--report`) the written file is the output: the
//! frames are printed only when `--json` or `--output` asks for them.
//!
//! SDO transfers are followed by the library's passive observer
//! (`canopen_codec::sdo::Observer`) on the default channel of every node
//! and on each channel `--sdo NODE=RXID,TXID` declares (node in decimal,
//! the COB-IDs the server receives on and answers on in hex, as in its
//! 1200h sub 1 and 2: `--sdo 65=241,1C1`). Block transfers are reassembled
//! like segmented ones; their sub-block segments print as `SDO block
//! segment seq N` (JSON: `"command":"block segment"`, `seqno`, `last`,
//! `segment_data`).
//!
//! `--eds NODE=FILE` (repeatable) reads a node's EDS or DCF (CiA 306, with
//! `$NODEID` resolved): its PDO COB-IDs and mappings decode that node's PDOs
//! (marked `[from the EDS]`), named with the file's object names (which
//! name its SDO transfers' values too); its 1200h
//! adds its SDO channel when not the default and valid (a COB-ID with bit
//! 31 set adds none); a device type (1000h) of profile 418 or 419 gives the
//! node its role, Delta-Q's vendor ID (1018h:01 or `VendorNumber`) makes it
//! a Delta-Q device. PDO mappings and COB-IDs
//! written or read by SDO in the log (1400h-1BFFh) apply to the PDOs that
//! follow, and the transfer's line says so (`[TPDO1 of node 5 maps ...]`).
//!
//! The trace format is detected from its first telling line, or given with
//! `--format`: `candump` (candump `-L` log lines), `candump-screen`
//! (candump screen output; `candump-screen-delta` for `-t d` times),
//! `trc` (PCAN-View 1.0-2.1), `asc` (Vector ASC), `csv` (python-can CSV)
//! (`canopen_codec::trace`), `blf` (Vector BLF, binary; a file beginning
//! with `LOGG` is read as one), each file read by the module
//! `canopen_codec::log::input` (as `canopen-replay`'s). Header and comment
//! lines are skipped; CAN FD and error frames are reported on stderr (line
//! by line or object by object), counted at the end and in the bus load,
//! not as bad lines.
//!
//! With no FILE it reads stdin; with no FILE and a terminal on stdin it
//! decodes the bundled session of the crate's own virtual charger and
//! battery module (`tests/data/virtual-session.log`: normal start,
//! heartbeat loss with E-0-3-2, recovery) so a new user sees it work.
//! Malformed lines (and frames that do not fit their CANopen object, lines
//! that are not UTF-8 text and lines longer than 64 KiB) are reported on
//! stderr with their line number; the run goes on. A log of which no line
//! is a frame is an error naming the format tried. Exit status:
//! 0 all lines good, 1 some line bad or no frame at all, 2 usage or I/O error (a malformed
//! `--pdo` included).
//!
//! How PDO fields are named and printed (`--pdo`, the defaults, the
//! capture's mapping) is documented with the library's
//! `canopen_codec::log::mappings`, the SDO transfer lines and their JSON
//! with `canopen_codec::log::sdo`; docs/DECODER.md gives the overview.
//!
//! TIME frames are shown with the UTC date and time they mean after the raw
//! days and milliseconds (` = 1984-01-03T12:00:00.000Z`; JSON `utc`).
//!
//! `--summary` writes the summary after the frames; `--summary-file PATH`
//! writes it to PATH; with `--output csv` and no file it goes to stderr,
//! so the CSV stream stays one CSV.

mod args;
#[cfg(feature = "parquet")]
mod signals_parquet;

use canopen_codec::log::{input, run, run_each, run_path, Options, Outcome};
use std::io::{self, IsTerminal, Read};
use std::process::ExitCode;

/// The program's hooks: flate2 for BLF, memchr (SIMD) for line ends, the
/// Parquet writer.
fn hooks(opts: &mut Options) {
    opts.inflater = Some(|| Box::<input::Zlib>::default());
    opts.find_newline = Some(|bytes| memchr::memchr(b'\n', bytes));
    #[cfg(feature = "parquet")]
    {
        opts.parquet = Some(signals_parquet::write);
    }
}

const SESSION: &str = include_str!("../../../tests/data/virtual-session.log");
const SESSION_NAME: &str =
    "tests/data/virtual-session.log (bundled session of the virtual charger and battery module)";

fn main() -> ExitCode {
    use clap::{CommandFactory, Parser};
    // Usage errors exit 2 (clap's code too), help and version 0.
    let mut opts = match args::Cli::parse().options() {
        Ok(o) => o,
        Err(e) => {
            let mut cmd = args::Cli::command();
            eprintln!("canopen-decode: {e}\n\n{}", cmd.render_usage());
            return ExitCode::from(2);
        }
    };
    hooks(&mut opts);
    let (stdout, stderr) = (io::stdout(), io::stderr());
    let (mut out, mut diag) = (stdout.lock(), stderr.lock());
    // Several logs (or one with `--dataset`): each decoded on its own
    // (`canopen_codec::log::run_each`); the exit status is the
    // worst of the runs.
    let several = !opts.more_files.is_empty() || opts.dataset.is_some();
    let file = opts.file.clone().filter(|f| f != "-");
    let result = if several {
        run_each(&opts, &mut out, &mut diag)
    } else if let Some(path) = file.filter(|_| opts.bundled.is_none()) {
        run_path(&path, &mut out, &mut diag, &opts) // an MF4 file read in place
    } else {
        input(&mut opts).and_then(|input| run(input, &mut out, &mut diag, &opts))
    };
    match result {
        Ok(o) if o.open && opts.check => {
            if o.bad > 0 {
                eprintln!("canopen-decode: {} bad line(s)", o.bad);
            }
            let which = if several { "a" } else { "the" };
            eprintln!("canopen-decode: problems open at the end of {which} log (--check)");
            ExitCode::from(3)
        }
        Ok(o) => exit_status(o),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("canopen-decode: {e}");
            ExitCode::from(2)
        }
    }
}

/// The one log but a file (`run_path`): stdin, or the bundled session (asked for, or
/// no input given with a terminal on stdin).
fn input(opts: &mut Options) -> io::Result<Box<dyn Read>> {
    Ok(match (opts.bundled, opts.file.as_deref()) {
        (Some(_), _) => {
            opts.roles.demo();
            eprintln!("canopen-decode: decoding {SESSION_NAME}");
            Box::new(SESSION.as_bytes())
        }
        (None, Some(_)) => Box::new(io::stdin().lock()),
        (None, None) if io::stdin().is_terminal() => {
            opts.roles.demo();
            eprintln!("canopen-decode: no input given; decoding {SESSION_NAME}");
            Box::new(SESSION.as_bytes())
        }
        (None, None) => Box::new(io::stdin().lock()),
    })
}

/// 0, or 1 with the count of bad lines (a log without a frame has said so
/// already).
fn exit_status(o: Outcome) -> ExitCode {
    if o.bad > 0 {
        eprintln!("canopen-decode: {} bad line(s)", o.bad);
    }
    if o.failed() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
