//! What a decoding run is told and how it ends ([`Options`], [`Outcome`]),
//! the EDS files it reads ([`load_eds`]) and the lines of finished SDO
//! transfers; the run itself is [`run`](super::run), over a
//! [`Decoding`](super::Decoding).

use std::io::{self, Write};
use std::prelude::rust_2021::*;

use crate::od::index::{DEVICE_TYPE, IDENTITY, SDO_SERVER_PARAMETER};
use crate::sdo::SdoChannel;
use crate::trace::Format;
use crate::{CanId, NodeId};

use crate::log::frame_line::is_default;
use crate::log::input;
use crate::log::roles::{Roles, DELTAQ_VENDOR_ID};
use crate::log::{json, mappings, pdo_learn, report, sdo, words};

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
    /// `--bitrate BPS`: the bus's bit rate for the summary's bus load
    /// (`None`: 250 kbit/s, said to be assumed).
    pub bitrate: Option<u32>,
    /// `--data-bitrate BPS`: the data phase's bit rate of CAN FD frames
    /// with BRS set (`None`: 2 Mbit/s, said to be assumed).
    pub data_bitrate: Option<u32>,
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
    /// `--format blf` (or another binary format): the input is of that
    /// format (also detected by its magic number when no format is given).
    pub binary: Option<input::Binary>,
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
    /// `--dataset FORMAT`, or logs named by a folder or a glob: `--signals
    /// PATH` is a folder holding one dataset partitioned by log, its parts
    /// in this format, even for one log (several logs always make one, its
    /// parts' format from PATH's name: [`crate::log::dataset`]).
    pub dataset: Option<crate::log::dataset::PartFormat>,
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
            bitrate: None,
            data_bitrate: None,
            roles: Roles::default(),
            pdos: mappings::Mappings {
                given: Vec::new(),
                defaults: true,
            },
            file: None,
            more_files: Vec::new(),
            bundled: None,
            format: None,
            binary: None,
            delta_times: false,
            strict: false,
            sdo_channels: Vec::new(),
            eds: Vec::new(),
            no_cache: false,
            signals: None,
            dataset: None,
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
