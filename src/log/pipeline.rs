//! The decoder's pipeline: trace lines in, decoded lines out (words, JSON
//! or CSV), with the SDO observer, the roles, the PDO mappings learned and
//! the summary carried from line to line.

use std::io::{self, Read, Write};
use std::prelude::rust_2021::*;

use crate::od::index::{DEVICE_TYPE, IDENTITY, SDO_SERVER_PARAMETER};
use crate::sdo::{SdoChannel, Side as SdoSide};
use crate::trace::candump::LogLine;
use crate::trace::Format;
use crate::{CanId, NodeId};

use crate::log::input::{self, Item, Kind};
use crate::log::{json, mappings, pdo_learn, report, sdo, words};

/// A block transfer's sub-block segment (CiA 301 SDO block download and
/// upload): byte 0 is a sequence number, not a command specifier.
#[derive(Clone, Copy, Debug)]
pub struct BlockSegment {
    /// The server's node.
    pub node: NodeId,
    /// The sender of the data.
    pub from: SdoSide,
    /// The sequence number (1 to 127).
    pub seqno: u8,
    /// The last segment of the transfer.
    pub last: bool,
    /// The segment's data (7 bytes).
    pub data: crate::sdo::SegmentData,
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
pub fn is_default(channel: SdoChannel) -> bool {
    channel == SdoChannel::default_for(channel.node)
}

/// One frame's line as the output forms see it: the trace line, what it
/// decoded to, the roles, its named PDO fields and the notes on it.
#[derive(Clone, Copy)]
pub struct FrameLine<'a> {
    /// The line as read.
    pub log: &'a crate::trace::candump::LogLine<'a>,
    /// What the frame decoded to.
    pub decoded: &'a Result<crate::Message, crate::DecodeError>,
    /// Which node is which.
    pub roles: &'a Roles,
    /// The PDO's named fields, with where their mapping came from.
    pub fields: Option<&'a (crate::log::mappings::Source, crate::pdo::NamedFields)>,
    /// What the decoder knows besides the message.
    pub notes: &'a Notes,
}

/// What the decoder knows about a line besides its message.
#[derive(Clone, Copy, Default)]
pub struct Notes {
    /// The frame answers a node-guarding request.
    pub guard_reply: bool,
    /// How the frame deviates from CiA 301 (read anyway).
    pub deviation: Option<crate::message::lenient::Deviation>,
    /// The frame is a block transfer's sub-block segment.
    pub block_segment: Option<BlockSegment>,
}

/// Which node is which, for naming Delta-Q codes and roles. A node has a
/// role only from evidence: `--charger-node` / `--battery-node`, its device
/// type (1000h) read by SDO in the log or given by its EDS naming profile
/// 419 (a charger) or 418 (a battery module). A charger is a Delta-Q
/// charger (Delta-Q object names, error labels and default PDOs) only with
/// Delta-Q evidence: `--charger-node`, an EDS whose vendor ID (1018h:01 or
/// `VendorNumber`) is Delta-Q's, or that vendor ID read by SDO in the log;
/// otherwise it is a CiA 419 charger, named with the CiA 419 objects only.
#[derive(Clone, Copy, Default)]
pub struct Roles {
    /// The charger (Delta-Q or CiA 419).
    pub charger: Option<NodeId>,
    /// The CiA 418 battery module.
    pub battery: Option<NodeId>,
    /// The node known to be a Delta-Q device.
    pub deltaq: Option<NodeId>,
}

/// Delta-Q's vendor ID (1018h sub 1).
const DELTAQ_VENDOR_ID: u32 = crate::deltaq::VENDOR_ID;

impl Roles {
    /// `charger`, `battery` or nothing, for `node`.
    pub fn role(&self, node: Option<NodeId>) -> Option<&'static str> {
        match node {
            Some(n) if Some(n) == self.charger => Some("charger"),
            Some(n) if Some(n) == self.battery => Some("battery"),
            _ => None,
        }
    }

    /// The bundled session's nodes (the Delta-Q charger 10, the battery
    /// module 1) unless given.
    pub fn demo(&mut self) {
        self.charger = self.charger.or(NodeId::new(10));
        self.battery = self.battery.or(NodeId::new(1));
        self.deltaq = self.deltaq.or(self.charger);
    }

    /// True when `node` is the charger (Delta-Q or CiA 419).
    pub fn is_charger(&self, node: NodeId) -> bool {
        self.charger == Some(node)
    }

    /// True when `node` is the charger and a Delta-Q one.
    pub fn is_deltaq_charger(&self, node: NodeId) -> bool {
        self.is_charger(node) && self.deltaq == Some(node)
    }

    /// True when `node` is the battery module (and not also the charger).
    pub fn is_battery(&self, node: NodeId) -> bool {
        self.battery == Some(node) && self.charger != Some(node)
    }

    /// Learns from a completed upload: of 1000h (device type) a role, the
    /// profile number in bits 0-15, 418 a battery module, 419 a charger; of
    /// 1018h sub 1 (vendor ID) Delta-Q's, that the node is a Delta-Q
    /// device (a charger, unless it has another role). Roles given on the
    /// command line or learned before are kept. Returns what was learned,
    /// in words.
    pub fn learn(&mut self, report: &sdo::Report) -> Option<String> {
        if !matches!(report.end, sdo::End::Complete)
            || !matches!(report.direction, sdo::Direction::Upload)
        {
            return None;
        }
        match (report.index, report.sub, &report.bytes[..]) {
            (DEVICE_TYPE, 0, [a, b, ..]) => {
                let (name, given) =
                    self.give_by_profile(report.node, u16::from_le_bytes([*a, *b]))?;
                given.then(|| format!("the {name} (its device type, {DEVICE_TYPE:04X}h, says so)"))
            }
            (IDENTITY, 1, [a, b, c, d]) => {
                let vendor = u32::from_le_bytes([*a, *b, *c, *d]);
                self.give_deltaq(report.node, vendor).then(|| {
                    format!(
                        "a Delta-Q device (its vendor ID, {IDENTITY:04X}h:01, is {vendor:08X}h)"
                    )
                })
            }
            _ => None,
        }
    }

    /// Makes `node` the Delta-Q device when `vendor` is Delta-Q's vendor ID
    /// and no other node is; it becomes the charger unless it has a role.
    /// True when this changed anything.
    fn give_deltaq(&mut self, node: NodeId, vendor: u32) -> bool {
        if vendor != DELTAQ_VENDOR_ID || self.deltaq.is_some_and(|d| d != node) {
            return false;
        }
        let before = (self.charger, self.deltaq);
        self.deltaq = Some(node);
        if self.charger.is_none() && self.battery != Some(node) {
            self.charger = Some(node);
        }
        before != (self.charger, self.deltaq)
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

/// What a run does: the output form, what it prints, which node is which,
/// the PDO mappings and SDO channels it knows, and the files it writes
/// besides its output (each option of `canopen-decode` is one field:
/// docs/DECODER.md). [`Options::default`] is the program with no option.
#[derive(Clone)]
pub struct Options {
    /// `--json`: one JSON object per frame.
    pub json: bool,
    /// `--output csv`.
    pub csv: bool,
    /// `--summary`, `--summary-only`, `--check`, `--summary-file`.
    pub summary: bool,
    /// `--summary-file PATH`: the summary goes there instead of stdout (or
    /// stderr, where a CSV stream is on stdout).
    pub summary_file: Option<String>,
    /// The frames are printed (not with `--summary-only`).
    pub frames: bool,
    /// `--check`: the caller exits 3 when a problem is open at the end.
    pub check: bool,
    /// Which node is which, as given.
    pub roles: Roles,
    /// The PDO mappings given, and whether the defaults apply.
    pub pdos: mappings::Mappings,
    /// The log's file name (the report's title).
    pub file: Option<String>,
    /// The logs after the first (each decoded on its own).
    pub more_files: Vec<String>,
    /// `--bundled session`.
    pub bundled: Option<&'static str>,
    /// `--format`: the trace format (detected when absent) and `-t d` times.
    pub format: Option<Format>,
    /// `--format blf`: the input is Vector BLF (also detected by `LOGG`).
    pub blf: bool,
    /// candump screen times are deltas (`-t d`).
    pub delta_times: bool,
    /// `--strict`: frames that deviate from CiA 301 are malformed.
    pub strict: bool,
    /// `--sdo NODE=RXID,TXID`: SDO channels besides the default ones.
    pub sdo_channels: Vec<SdoChannel>,
    /// `--eds NODE=FILE`: device descriptions of nodes.
    pub eds: Vec<(NodeId, String)>,
    /// `--no-cache`: format every line anew (for checking the line cache).
    pub no_cache: bool,
    /// `--signals PATH`: the PDO fields as signals (CSV).
    pub signals: Option<String>,
    /// `--dbc PATH`: the PDO mappings in use as a DBC file.
    pub dbc: Option<String>,
    /// `--report FILE.html`: the session as an HTML page.
    pub report: Option<String>,
    /// Makes the inflater of a BLF file's zlib containers (`None`: none,
    /// [`input::NoInflate`]).
    pub inflater: Option<fn() -> Box<dyn input::Inflate>>,
    /// Writes `--signals` to a `.parquet` path (`None`: such a path is an
    /// error at the end of the run). The program passes its Parquet writer.
    pub parquet: Option<crate::log::signals::ParquetWriter>,
    /// Finds a line's end in a text trace (`None`:
    /// [`input::newline`]); the program passes memchr's.
    pub find_newline: Option<input::FindNewline>,
}

impl Default for Options {
    /// The program with no option: words, every frame, the default PDOs.
    fn default() -> Self {
        Options {
            json: false,
            csv: false,
            summary: false,
            summary_file: None,
            frames: true,
            check: false,
            roles: Roles::default(),
            pdos: mappings::Mappings {
                given: Vec::new(),
                defaults: true,
            },
            file: None,
            more_files: Vec::new(),
            bundled: None,
            format: None,
            blf: false,
            delta_times: false,
            strict: false,
            sdo_channels: Vec::new(),
            eds: Vec::new(),
            no_cache: false,
            signals: None,
            dbc: None,
            report: None,
            inflater: None,
            parquet: None,
            find_newline: None,
        }
    }
}

/// How the decoding of one log ended.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outcome {
    /// Lines (or BLF objects) that are neither a frame nor a known event.
    pub bad: usize,
    /// The summary found a problem still open at the end.
    pub open: bool,
    /// Not one CAN frame in an input that had lines (or a BLF file that
    /// had a header): said on `diag`.
    pub no_frame: bool,
}

impl Outcome {
    /// Exit status 1: bad lines, or nothing read as a frame.
    #[must_use]
    pub fn failed(&self) -> bool {
        self.bad > 0 || self.no_frame
    }

    /// Both logs' outcomes, as of one run over several logs.
    #[must_use]
    pub fn and(self, other: Outcome) -> Outcome {
        Outcome {
            bad: self.bad + other.bad,
            open: self.open || other.open,
            no_frame: self.no_frame || other.no_frame,
        }
    }
}

/// Decodes every line of `input` into `out`, with what is wrong with a
/// line (and what `--eds` took) on `diag` (stderr in the program); returns
/// how it ended ([`Outcome`]).
pub fn run(
    input: impl Read,
    out: &mut impl Write,
    diag: &mut impl Write,
    opts: &Options,
) -> io::Result<Outcome> {
    let mut run = crate::log::decoding::Decoding::new(opts, diag)?;
    let how = input::How {
        format: opts.format,
        blf: opts.blf,
        delta_times: opts.delta_times,
        find_newline: opts.find_newline,
    };
    let mut zlib = opts.inflater.map_or_else(
        || Box::new(input::NoInflate) as Box<dyn input::Inflate>,
        |make| make(),
    );
    let totals = input::read(input, how, zlib.as_mut(), |item| match item {
        Item::Frame { at, frame } => {
            let line = LogLine {
                timestamp: frame.timestamp,
                interface: frame.channel,
                frame: frame.frame,
            };
            run.frame(&at, &line, frame.direction, out, diag)
        }
        Item::Unsupported { at, what, detail } => {
            run.unsupported(&at, what, &detail, diag);
            Ok(())
        }
        Item::Bad { at, why } => {
            let _ = writeln!(diag, "{at}: {why}");
            run.bad += 1;
            Ok(())
        }
    })?;
    if let Kind::Blf { skipped, .. } = totals.kind {
        if skipped > 0 {
            let _ = writeln!(
                diag,
                "canopen-decode: {skipped} other BLF object(s) skipped (not CAN frames)"
            );
        }
    }
    let (bad, open) = run.finish(out, diag)?;
    let no_frame = match totals.kind {
        _ if totals.frames > 0 => false,
        Kind::Lines { lines: 0, .. } => false,
        kind @ Kind::Lines { lines, .. } => {
            let _ = writeln!(
                diag,
                "canopen-decode: none of the {lines} line(s) is a CAN frame ({kind}; --format names one)"
            );
            true
        }
        kind @ Kind::Blf { objects, .. } => {
            let _ = writeln!(
                diag,
                "canopen-decode: none of the {objects} object(s) is a CAN frame ({kind})"
            );
            true
        }
    };
    Ok(Outcome {
        bad,
        open,
        no_frame,
    })
}

/// Reads the EDS or DCF of `node` (`--eds NODE=FILE`): its PDOs (COB-IDs
/// and mappings, `$NODEID` resolved) decode that node's PDO frames, its
/// server SDO parameter (1200h) adds the SDO channel when it is not the
/// default (not when either COB-ID has bit 31 set: not valid), its device
/// type (1000h) of profile 418 or 419 gives the node its role unless one was
/// given, and a Delta-Q vendor ID (1018h sub 1 or `VendorNumber`) makes it
/// a Delta-Q device. Says what it took on `diag`.
pub fn load_eds(
    node: NodeId,
    path: &str,
    roles: &mut Roles,
    sdo: &mut sdo::Tracker,
    learned: &mut pdo_learn::Learned,
    diag: &mut impl Write,
) -> io::Result<()> {
    use crate::eds::{eval_int, parse_bytes};
    use crate::pdo::PdoDirection;
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
    if let Some(device_type) = int(DEVICE_TYPE, 0) {
        let profile = (device_type & 0xFFFF) as u16;
        said.push(match roles.give_by_profile(node, profile) {
            Some((role, _)) => format!("device type {device_type:08X}h: the {role}"),
            None => format!("device type {device_type:08X}h (profile {profile})"),
        });
    }
    // The vendor ID: 1018h sub 1, else the file's VendorNumber.
    if let Some(vendor) = int(IDENTITY, 1).or(eds.device_info.vendor_number) {
        if vendor == DELTAQ_VENDOR_ID
            && (roles.give_deltaq(node, vendor) || roles.deltaq == Some(node))
        {
            said.push(format!("vendor ID {vendor:08X}h: Delta-Q"));
        }
    }
    let profile = if roles.is_battery(node) {
        Some(crate::cia418::BATTERY_MODULE_CATALOGUE)
    } else if roles.is_deltaq_charger(node) {
        Some(crate::deltaq::CHARGER_CATALOGUE)
    } else if roles.is_charger(node) {
        Some(crate::cia419::CHARGER_CATALOGUE)
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
    // CiA 301, SDO server parameter (1200h): bit 31 of a COB-ID set means
    // the SDO is not valid, so it adds no channel.
    let ids = (int(SDO_SERVER_PARAMETER, 1), int(SDO_SERVER_PARAMETER, 2));
    if let (Some(rx), Some(tx)) = ids {
        if (rx | tx) & (1 << 31) != 0 {
            said.push(format!(
                "SDO server parameter {SDO_SERVER_PARAMETER:04X}h not valid (COB-IDs {rx:08X}h/{tx:08X}h, bit 31 set): no channel"
            ));
        }
    }
    let valid = ids
        .0
        .zip(ids.1)
        .filter(|(rx, tx)| (rx | tx) & (1 << 31) == 0);
    if let Some((rx, tx)) = valid {
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
    let _ = writeln!(
        diag,
        "canopen-decode: node {node} from {path}: {}",
        if said.is_empty() {
            "nothing the decoder uses".to_string()
        } else {
            said.join("; ")
        }
    );
    Ok(())
}

/// A finished SDO transfer on the report's timeline, with its line in words.
pub fn page_transfer(
    page: &mut report::Collector,
    report: &sdo::Report,
    roles: &Roles,
    learned: &pdo_learn::Learned,
) {
    let mut text = String::new();
    words::transfer(&mut text, report, roles, learned.catalogue(report.node));
    page.transfer(report, &text);
}

/// Writes the extra line of a finished SDO transfer (its objects named by
/// the node's EDS catalogue `eds` where it has one); `pdo_note` says how it
/// changed a PDO's configuration.
pub fn transfer(
    out: &mut String,
    report: &sdo::Report,
    json: bool,
    roles: &Roles,
    eds: Option<crate::pdo::Catalogue>,
    pdo_note: Option<&str>,
) {
    let mut text = String::new();
    if json {
        json::transfer(&mut text, report, roles, eds, pdo_note);
    } else {
        words::transfer(&mut text, report, roles, eds);
        if let Some(note) = pdo_note {
            text.push_str(" [");
            text.push_str(note);
            text.push(']');
        }
    }
    out.push_str(&text);
    out.push('\n');
}
