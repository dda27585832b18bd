//! `canopen-decode`, the CANopen log decoder: reads a CAN trace and prints
//! every frame in words or as JSON lines. Install it with
//! `cargo install --path . --features cli`; in the repository `cargo decode`
//! runs it (an alias of `cargo run --features cli --bin canopen-decode --`).
//!
//! ```text
//! canopen-decode [--json] [--format F] [--charger-node N] [--battery-node N]
//!     [--pdo COBID=INDEX:SUB:BITS,...]... [--no-default-pdos] [--pdo-capture-mapping]
//!     [--sdo NODE=RXID,TXID]... [FILE]
//! ```
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
//! (marked `[from the EDS]`), named with the file's object names; its 1200h
//! adds its SDO channel when not the default; a device type (1000h) of
//! profile 418 or 419 gives the node its role. PDO mappings and COB-IDs
//! written or read by SDO in the log (1400h-1BFFh) apply to the PDOs that
//! follow, and the transfer's line says so (`[TPDO1 of node 5 maps ...]`).
//!
//! The trace format is detected from its first telling line, or given with
//! `--format`: `candump` (candump `-L` log lines), `candump-screen`
//! (candump screen output; `candump-screen-delta` for `-t d` times),
//! `trc` (PCAN-View 1.0-2.1), `asc` (Vector ASC), `csv` (python-can CSV)
//! (`canopen_codec::trace`). Header and comment lines are skipped; CAN FD
//! and error frames are reported on stderr, line by line, and do not count
//! as bad lines.
//!
//! With no FILE it reads stdin; with no FILE and a terminal on stdin it
//! decodes the bundled session of the crate's own virtual charger and
//! battery module (`tests/data/virtual-session.log`: normal start,
//! heartbeat loss with E-0-3-2, recovery) so a new user sees it work.
//! Malformed lines (and frames that do not fit their CANopen object, lines
//! that are not UTF-8 text and lines longer than 64 KiB) are reported on
//! stderr with their line number; the run goes on. Exit status:
//! 0 all lines good, 1 some line bad, 2 usage or I/O error (a malformed
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
//!   objects are read from the dictionary of the node the COB-ID belongs to:
//!   the battery node's is CiA 418, any other node's the Delta-Q charger's.
//! - Without `--pdo` for a COB-ID, the defaults apply to nodes with a role:
//!   the Delta-Q charger's default PDOs on the charger's COB-IDs, the
//!   CiA 418 battery-module defaults on the battery module's. A node has a
//!   role only from evidence: `--charger-node` / `--battery-node`, or its
//!   1000h read by SDO in the log (profile 419: charger, 418: battery
//!   module; reported on a line of its own). `--pdo-capture-mapping` and
//!   the bundled session imply charger 10 and battery module 1.
//!   `--no-default-pdos` turns them off. A frame with no known mapping is
//!   printed raw, as before.
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
//! - The value is named and interpreted where the object is known: 1000h
//!   (CiA 418 optional PDOs when its profile is 418), 1001h, 1003h (with the
//!   Delta-Q code on the charger node), 1008h-100Ah strings, 1016h-1018h,
//!   PDO communication and mapping objects 1400h-1BFFh (numbered from 0 as
//!   the frame lines do: 1800h is TPDO0), and the profile objects of the
//!   node's catalogue: Delta-Q then CiA 418 on the charger node, CiA 418 on
//!   the battery node and on nodes with no role. Otherwise bytes only.
//! - Block transfers are followed (so their data frames are not misread) but
//!   not reassembled: only their aborts are reported.
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
mod csv;
mod json;
mod line_cache;
mod line_reader;
mod pdo_args;
mod pdo_learn;
mod sdo;
mod sdo_value;
mod summary;
mod time_column;
mod words;

use std::io::{self, IsTerminal, Read, Write};
use std::process::ExitCode;

use canopen_codec::candump::LogLine;
use canopen_codec::sdo::{Observed, SdoChannel, Side as SdoSide};
use canopen_codec::trace::{Format, LineParser, Record};
use canopen_codec::{CanId, Message, NodeId};

const SESSION: &str = include_str!("../../../tests/data/virtual-session.log");
const SESSION_NAME: &str =
    "tests/data/virtual-session.log (bundled session of the virtual charger and battery module)";

/// A block transfer's sub-block segment (CiA 301 SDO block download and
/// upload): byte 0 is a sequence number, not a command specifier.
#[derive(Clone, Copy, Debug)]
pub struct BlockSegment {
    /// The server's node.
    pub node: NodeId,
    /// The sender of the data.
    pub from: SdoSide,
    pub seqno: u8,
    pub last: bool,
    pub data: canopen_codec::sdo::SegmentData,
}

impl std::fmt::Display for BlockSegment {
    /// `SDO block segment seq 3 to node 2: 41 20 72 65 61 6C 6C`
    /// (`seq 5, last`; `from node 2` when the server sends).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SDO block segment seq {}", self.seqno)?;
        if self.last {
            f.write_str(", last")?;
        }
        let to = match self.from {
            SdoSide::Client => "to",
            SdoSide::Server => "from",
        };
        write!(f, " {to} node {}:", self.node)?;
        for b in self.data.as_slice() {
            write!(f, " {b:02X}")?;
        }
        Ok(())
    }
}

/// The default SDO channel of its node (Message::decode names those).
fn is_default(channel: SdoChannel) -> bool {
    channel == SdoChannel::default_for(channel.node)
}

/// What the decoder knows about a line besides its message.
#[derive(Clone, Copy, Default)]
pub struct Notes {
    /// The frame answers a node-guarding request.
    pub guard_reply: bool,
    /// How the frame deviates from CiA 301 (read anyway).
    pub deviation: Option<canopen_codec::lenient::Deviation>,
    /// The frame is a block transfer's sub-block segment.
    pub block_segment: Option<BlockSegment>,
}

/// Which node is which, for naming Delta-Q codes and roles. A node has a
/// role only from evidence: `--charger-node` / `--battery-node`, or its
/// device type (1000h) read by SDO in the log naming profile 419 (a
/// charger) or 418 (a battery module).
#[derive(Clone, Copy, Default)]
pub struct Roles {
    pub charger: Option<NodeId>,
    pub battery: Option<NodeId>,
}

impl Roles {
    pub fn role(&self, node: Option<NodeId>) -> Option<&'static str> {
        match node {
            Some(n) if Some(n) == self.charger => Some("charger"),
            Some(n) if Some(n) == self.battery => Some("battery"),
            _ => None,
        }
    }

    /// The bundled session's nodes (charger 10, battery module 1) unless given.
    fn demo(&mut self) {
        self.charger = self.charger.or(NodeId::new(10));
        self.battery = self.battery.or(NodeId::new(1));
    }

    /// True when `node` is the charger.
    pub fn is_charger(&self, node: NodeId) -> bool {
        self.charger == Some(node)
    }

    /// True when `node` is the battery module (and not also the charger).
    pub fn is_battery(&self, node: NodeId) -> bool {
        self.battery == Some(node) && self.charger != Some(node)
    }

    /// Learns a role from a completed upload of 1000h (device type): the
    /// profile number in bits 0-15, 418 a battery module, 419 a charger.
    /// Roles given on the command line or learned before are kept.
    fn learn(&mut self, report: &sdo::Report) -> Option<&'static str> {
        if (report.index, report.sub) != (0x1000, 0)
            || !matches!(report.end, sdo::End::Complete)
            || !matches!(report.direction, sdo::Direction::Upload)
        {
            return None;
        }
        let [a, b, ..] = report.bytes[..] else {
            return None;
        };
        let (name, given) = self.give_by_profile(report.node, u16::from_le_bytes([a, b]))?;
        given.then_some(name)
    }

    /// The role a device type's profile (bits 0-15 of 1000h) names, 418 a
    /// battery module and 419 a charger, given to `node` unless another
    /// node has it already: the role's name and whether it was given.
    fn give_by_profile(&mut self, node: NodeId, profile: u16) -> Option<(&'static str, bool)> {
        let (slot, name) = match profile {
            418 => (&mut self.battery, "battery"),
            419 => (&mut self.charger, "charger"),
            _ => return None,
        };
        let given = slot.is_none();
        if given {
            *slot = Some(node);
        }
        Some((name, given))
    }
}

pub struct Options {
    pub json: bool,
    /// `--output csv`.
    pub csv: bool,
    /// `--summary`, `--summary-only`, `--check`.
    pub summary: bool,
    pub frames: bool,
    pub check: bool,
    pub roles: Roles,
    pub pdos: pdo_args::Mappings,
    pub file: Option<String>,
    /// `--bundled session`.
    pub bundled: Option<&'static str>,
    /// `--format`: the trace format (detected when absent) and `-t d` times.
    pub format: Option<Format>,
    pub delta_times: bool,
    /// `--strict`: frames that deviate from CiA 301 are malformed.
    pub strict: bool,
    /// `--sdo NODE=RXID,TXID`: SDO channels besides the default ones.
    pub sdo_channels: Vec<SdoChannel>,
    /// `--eds NODE=FILE`: device descriptions of nodes.
    pub eds: Vec<(NodeId, String)>,
    /// `--no-cache`: format every line anew (for checking the line cache).
    pub no_cache: bool,
}

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
    let input: Box<dyn Read> = match (opts.bundled, opts.file.as_deref()) {
        (Some(_), _) => {
            opts.roles.demo();
            eprintln!("canopen-decode: decoding {SESSION_NAME}");
            Box::new(SESSION.as_bytes())
        }
        (None, Some("-")) => Box::new(io::stdin().lock()),
        (None, Some(path)) => match std::fs::File::open(path) {
            Ok(f) => Box::new(f),
            Err(e) => {
                eprintln!("canopen-decode: {path}: {e}");
                return ExitCode::from(2);
            }
        },
        (None, None) if io::stdin().is_terminal() => {
            opts.roles.demo();
            eprintln!("canopen-decode: no input given; decoding {SESSION_NAME}");
            Box::new(SESSION.as_bytes())
        }
        (None, None) => Box::new(io::stdin().lock()),
    };
    match run(input, &opts) {
        Ok((_, true)) if opts.check => {
            eprintln!("canopen-decode: problems open at the end of the log (--check)");
            ExitCode::from(3)
        }
        Ok((0, _)) => ExitCode::SUCCESS,
        Ok((bad, _)) => {
            eprintln!("canopen-decode: {bad} bad line(s)");
            ExitCode::from(1)
        }
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("canopen-decode: {e}");
            ExitCode::from(2)
        }
    }
}

/// Decodes every line; returns the number of bad lines and whether the
/// summary found a problem still open at the end.
fn run(input: Box<dyn Read>, opts: &Options) -> io::Result<(usize, bool)> {
    let mut roles = opts.roles;
    let mut summary = summary::Summary::default();
    let stdout = io::stdout();
    let mut out = stdout.lock();
    let mut bad = 0;
    // The output not written yet: lines are appended here and written in
    // blocks of about `PAGE` bytes (one write per block, no copy per line).
    const PAGE: usize = 64 * 1024;
    let mut text = String::with_capacity(2 * PAGE);
    let mut times = time_column::TimeColumn::new(if opts.json || opts.csv { 0 } else { 10 });
    let mut sdo = sdo::Tracker::default();
    let mut learned = pdo_learn::Learned::default();
    let mut cache = line_cache::LineCache::new(!opts.no_cache);
    for (node, path) in &opts.eds {
        load_eds(*node, path, &mut roles, &mut sdo, &mut learned)?;
    }
    for &channel in &opts.sdo_channels {
        sdo.add_channel(channel)
            .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, format!("--sdo: {e}")))?;
    }
    let mut reader = opts.format.map_or_else(LineParser::auto, LineParser::new);
    if opts.csv {
        text.push_str(csv::HEADER);
        text.push('\n');
    }
    // Nodes with a node-guarding request not answered yet.
    let mut guarding = [false; 128];
    if opts.delta_times {
        reader = reader.with_delta_times();
    }
    let mut lines = line_reader::LineReader::new(input);
    let mut lineno = 0usize;
    while let Some(block) = lines.next_block()? {
        for piece in block {
            lineno += 1;
            let line = match piece {
                line_reader::Piece::Line(line) => line,
                line_reader::Piece::NotUtf8 => {
                    eprintln!("line {lineno}: not UTF-8 text");
                    bad += 1;
                    continue;
                }
                line_reader::Piece::TooLong => {
                    eprintln!("line {lineno}: longer than {} bytes", line_reader::MAX_LINE);
                    bad += 1;
                    continue;
                }
            };
            let parsed = match reader.parse(line) {
                Ok(Record::Frame(f)) => LogLine {
                    timestamp: f.timestamp,
                    interface: f.channel,
                    frame: f.frame,
                },
                Ok(Record::Unsupported(what)) => {
                    eprintln!("line {lineno}: {what:?} not decoded: {line}");
                    continue;
                }
                Ok(_) => continue,
                Err(e) => {
                    eprintln!("line {lineno}: {e}: {line}");
                    bad += 1;
                    continue;
                }
            };
            // The SDO observer first: a frame on a declared SDO channel is SDO,
            // and a block transfer's sub-block segment is no command.
            let seen = sdo.handle(parsed.timestamp, &parsed.frame);
            let (decoded, deviation) = if opts.strict {
                (Message::decode(&parsed.frame), None)
            } else {
                match Message::decode_lenient(&parsed.frame) {
                    Ok((m, d)) => (Ok(m), d),
                    Err(e) => (Err(e), None),
                }
            };
            let mut block_segment = None;
            let decoded = match seen {
                Observed::Request { channel, request } if !is_default(channel) => {
                    Ok(Message::SdoRequest {
                        node: channel.node,
                        sdo: request,
                    })
                }
                Observed::Response { channel, response } if !is_default(channel) => {
                    Ok(Message::SdoResponse {
                        node: channel.node,
                        sdo: response,
                    })
                }
                Observed::BlockSegment {
                    channel,
                    from,
                    seqno,
                    last,
                    data,
                } => {
                    block_segment = Some(BlockSegment {
                        node: channel.node,
                        from,
                        seqno,
                        last,
                        data,
                    });
                    decoded
                }
                _ => decoded,
            };
            if let (Err(e), None) = (&decoded, block_segment) {
                eprintln!("line {lineno}: frame {} does not decode: {e}", parsed.frame);
                bad += 1;
            }
            // A reply on 700h + node after a remote request there is a guarding
            // reply, whatever its toggle.
            let guard_reply = match &decoded {
                Ok(Message::NodeGuardRequest { node, .. }) => {
                    if let Some(g) = guarding.get_mut(usize::from(node.raw())) {
                        *g = true;
                    }
                    false
                }
                Ok(Message::Heartbeat { node, .. }) => guarding
                    .get_mut(usize::from(node.raw()))
                    .is_some_and(std::mem::take),
                _ => false,
            };
            let notes = Notes {
                guard_reply,
                deviation,
                block_segment,
            };
            if let (true, Ok(msg)) = (opts.summary, &decoded) {
                summary.frame(
                    parsed.timestamp,
                    parsed.frame.id().raw(),
                    msg,
                    guard_reply,
                    &roles,
                );
            }
            if opts.frames {
                if opts.csv {
                    csv::time(&mut text, &mut times, parsed.timestamp);
                } else if opts.json {
                    json::time(&mut text, &mut times, parsed.timestamp);
                } else {
                    words::time(&mut text, &mut times, parsed.timestamp);
                }
                // The text after the time depends on the frame alone for these
                // (and on the roles and mappings, which clear the cache).
                let cacheable = !guard_reply
                    && block_segment.is_none()
                    && matches!(
                        decoded,
                        Ok(Message::Tpdo { .. }
                            | Message::Rpdo { .. }
                            | Message::Heartbeat { .. }
                            | Message::Emcy { .. }
                            | Message::Nmt(_)
                            | Message::Sync(_)
                            | Message::Time(_)
                            | Message::Unknown(_))
                    );
                if !(cacheable && cache.get(&parsed.frame, &mut text)) {
                    let start = text.len();
                    let fields = decoded
                        .as_ref()
                        .ok()
                        .and_then(|m| opts.pdos.fields(&parsed.frame, m, &roles, &learned));
                    let args = (&parsed, &decoded, &roles, fields.as_ref(), &notes);
                    if opts.csv {
                        csv::rest(&mut text, args.0, args.1, args.2, args.3, args.4);
                    } else if opts.json {
                        json::rest(&mut text, args.0, args.1, args.2, args.3, args.4);
                    } else {
                        words::rest(&mut text, args.0, args.1, args.2, args.3, args.4);
                    }
                    if cacheable {
                        cache.put(&parsed.frame, text.get(start..).unwrap_or(""));
                    }
                }
                text.push('\n');
            }
            for report in sdo.reports() {
                if opts.summary {
                    summary.transfer(&report);
                }
                let role_learned = roles.learn(&report);
                let pdo_note = learned.transfer(&report);
                if role_learned.is_some() || pdo_note.is_some() {
                    cache.clear();
                }
                // CSV rows are frames only.
                if !opts.frames || opts.csv {
                    continue;
                }
                transfer(&mut text, &report, opts.json, &roles, pdo_note.as_deref());
                if let Some(role) = role_learned {
                    let what = if opts.json {
                        format!(
                            "{{\"kind\":\"role\",\"node\":{},\"role\":\"{role}\"}}",
                            report.node
                        )
                    } else {
                        format!(
                            "node {} is the {role} (its device type, 1000h, says so)",
                            report.node
                        )
                    };
                    text.push_str(&what);
                    text.push('\n');
                }
            }
            if text.len() >= PAGE {
                out.write_all(text.as_bytes())?;
                text.clear();
            }
        }
    }
    for report in sdo.finish() {
        summary.transfer(&report);
        if opts.frames && !opts.csv {
            transfer(&mut text, &report, opts.json, &roles, None);
        }
    }
    let mut open = false;
    if opts.summary {
        if opts.json {
            open = summary.json(&mut text, &roles);
            text.push('\n');
        } else {
            open = summary.words(&mut text, &roles);
        }
    }
    out.write_all(text.as_bytes())?;
    out.flush()?;
    Ok((bad, open))
}

/// Writes the extra line of a finished SDO transfer.
/// Reads the EDS or DCF of `node` (`--eds NODE=FILE`): its PDOs (COB-IDs
/// and mappings, `$NODEID` resolved) decode that node's PDO frames, its
/// server SDO parameter (1200h) adds the SDO channel when it is not the
/// default, and its device type (1000h) of profile 418 or 419 gives the node
/// its role unless one was given. Says what it took on stderr.
fn load_eds(
    node: NodeId,
    path: &str,
    roles: &mut Roles,
    sdo: &mut sdo::Tracker,
    learned: &mut pdo_learn::Learned,
) -> io::Result<()> {
    use canopen_codec::eds::{eval_int, parse_bytes};
    use canopen_codec::pdo::PdoDirection;
    let invalid = |e: String| io::Error::new(io::ErrorKind::InvalidInput, e);
    let bytes = std::fs::read(path).map_err(|e| invalid(format!("--eds {path}: {e}")))?;
    let eds = parse_bytes(&bytes).map_err(|e| invalid(format!("--eds {path}: {e}")))?;
    let int = |index: u16, sub: u8| {
        eds.entry(index, sub)
            .and_then(|e| e.value())
            .and_then(|v| eval_int(v, Some(node.raw())).ok())
            .and_then(|v| u32::try_from(v).ok())
    };
    let mut said = Vec::new();
    if let Some(device_type) = int(0x1000, 0) {
        let profile = (device_type & 0xFFFF) as u16;
        said.push(match roles.give_by_profile(node, profile) {
            Some((role, _)) => format!("device type {device_type:08X}h: the {role}"),
            None => format!("device type {device_type:08X}h (profile {profile})"),
        });
    }
    let profile = if roles.is_battery(node) {
        Some(canopen_codec::cia418::BATTERY_MODULE_CATALOGUE)
    } else if roles.is_charger(node) {
        Some(canopen_codec::deltaq::CHARGER_CATALOGUE)
    } else {
        None
    };
    learned.name_objects(node, &eds, profile);
    let mut mapped = Vec::new();
    for d in eds.pdos(node) {
        let tx = d.direction == PdoDirection::Transmit;
        if let Some(id) =
            learned.preset(node, tx, d.number, d.cob_id.map(|c| c.to_u32()), &d.entries)
        {
            mapped.push(format!(
                "{}{} on {id:03X}h",
                if tx { "TPDO" } else { "RPDO" },
                d.number
            ));
        }
    }
    if !mapped.is_empty() {
        said.push(format!("PDOs mapped: {}", mapped.join(", ")));
    }
    let ids = (int(0x1200, 1), int(0x1200, 2));
    if let (Some(rx), Some(tx)) = ids {
        let id = |raw: u32| u16::try_from(raw & 0x7FF).ok().and_then(CanId::standard);
        if let (Some(request), Some(response)) = (id(rx), id(tx)) {
            let channel = SdoChannel {
                node,
                request,
                response,
            };
            if !is_default(channel) {
                sdo.add_channel(channel)
                    .map_err(|e| invalid(format!("--eds {path}: SDO channel: {e}")))?;
                said.push(format!("SDO on {:03X}h/{:03X}h", rx & 0x7FF, tx & 0x7FF));
            }
        }
    }
    eprintln!(
        "canopen-decode: node {node} from {path}: {}",
        if said.is_empty() {
            "nothing the decoder uses".to_string()
        } else {
            said.join("; ")
        }
    );
    Ok(())
}

/// Writes the extra line of a finished SDO transfer; `pdo_note` says how it
/// changed a PDO's configuration.
fn transfer(
    out: &mut String,
    report: &sdo::Report,
    json: bool,
    roles: &Roles,
    pdo_note: Option<&str>,
) {
    let mut text = String::new();
    if json {
        json::transfer(&mut text, report, roles);
        if let (Some(note), Some(body)) = (pdo_note, text.strip_suffix('}')) {
            let mut with = body.to_string();
            json::key(&mut with, "pdo_config");
            json::string(&mut with, note);
            with.push('}');
            text = with;
        }
    } else {
        words::transfer(&mut text, report, roles);
        if let Some(note) = pdo_note {
            text.push_str(" [");
            text.push_str(note);
            text.push(']');
        }
    }
    out.push_str(&text);
    out.push('\n');
}
