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
//! lines are skipped; CAN FD and error frames are reported on stderr, line
//! by line (object by object), counted at the end, and do not count as
//! bad lines.
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
//! ## PDO fields
//!
//! A PDO's bytes mean nothing without its mapping, so the decoder takes it
//! as configuration:
//!
//! - `--pdo COBID=INDEX:SUB:BITS,...` (repeatable, one COB-ID each) gives
//!   the mapping of the PDO on identifier COBID: COBID, INDEX and SUB in hex
//!   (`18A` or `0x18A`), BITS in decimal, entries in mapping order. Dummy
//!   entries (index 1..1F, e.g. `6:0:16`) and 2FFAh are padding. The
//!   objects are named from the dictionary of the node the COB-ID belongs
//!   to, as far as the evidence says whose it is: its EDS, else the battery
//!   node's CiA 418, a Delta-Q charger's Delta-Q and CiA 418 objects, a
//!   CiA 419 charger's CiA 418/419 objects; a node without a role or EDS
//!   names nothing (`2002h unknown object: raw 1374h (16 bits)`). An entry
//!   mapped with fewer bits than its object is read from those bits
//!   (sign-extended for a signed object) and flagged `[deviates: mapped as
//!   4 bits, object has 8]`.
//! - Without `--pdo` for a COB-ID, the defaults apply to nodes with a role:
//!   the Delta-Q charger's default PDOs on a Delta-Q charger's COB-IDs, the
//!   CiA 418 battery-module defaults on the battery module's. A node has a
//!   role only from evidence: `--charger-node` / `--battery-node`, its
//!   EDS's 1000h, or its 1000h read by SDO in the log (profile 419:
//!   charger, 418: battery module; reported on a line of its own). A charger
//!   is a Delta-Q one only with Delta-Q evidence: `--charger-node`, an EDS
//!   with Delta-Q's vendor ID, or 1018h:01 read in the log with Delta-Q's
//!   vendor ID (00000110h; reported on a line of its own; in JSON each
//!   fact learned is `{"kind":"role","node","role","deltaq","text"}`).
//!   `--pdo-capture-mapping` and the bundled session imply the Delta-Q
//!   charger 10 and battery module 1. `--no-default-pdos` turns the
//!   defaults off. A frame with no known mapping is printed raw, as before.
//! - `--pdo-capture-mapping` decodes the real Delta-Q captures (third-party
//!   data, not in this repository; see tests/data/CAPTURES.md): it adds the
//!   mapping of tests/data/CAPTURES.md (the integrator remapped that
//!   charger) and implies `--no-default-pdos`; 0x28A, whose layout is not
//!   published, stays raw. It is the same as
//!
//! ```text
//! canopen-decode --no-default-pdos \
//!     --pdo 18A=2002:0:16,2101:0:16,2006:0:16,6:0:16 \
//!     --pdo 38A=2060:0:32,2200:0:16,6080:0:8,5:0:8 \
//!     --pdo 20A=2FFA:1:8,6081:0:8,4201:0:8,2276:0:16,6070:0:16,6000:0:8 \
//!     --pdo 30A=2FFA:1:8,2FFA:1:8,2002:0:16,2101:0:16,6010:0:16 \
//!     deltaq-icl1500-charging.log
//! ```
//!
//! In words, the fields follow the frame after ` = `, numbers **rounded to
//! at most 2 decimals** with trailing zeros dropped (halves away from zero:
//! 0x1374/256 A prints `19.45 A`, 0x07BA/16 V `123.63 V`, 0x5200/256 V
//! `82 V`), padding left out, and
//! `(+N unmapped bytes)` when the frame is longer than its mapping; a
//! default mapping is labelled `[charger default]` / `[battery default]`.
//! In `--json` the frame gets `mapping` (`given`, `charger default`,
//! `battery default`), `unmapped_bytes` and `fields`: one object per entry
//! with `index`, `sub`, `bits`, `name`, `raw`, `kind` (`scaled`, `flags`,
//! `invalid`, `no_value`, `padding`, `missing`, `raw`, ...), `value` (the
//! **exact** number for scaled values, e.g. 19.453125; words for bit fields
//! and codes; null otherwise), `unit` where the object has one, and `text`.
//!
//! ## SDO transfers
//!
//! The decoder follows one SDO transfer per server node (requests on
//! 0x600 + node, responses on 0x580 + node) and, after the frame that ends
//! one, prints one extra line (in `--json`, one extra object):
//!
//! ```text
//! 1757100000.207750  transfer  -        SDO upload 1008h:00 from node 2: 26 bytes "Tiny Node - Mega Domains !" (manufacturer device name)
//! 1757100000.101350  transfer  -        SDO download 1017h:00 to node 2: A0 0F (producer heartbeat time: 4000 ms)
//! 1757100000.501350  transfer  -        SDO upload 1018h:01 from node 2 aborted: 06090011h Sub-index does not exist
//! ```
//!
//! - A transfer ends with the expedited response or acknowledgement, the
//!   last upload segment (c = 1), the acknowledgement of the last download
//!   segment, or an abort from either side (`aborted by the client` when the
//!   client sent it; the transfer's own index and sub-index are shown, not
//!   the abort frame's).
//! - A transfer broken off (a new initiate on its channel, a wrong toggle
//!   bit, a response for another object, a frame that does not fit, a
//!   malformed frame, or the end of the log) is reported once as
//!   `incomplete: <why> (N bytes transferred of M indicated)`. Frames with no
//!   transfer open (a stray segment, an abort) add no transfer line.
//! - An indicated size other than the bytes transferred is printed as
//!   `[size mismatch: ...]` (JSON `size_mismatch`, `indicated_size`, `size`);
//!   an expedited value with s = 0 as `[size not indicated]`. At most 64 KiB
//!   of a transfer are kept (`[truncated: ...]`, JSON `truncated`); the
//!   count goes on.
//! - The value is named and interpreted where the object is known: every
//!   object of the CiA 301 communication profile area 1000h-1FFFh on any
//!   node (1000h with the CiA 418 optional PDOs when its profile is 418,
//!   1003h with the Delta-Q code on a Delta-Q charger, 100Ch/100Dh, 1005h,
//!   1010h/1011h, 1029h, 1200h-12FFh, the PDO parameters 1400h-1BFFh
//!   numbered from 0 as the frame lines do: 1800h is TPDO0, 1F50h-1F57h,
//!   1F80h, ...; an unassigned index as reserved), and the profile objects
//!   of the node's catalogue: Delta-Q then CiA 418 on a Delta-Q charger,
//!   CiA 418/419 on a CiA 419 charger and on the battery node. A node with
//!   no role gets no profile names: bytes only.
//! - Block transfers are reassembled like segmented ones.
//!
//! TIME frames are shown with the UTC date and time they mean after the raw
//! days and milliseconds (` = 1984-01-03T12:00:00.000Z`; JSON `utc`).
//!
//! `--summary` writes the summary after the frames; `--summary-file PATH`
//! writes it to PATH; with `--output csv` and no file it goes to stderr,
//! so the CSV stream stays one CSV.
//!
//! JSON: `{"t","kind":"sdo_transfer","node","role","direction":"upload"|
//! "download","index","sub","status":"complete"|"aborted"|"incomplete",
//! "size","indicated_size","size_indicated","size_mismatch","truncated",
//! "bytes"(hex),"name","value","unit","meaning","text"}` plus
//! `"abort":{"code","meaning","by"}` or `"incomplete":"why"`; `value`,
//! `unit` and `meaning` are null unless the transfer completed.
//!
//! 6010h temperature is decoded per CiA 418 (0.125 degC/bit, no offset):
//! the capture README's DBC adds -40 degC, which the profile does not have.

mod args;
#[cfg(feature = "parquet")]
mod signals_parquet;

use canopen_codec::log::{dataset, input, run, Options, Outcome};
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
    // (`canopen_codec::log::dataset::run_each`); the exit status is the
    // worst of the runs.
    let several = !opts.more_files.is_empty() || opts.dataset.is_some();
    let result = if several {
        dataset::run_each(&opts, &mut out, &mut diag)
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

/// The one log: the file, stdin, or the bundled session (asked for, or
/// no input given with a terminal on stdin).
fn input(opts: &mut Options) -> io::Result<Box<dyn Read>> {
    Ok(match (opts.bundled, opts.file.as_deref()) {
        (Some(_), _) => {
            opts.roles.demo();
            eprintln!("canopen-decode: decoding {SESSION_NAME}");
            Box::new(SESSION.as_bytes())
        }
        (None, Some("-")) => Box::new(io::stdin().lock()),
        (None, Some(path)) => Box::new(
            std::fs::File::open(path)
                .map_err(|e| io::Error::new(e.kind(), format!("{path}: {e}")))?,
        ),
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
