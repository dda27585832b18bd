//! Real-world CAN trace formats, one line at a time, without allocation:
//! candump `-L` log lines, candump screen output, PCAN-View `.trc`
//! (versions 1.0, 1.1, 2.0 and 2.1), Vector ASC and python-can CSV.
//!
//! A [`LineParser`] is fed the lines of one trace in order (some formats
//! carry state in their header: the `.trc` version and start time, the ASC
//! number base) and gives one [`Record`] per line: a frame with what the
//! line says about it, a header or comment line ([`Record::Meta`]), or a
//! line about something this crate does not decode ([`Record::Unsupported`]:
//! CAN FD and error frames, reported per line and never fatal; or
//! [`Record::OnBus`] when the line gives what the bus load needs of them:
//! their time and an FD frame's identifier, flags and data). Lines that
//! cannot be read are a typed [`TraceError`]. Every parser is total: any
//! text gives one of these, never a panic.
//!
//! [`Format::detect`] recognises a format from one line; a parser made with
//! [`LineParser::auto`] detects it from the first line that tells.
//!
//! Vector BLF files are binary, not lines: [`blf::BlfReader`] reads them
//! from the byte chunks the caller feeds (the zlib containers inflated by
//! the caller), with the same [`Unsupported`] kinds for what it skips;
//! so does [`pcap::PcapReader`] for pcap and pcapng captures of SocketCAN
//! interfaces.
//!
//! ```
//! use canopen_codec::trace::{Format, LineParser, Record};
//! let mut p = LineParser::auto();
//! let lines = [
//!     ";$FILEVERSION=1.1",
//!     "     1)      1841.6  Rx         018A  8  74 13 45 4E 70 00 00 00",
//! ];
//! assert!(matches!(p.parse(lines[0]), Ok(Record::Meta)));
//! let Ok(Record::Frame(f)) = p.parse(lines[1]) else { panic!() };
//! assert_eq!(p.format(), Some(Format::PcanTrc));
//! assert_eq!(f.frame.to_string(), "18A#7413454E70000000");
//! assert_eq!(f.timestamp.unwrap().as_micros(), 1_841_600);
//! ```

mod asc;
pub mod blf;
pub mod candump;
mod csv;
mod fd;
mod fields;
#[cfg(feature = "alloc")]
pub mod inflate;
#[cfg(feature = "alloc")]
pub mod mf4;
pub mod pcap;
mod screen;
mod trc;

use crate::clock::Timestamp;
use crate::frame::CanFrame;

pub use fd::{FdFrame, FD_LENGTHS};

/// The trace formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// candump `-L` log lines: `(1700000000.123456) can0 18A#7413454E`.
    CandumpLog,
    /// candump screen output, with or without `-t a|d|z|A` timestamps:
    /// `  can0  18A   [8]  74 13 45 4E 70 00 00 00`.
    CandumpScreen,
    /// PCAN-View `.trc`; the `;$FILEVERSION` header line tells the version
    /// (1.1 when absent).
    PcanTrc,
    /// Vector ASC: `   1.234567 1  18A             Rx   d 8 74 13 ...`.
    VectorAsc,
    /// python-can CSV: `timestamp,arbitration_id,extended,remote,error,dlc,data`
    /// (data base64-encoded, as python-can's `CSVWriter` writes it).
    PythonCanCsv,
}

impl Format {
    /// The format one line shows, if it tells (a bare candump `ID#DATA`
    /// frame counts as the candump log format).
    #[must_use]
    pub fn detect(line: &str) -> Option<Format> {
        let t = line.trim();
        if t.starts_with(';') || trc::looks_like_frame(t) {
            return Some(Format::PcanTrc);
        }
        if t.starts_with("date ")
            || t.starts_with("base ")
            || t.starts_with("Begin Triggerblock")
            || t.starts_with("Begin TriggerBlock")
            || asc::looks_like_frame(t)
        {
            return Some(Format::VectorAsc);
        }
        if t.starts_with("timestamp,arbitration_id") {
            return Some(Format::PythonCanCsv);
        }
        if screen::looks_like_frame(t) {
            return Some(Format::CandumpScreen);
        }
        if candump_log(t).is_ok() {
            return Some(Format::CandumpLog);
        }
        None
    }

    /// The name used by `--format` options: `candump`, `candump-screen`,
    /// `trc`, `asc`, `csv`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Format::CandumpLog => "candump",
            Format::CandumpScreen => "candump-screen",
            Format::PcanTrc => "trc",
            Format::VectorAsc => "asc",
            Format::PythonCanCsv => "csv",
        }
    }

    /// The format of a [`name`](Self::name).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Format> {
        [
            Format::CandumpLog,
            Format::CandumpScreen,
            Format::PcanTrc,
            Format::VectorAsc,
            Format::PythonCanCsv,
        ]
        .into_iter()
        .find(|f| f.name() == name)
    }
}

/// Whether the trace says a frame was received or transmitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RxTx {
    /// Received (`Rx`).
    Rx,
    /// Transmitted by the logging node (`Tx`).
    Tx,
}

/// A frame of a trace with what its line says about it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TraceFrame<'a> {
    /// The time the line gives: UNIX time for candump `-L`, `-t a`, `-t A`,
    /// python-can CSV and a `.trc` with a `$STARTTIME`; time since the start
    /// of the trace otherwise (ASC, `.trc` without a start time, candump
    /// `-t z`, and candump `-t d` read with
    /// [`LineParser::with_delta_times`], whose deltas are summed).
    pub timestamp: Option<Timestamp>,
    /// The channel or interface (`can0`, `1`), if the line names one.
    pub channel: Option<&'a str>,
    /// Rx/Tx, if the line says.
    pub direction: Option<RxTx>,
    /// The frame.
    pub frame: CanFrame,
}

/// A line this crate reads but does not decode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Unsupported {
    /// A CAN FD frame.
    CanFd,
    /// An error frame or a bus-error event.
    ErrorFrame,
    /// Another event line of the format (status, statistics, markers).
    Event,
    /// A CAN XL frame (a SocketCAN capture's).
    CanXl,
    /// A packet of a capture whose link type is not SocketCAN (pcap,
    /// pcapng).
    LinkType,
}

/// A frame on the bus the crate does not decode, as far as a trace tells
/// it: what a bus load counts of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OnBus {
    /// A CAN FD frame.
    Fd(FdFrame),
    /// An error frame (ISO 11898-1:2015 section 10.4.4).
    ErrorFrame,
}

impl OnBus {
    /// What the line is, as [`Record::Unsupported`] would say.
    #[must_use]
    pub const fn kind(&self) -> Unsupported {
        match self {
            OnBus::Fd(_) => Unsupported::CanFd,
            OnBus::ErrorFrame => Unsupported::ErrorFrame,
        }
    }
}

/// What one line of a trace is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Record<'a> {
    /// A classic CAN frame.
    Frame(TraceFrame<'a>),
    /// A header, comment or blank line.
    Meta,
    /// A line about something the crate does not decode.
    Unsupported(Unsupported),
    /// A CAN FD or error frame (not decoded) with its time, when the line
    /// gives it.
    OnBus {
        /// The line's time (as [`TraceFrame::timestamp`]).
        timestamp: Option<Timestamp>,
        /// The frame.
        what: OnBus,
    },
}

/// Why a line of a trace could not be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TraceError {
    /// No format has been recognised yet and this line does not tell.
    #[error("the line does not match any known trace format")]
    UnknownFormat,
    /// A field the format needs is missing.
    #[error("a field is missing")]
    MissingField,
    /// The time field is not a decimal time.
    #[error("bad timestamp")]
    BadTimestamp,
    /// The identifier is not a hex number of at most 29 bits.
    #[error("bad identifier")]
    BadId,
    /// The length is not 0..=8 or does not match the data bytes.
    #[error("bad length")]
    BadDlc,
    /// A data byte is not two hex digits (or base64 for CSV).
    #[error("bad data bytes")]
    BadData,
    /// A CAN FD length (above 8) where a classic frame was expected.
    #[error("CAN FD frame")]
    CanFd,
    /// The candump log line did not parse.
    #[error("{0}")]
    Candump(crate::trace::candump::CandumpError),
}

/// The format-specific state of a trace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct State {
    /// `.trc`: the version (major, minor) from `$FILEVERSION`.
    trc_version: (u8, u8),
    /// `.trc`: `$STARTTIME` as UNIX microseconds.
    trc_start_us: Option<u64>,
    /// `.trc` 2.x: the column letters (`$COLUMNS`), 0 = unset.
    trc_columns: [u8; 12],
    /// ASC: identifiers in decimal (`base dec`).
    asc_decimal: bool,
    /// ASC: `timestamps relative`: each line's time is the time since the
    /// line before.
    asc_relative: bool,
    /// ASC with relative times: the time so far.
    asc_clock_us: u64,
    /// candump screen `-t d`: accumulate deltas.
    screen_delta: bool,
    /// candump screen `-t d`: the time so far.
    screen_clock_us: u64,
}

/// Parses the lines of one trace in order. See the [module docs](self).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineParser {
    format: Option<Format>,
    state: State,
}

impl LineParser {
    /// A parser for `format`.
    #[must_use]
    pub fn new(format: Format) -> Self {
        LineParser {
            format: Some(format),
            state: State {
                // A file without `;$FILEVERSION` is 1.0 (PEAK's PCAN-View and
                // python-can read it so).
                trc_version: (1, 0),
                ..State::default()
            },
        }
    }

    /// A parser that detects the format from the first line that tells.
    #[must_use]
    pub fn auto() -> Self {
        LineParser {
            format: None,
            state: State {
                // A file without `;$FILEVERSION` is 1.0 (PEAK's PCAN-View and
                // python-can read it so).
                trc_version: (1, 0),
                ..State::default()
            },
        }
    }

    /// candump screen output made with `-t d`: its times are deltas, not
    /// times since the start (the lines look the same).
    #[must_use]
    pub fn with_delta_times(mut self) -> Self {
        self.state.screen_delta = true;
        self
    }

    /// The format, once known.
    #[must_use]
    pub const fn format(&self) -> Option<Format> {
        self.format
    }

    /// Parses the next line.
    pub fn parse<'a>(&mut self, line: &'a str) -> Result<Record<'a>, TraceError> {
        let line = if matches!(line.as_bytes().last(), Some(b'\r' | b'\n')) {
            line.trim_end_matches(['\r', '\n'])
        } else {
            line
        };
        if trim(line).is_empty() {
            return Ok(Record::Meta);
        }
        let format = match self.format {
            Some(f) => f,
            None => {
                let f = Format::detect(line).ok_or(TraceError::UnknownFormat)?;
                self.format = Some(f);
                f
            }
        };
        match format {
            Format::CandumpLog => candump_log(line),
            Format::CandumpScreen => screen::parse(line, &mut self.state),
            Format::PcanTrc => trc::parse(line, &mut self.state),
            Format::VectorAsc => asc::parse(line, &mut self.state),
            Format::PythonCanCsv => csv::parse(line),
        }
    }
}

/// `line.trim()`, answered from the two end bytes for the usual line (this
/// is the decoder's hot path).
fn trim(line: &str) -> &str {
    match line.as_bytes() {
        [first, .., last] if first.is_ascii_graphic() && last.is_ascii_graphic() => line,
        _ => line.trim(),
    }
}

/// A candump `-L` line, with the direction flag python-can's writer (and
/// candump `-x`) appends (`R`, `T`) accepted.
fn candump_log(line: &str) -> Result<Record<'_>, TraceError> {
    let t = trim(line);
    // Only the last two bytes decide (this is the decoder's hot path).
    let (body, direction) = if let Some(b) = t.strip_suffix(" R") {
        (b, Some(RxTx::Rx))
    } else if let Some(b) = t.strip_suffix(" T") {
        (b, Some(RxTx::Tx))
    } else {
        (t, None)
    };
    use crate::trace::candump::{parse_line, parse_on_bus, CandumpError};
    match parse_line(body) {
        Ok(l) => Ok(Record::Frame(TraceFrame {
            timestamp: l.timestamp,
            channel: l.interface,
            direction,
            frame: l.frame,
        })),
        Err(CandumpError::CanFd | CandumpError::ErrorFrame) => match parse_on_bus(body) {
            Ok((timestamp, what)) => Ok(Record::OnBus { timestamp, what }),
            Err(e) => Err(TraceError::Candump(e)),
        },
        Err(e) => Err(TraceError::Candump(e)),
    }
}

#[cfg(test)]
mod tests;
