//! Reading a trace file (both programs, `canopen-decode` and
//! `canopen-replay`, read through it): the bytes of a recording in, its
//! frames with their times out, one by one, with what could not be read
//! and the format the file was read as. The formats themselves are parsed
//! by [`crate::trace`] (one parser per line format, the BLF and MF4
//! readers).
//!
//! - Line formats (candump log, candump screen, PCAN `.trc` 1.0-2.1,
//!   Vector ASC, python-can CSV): the input is read in blocks of lines
//!   (module `lines`), each line handed to one `LineParser` (the format
//!   given, or detected from the first line that tells).
//! - Binary formats ([`Binary`]): told by their magic bytes when no line
//!   format is given, or asked for. Vector BLF is read in blocks through
//!   the library's
//!   `BlfReader`, the zlib containers inflated by the caller's
//!   [`Inflate`] (with feature `zlib`, flate2's: [`Zlib`], which the
//!   programs pass; [`NoInflate`] reports each compressed container as
//!   unreadable). pcap and pcapng captures of SocketCAN interfaces are
//!   read in blocks through the library's `PcapReader`.
//!   ASAM MDF 4 bus logging is read record by record through the
//!   library's `Mf4Reader`, each `##DZ` block inflated by the same
//!   [`Inflate`], the frames of its data groups merged by time: a file
//!   that seeks in place ([`read_seekable`]); other input (a pipe, a
//!   gzip-compressed file) into memory when it is at most 1 MiB, else
//!   copied to a temporary file of the system's temporary folder first
//!   and read in place from there (its blocks link to anywhere in the
//!   file, and python-can's and asammdf's describing blocks come after
//!   the data), the file removed at once on Unix (the open file stays
//!   readable), when the reading ends elsewhere.
//! - gzip-compressed input of any format (`.gz`, told by its magic
//!   number `1F 8B`) is decompressed first, with feature `zlib` (flate2's
//!   `MultiGzDecoder`); without it such input is an error that names the
//!   feature.
//!
//! [`read`] hands each [`Item`] to the caller as it comes (memory stays
//! bounded on any input; an MF4 file given by [`read_seekable`] needs no
//! temporary file: the decoder's way); [`frames`] collects the
//! frames of a whole file (the replay's way). Neither panics on any input.

mod blf;
mod lines;
mod mf4;
mod pcap;
mod printable;
mod spill;
#[cfg(feature = "zlib")]
mod zlib;

use std::prelude::rust_2021::*;

use std::fmt;
use std::io::{self, Read, Seek};

use crate::trace::blf::{BlfError, BlfReader};
use crate::trace::mf4::{Mf4Error, Mf4Reader};
use crate::trace::pcap::{Flavor, PcapError};
use crate::trace::{Format, LineParser, OnBus, Record, RxTx, TraceError, TraceFrame, Unsupported};
use crate::{CanFrame, Timestamp};

#[cfg(feature = "zlib")]
pub use crate::trace::inflate::Zlib;
pub use blf::{Inflate, Inflated, NoInflate};
pub use lines::{newline, Block, FindNewline, LineReader, Piece, MAX_LINE};
pub(crate) use printable::Printable;

/// A binary trace format: told from a file's first bytes (its magic
/// number, [`Binary::detect`]) when no line format is given, or named by
/// `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Binary {
    /// Vector BLF (CANalyzer / CANoe, python-can's `BLFWriter`): `LOGG`.
    Blf,
    /// ASAM MDF 4 bus logging (python-can's `MF4Writer`, CANedge, Vector):
    /// `MDF     `.
    Mf4,
    /// pcap (libpcap, tcpdump) with the SocketCAN link type: `A1B2C3D4h`
    /// or `A1B23C4Dh` in either byte order. Read by the same reader as
    /// [`Binary::PcapNg`] (the magic number tells them apart).
    Pcap,
    /// pcapng (Wireshark, dumpcap) with the SocketCAN link type: a
    /// Section Header Block, `0A0D0D0Ah`.
    PcapNg,
}

impl Binary {
    /// The most bytes [`Binary::detect`] looks at.
    pub const HEAD: usize = 8;

    /// The binary format whose magic number `head` (the first bytes of a
    /// file, up to [`Binary::HEAD`] of them) begins with, if any.
    ///
    /// ```
    /// use canopen_codec::log::input::Binary;
    /// assert_eq!(Binary::detect(b"LOGG\x90\0\0\0"), Some(Binary::Blf));
    /// assert_eq!(Binary::detect(b"MDF     "), Some(Binary::Mf4));
    /// assert_eq!(Binary::detect(&[0x0A, 0x0D, 0x0D, 0x0A, 0x1C, 0, 0, 0]), Some(Binary::PcapNg));
    /// assert_eq!(Binary::detect(&[0xD4, 0xC3, 0xB2, 0xA1, 2, 0, 4, 0]), Some(Binary::Pcap));
    /// assert_eq!(Binary::detect(b"(1.5) ca"), None);
    /// ```
    #[must_use]
    pub fn detect(head: &[u8]) -> Option<Binary> {
        if BlfReader::detect(head) {
            return Some(Binary::Blf);
        }
        if Mf4Reader::detect(head) {
            return Some(Binary::Mf4);
        }
        match Flavor::detect(head)? {
            Flavor::Pcap { .. } => Some(Binary::Pcap),
            Flavor::PcapNg => Some(Binary::PcapNg),
        }
    }

    /// Its `--format` name (`blf`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Binary::Blf => "blf",
            Binary::Mf4 => "mf4",
            Binary::Pcap => "pcap",
            Binary::PcapNg => "pcapng",
        }
    }

    /// What the format's items are called, in the plural form the
    /// messages use (`object(s)`).
    #[must_use]
    pub const fn units(self) -> &'static str {
        match self {
            Binary::Blf => "object(s)",
            Binary::Mf4 => "record(s)",
            Binary::Pcap | Binary::PcapNg => "packet(s)",
        }
    }
}

/// How to read a file: the line format (detected when `None`) or a binary
/// format, whether candump screen times are deltas (`-t d`, which the
/// lines do not tell), and the search for a line's end.
#[derive(Clone, Copy, Debug, Default)]
pub struct How {
    /// The line format; `None`: detected from the first line that tells.
    pub format: Option<Format>,
    /// A binary format; `None` (with `format` `None`): detected from the
    /// file's magic number ([`Binary::detect`]).
    pub binary: Option<Binary>,
    /// candump screen times are deltas (`-t d`).
    pub delta_times: bool,
    /// The search for a line's end (`None`: [`newline`]).
    pub find_newline: Option<FindNewline>,
}

impl How {
    /// Read as `format` (a line format), or detected from the content
    /// when `None`.
    #[must_use]
    pub const fn format(format: Option<Format>) -> How {
        How {
            format,
            binary: None,
            delta_times: false,
            find_newline: None,
        }
    }

    /// Read as the binary format `binary`.
    #[must_use]
    pub const fn binary(binary: Binary) -> How {
        How {
            binary: Some(binary),
            ..How::format(None)
        }
    }

    /// The same, with candump screen times read as deltas (`-t d`).
    #[must_use]
    pub const fn with_delta_times(self) -> How {
        How {
            delta_times: true,
            ..self
        }
    }

    /// The way of reading [`FORMAT_NAMES`] gives `name`; `None` for a
    /// name it does not list.
    ///
    /// ```
    /// use canopen_codec::log::input::{Binary, How};
    /// use canopen_codec::trace::Format;
    /// let how = How::named("candump-screen-delta").unwrap();
    /// assert_eq!((how.format, how.delta_times), (Some(Format::CandumpScreen), true));
    /// assert_eq!(How::named("blf").unwrap().binary, Some(Binary::Blf));
    /// assert_eq!(How::named("pcap").unwrap().binary, Some(Binary::Pcap));
    /// assert!(How::named("tcpdump").is_none());
    /// ```
    #[must_use]
    pub fn named(name: &str) -> Option<How> {
        FORMAT_NAMES.iter().find(|f| f.name == name).map(|f| f.how)
    }
}

/// One named way of reading a file: what the programs' `--format` option
/// takes.
#[derive(Clone, Copy, Debug)]
pub struct FormatName {
    /// The name (`candump`, `trc`, ...).
    pub name: &'static str,
    /// What it reads, in a few words (the programs' `--help`).
    pub help: &'static str,
    /// How it reads.
    pub how: How,
}

impl FormatName {
    const fn new(name: &'static str, help: &'static str, how: How) -> Self {
        FormatName { name, help, how }
    }
}

/// Every format by name; a file of none of them given is detected from its
/// content ([`How::default`]). candump's screen output with `-t d` (delta
/// times) cannot be told from its lines, so it has a name of its own.
pub const FORMAT_NAMES: [FormatName; 10] = [
    FormatName::new(
        "candump",
        "candump -L log lines",
        How::format(Some(Format::CandumpLog)),
    ),
    FormatName::new(
        "candump-screen",
        "candump screen output (any -t form but -t d)",
        How::format(Some(Format::CandumpScreen)),
    ),
    FormatName::new(
        "candump-screen-delta",
        "candump screen output with -t d (delta) times",
        How::format(Some(Format::CandumpScreen)).with_delta_times(),
    ),
    FormatName::new(
        "trc",
        "PCAN-View .trc, versions 1.0 to 2.1",
        How::format(Some(Format::PcanTrc)),
    ),
    FormatName::new("asc", "Vector ASC", How::format(Some(Format::VectorAsc))),
    FormatName::new(
        "csv",
        "python-can CSV",
        How::format(Some(Format::PythonCanCsv)),
    ),
    FormatName::new(
        "blf",
        "Vector BLF (binary; detected by its LOGG signature too)",
        How::binary(Binary::Blf),
    ),
    FormatName::new(
        "mf4",
        "ASAM MDF 4 bus logging (binary; detected by its MDF identification too)",
        How::binary(Binary::Mf4),
    ),
    FormatName::new(
        "pcap",
        "pcap of a SocketCAN interface (binary; detected by its magic number too)",
        How::binary(Binary::Pcap),
    ),
    FormatName::new(
        "pcapng",
        "pcapng of SocketCAN interfaces (binary; detected by its magic number too)",
        How::binary(Binary::PcapNg),
    ),
];

/// Where in the file an item is: lines, BLF objects and pcap packets are
/// numbered from 1 in file order (BLF containers and pcapng blocks other
/// than packets not counted), MF4 bus-logging records from 1 in the order
/// read (time order).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum At {
    /// A line of a text trace.
    Line(usize),
    /// A BLF object.
    Object(u64),
    /// Past the last object read (an error of the file's structure).
    AfterObject(u64),
    /// An MF4 bus-logging record.
    Record(u64),
    /// Past the last MF4 record read (an error of the file's structure).
    AfterRecord(u64),
    /// A packet of a pcap or pcapng file (Wireshark's frame number).
    Packet(u64),
    /// Past the last packet read (an error of the file's structure).
    AfterPacket(u64),
}

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            At::Line(n) => write!(f, "line {n}"),
            At::Object(n) => write!(f, "object {n}"),
            At::AfterObject(n) => write!(f, "after object {n}"),
            At::Record(n) => write!(f, "record {n}"),
            At::AfterRecord(n) => write!(f, "after record {n}"),
            At::Packet(n) => write!(f, "packet {n}"),
            At::AfterPacket(n) => write!(f, "after packet {n}"),
        }
    }
}

/// What a line, object or packet read but not decoded was: the line, the
/// BLF object's type, or the packet's link type.
#[derive(Clone, Copy, Debug)]
pub enum Detail<'a> {
    /// The line as read.
    Line(&'a str),
    /// The BLF object's type number.
    ObjectType(u32),
    /// An MF4 bus-logging record (its event type says what it is).
    Record,
    /// The pcap link type of the packet's interface (227: SocketCAN).
    LinkType(u16),
}

impl fmt::Display for Detail<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Detail::Line(l) => f.write_str(l),
            Detail::ObjectType(t) => write!(f, "object type {t}"),
            Detail::Record => f.write_str("MF4 bus-logging record"),
            Detail::LinkType(t) => write!(f, "link type {t}"),
        }
    }
}

/// Why a line or an object could not be read.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Bad<'a> {
    /// A line that is not UTF-8 text.
    NotUtf8,
    /// A line longer than [`MAX_LINE`] bytes.
    TooLong,
    /// The format's parser refused the line.
    Line(TraceError, &'a str),
    /// A malformed BLF object, skipped by its size.
    Object(BlfError),
    /// An error of the BLF file's structure: the rest is not read.
    Structure(BlfError),
    /// A zlib container that does not inflate (the inflater's message):
    /// the rest is not read.
    Inflate(String),
    /// The BLF file ends inside an object or container.
    End(BlfError),
    /// A malformed MF4 record, skipped.
    Mf4Record(Mf4Error),
    /// An error of the MF4 file's structure (or a `##DZ` block that does
    /// not inflate): the rest is not read.
    Mf4Structure(Mf4Error),
    /// A malformed pcap packet, skipped by its length.
    Packet(PcapError),
    /// An error of a pcap file's structure (or its end inside a block or
    /// record): the rest is not read.
    Capture(PcapError),
}

impl fmt::Display for Bad<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Bad::NotUtf8 => f.write_str("not UTF-8 text"),
            Bad::TooLong => write!(f, "longer than {MAX_LINE} bytes"),
            Bad::Line(e, line) => write!(f, "{e}: {line}"),
            Bad::Object(e) | Bad::End(e) => write!(f, "{e}"),
            Bad::Mf4Record(e) => write!(f, "{e}"),
            Bad::Mf4Structure(e) => write!(f, "{e}: the rest is not read"),
            Bad::Packet(e) => write!(f, "{e}"),
            Bad::Capture(e) => write!(f, "{e}: the rest is not read"),
            Bad::Structure(e) => write!(f, "{e}: the rest is not read"),
            Bad::Inflate(e) => write!(f, "container does not inflate ({e}): the rest is not read"),
        }
    }
}

/// One thing the file holds.
#[derive(Clone, Debug)]
pub enum Item<'a> {
    /// A classic CAN frame (BLF frames have no channel name).
    Frame {
        /// Where it is.
        at: At,
        /// The frame.
        frame: TraceFrame<'a>,
    },
    /// A CAN FD frame, an error frame or another event, not decoded.
    Unsupported {
        /// Where it is.
        at: At,
        /// What it is.
        what: Unsupported,
        /// The line, or the object's type.
        detail: Detail<'a>,
        /// Its time, when the reader gives it.
        timestamp: Option<Timestamp>,
        /// What the bus load counts of it, when the reader gives it (a CAN
        /// FD frame's identifier, flags and data).
        on_bus: Option<OnBus>,
    },
    /// What cannot be read (`at: why` is the message for it).
    Bad {
        /// Where it is.
        at: At,
        /// Why it cannot be read.
        why: Bad<'a>,
    },
}

/// What the file was read as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A line format: the lines read and the format (given or detected;
    /// `None` when no line told).
    Lines {
        /// Lines read.
        lines: usize,
        /// The format given or detected.
        format: Option<Format>,
    },
    /// A binary format: its objects or packets read (BLF containers not
    /// counted) and those skipped (neither frames nor events of the bus).
    Binary {
        /// The format.
        binary: Binary,
        /// Objects or packets read.
        objects: u64,
        /// Objects or packets skipped.
        skipped: u64,
    },
}

impl Kind {
    /// What the file's items are called, in the plural form the messages
    /// use: `line(s)`, `object(s)`.
    #[must_use]
    pub const fn units(self) -> &'static str {
        match self {
            Kind::Lines { .. } => "line(s)",
            Kind::Binary { binary, .. } => binary.units(),
        }
    }
}

/// `read as candump`, `read as blf`, `no format detected`.
impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Kind::Lines {
                format: Some(format),
                ..
            } => write!(f, "read as {}", format.name()),
            Kind::Lines { format: None, .. } => f.write_str("no format detected"),
            Kind::Binary { binary, .. } => write!(f, "read as {}", binary.name()),
        }
    }
}

/// What a whole file held, counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Totals {
    /// What the file was read as.
    pub kind: Kind,
    /// Frames read ([`Item::Frame`]).
    pub frames: usize,
    /// Items read but not decoded ([`Item::Unsupported`]).
    pub unsupported: usize,
    /// Lines or objects that could not be read ([`Item::Bad`]).
    pub bad: usize,
}

/// Reads every item of `input` as `how` says and hands each to `each` in
/// file order, BLF zlib containers inflated by `zlib`; an error of `each`
/// ends the read and is returned. Errors of the input are returned; bad
/// lines and objects are items. An MF4 of more than 1 MiB (after gzip)
/// is first copied to a temporary file of `std::env::temp_dir()` (ASAM
/// MDF 4 blocks link to anywhere in the file; the name is removed as soon
/// as it is open on Unix): an error writing it is returned and names it.
pub fn read<F>(
    input: impl Read,
    how: How,
    zlib: &mut dyn Inflate,
    mut each: F,
) -> io::Result<Totals>
where
    F: FnMut(Item<'_>) -> io::Result<()>,
{
    counting(&mut each, |counted| {
        read_file(input, how, zlib, counted, true)
    })
}

/// What `read` gives to `each`, counted, and the totals.
fn counting<F: FnMut(Item<'_>) -> io::Result<()>>(
    each: &mut F,
    read: impl FnOnce(&mut Counted<'_, F>) -> io::Result<Kind>,
) -> io::Result<Totals> {
    let mut counted = Counted {
        each,
        frames: 0,
        unsupported: 0,
        bad: 0,
    };
    let kind = read(&mut counted)?;
    Ok(Totals {
        kind,
        frames: counted.frames,
        unsupported: counted.unsupported,
        bad: counted.bad,
    })
}

/// The first bytes of `input`, up to [`Binary::HEAD`] (fewer at its end):
/// how many.
fn head_of(input: &mut impl Read, head: &mut [u8; Binary::HEAD]) -> io::Result<usize> {
    let mut got = 0;
    while got < head.len() {
        match read_some(input, head.get_mut(got..).unwrap_or(&mut []))? {
            0 => break,
            n => got += n,
        }
    }
    Ok(got)
}

/// Reads every item of the file `file` as [`read`] does, an MF4 file in
/// place: its data blocks read as they are reached (through the library's
/// `SeekSource`), so that memory stays constant in the file's size, where
/// [`read`] copies an MF4 of more than 1 MiB to a temporary file first
/// (its links point anywhere in it). The programs read a file named on
/// their command line so.
pub fn read_seekable<F>(
    mut file: impl Read + Seek,
    how: How,
    zlib: &mut dyn Inflate,
    mut each: F,
) -> io::Result<Totals>
where
    F: FnMut(Item<'_>) -> io::Result<()>,
{
    let start = file.stream_position()?;
    let mut head = [0u8; Binary::HEAD];
    let got = head_of(&mut file, &mut head)?;
    file.seek(io::SeekFrom::Start(start))?;
    let head = head.get(..got).unwrap_or(&[]);
    let mf4 = how.format.is_none()
        && start == 0
        && how.binary.or_else(|| Binary::detect(head)) == Some(Binary::Mf4)
        && !head.starts_with(&GZIP_MAGIC);
    if !mf4 {
        return read(file, how, zlib, each);
    }
    counting(&mut each, |counted| mf4::read_in_place(file, zlib, counted))
}

/// The first bytes of a gzip member (RFC 1952 section 2.3.1).
const GZIP_MAGIC: [u8; 2] = [0x1F, 0x8B];

/// Reads `input` as `how` says, a gzip-compressed one decompressed first
/// (when `gunzip`: once, not a gzip inside it).
fn read_file<F: FnMut(Item<'_>) -> io::Result<()>>(
    mut input: impl Read,
    how: How,
    zlib: &mut dyn Inflate,
    counted: &mut Counted<'_, F>,
    gunzip: bool,
) -> io::Result<Kind> {
    // A gzip or binary file is told by its magic number (the binary
    // formats unless a format is given).
    let mut head = [0u8; Binary::HEAD];
    let got = head_of(&mut input, &mut head)?;
    let head = head.get(..got).unwrap_or(&[]);
    let input = head.chain(input);
    if gunzip && head.starts_with(&GZIP_MAGIC) {
        return read_gzip(input, how, zlib, counted);
    }
    let binary = match how.format {
        None => how.binary.or_else(|| Binary::detect(head)),
        Some(_) => None,
    };
    match binary {
        Some(Binary::Blf) => blf::read(input, zlib, counted),
        Some(Binary::Mf4) => mf4::read(input, zlib, counted),
        Some(b @ (Binary::Pcap | Binary::PcapNg)) => pcap::read(input, b, counted),
        None => read_lines(input, how, counted),
    }
}

/// One `read` of `input` into `buf`, tried again while it is interrupted
/// (`io::ErrorKind::Interrupted`, a signal: not an error of the input, as
/// `Read::read_exact` also takes it): how many bytes came, 0 at the end of
/// the input. Every reader of this module reads its blocks through it.
fn read_some<R: Read + ?Sized>(input: &mut R, buf: &mut [u8]) -> io::Result<usize> {
    loop {
        match input.read(buf) {
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            read => return read,
        }
    }
}

/// A gzip-compressed file (`.gz`, of any format): its members
/// decompressed one after the other by flate2's `MultiGzDecoder`, as
/// `gzip -d` does, and read as `how` says.
#[cfg(feature = "zlib")]
fn read_gzip<F: FnMut(Item<'_>) -> io::Result<()>>(
    input: impl Read,
    how: How,
    zlib: &mut dyn Inflate,
    counted: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut gz = zlib::Gunzip(flate2::read::MultiGzDecoder::new(input));
    read_file(&mut gz as &mut dyn Read, how, zlib, counted, false)
}

/// Without feature `zlib` there is no gzip decompressor: an error that
/// says so.
#[cfg(not(feature = "zlib"))]
fn read_gzip<F: FnMut(Item<'_>) -> io::Result<()>>(
    _: impl Read,
    _: How,
    _: &mut dyn Inflate,
    _: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    Err(io::Error::new(
        io::ErrorKind::Unsupported,
        "the input is gzip-compressed and this build lacks feature `zlib` (flate2's gzip decompressor)",
    ))
}

/// The caller's `each`, counting what it is handed.
struct Counted<'f, F> {
    each: &'f mut F,
    frames: usize,
    unsupported: usize,
    bad: usize,
}

impl<F: FnMut(Item<'_>) -> io::Result<()>> Counted<'_, F> {
    fn give(&mut self, item: Item<'_>) -> io::Result<()> {
        match item {
            Item::Frame { .. } => self.frames += 1,
            Item::Unsupported { .. } => self.unsupported += 1,
            Item::Bad { .. } => self.bad += 1,
        }
        (self.each)(item)
    }
}

fn read_lines<F: FnMut(Item<'_>) -> io::Result<()>>(
    input: impl Read,
    how: How,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut parser = how.format.map_or_else(LineParser::auto, LineParser::new);
    if how.delta_times {
        parser = parser.with_delta_times();
    }
    let mut reader =
        lines::LineReader::with_search(input, how.find_newline.unwrap_or(lines::newline));
    let mut lineno = 0usize;
    while let Some(block) = reader.next_block()? {
        for piece in block {
            lineno += 1;
            let at = At::Line(lineno);
            let why = match piece {
                lines::Piece::Line(line) => Ok(line),
                lines::Piece::NotUtf8 => Err(Bad::NotUtf8),
                lines::Piece::TooLong => Err(Bad::TooLong),
            };
            let line = match why {
                Ok(line) => line,
                Err(why) => {
                    each.give(Item::Bad { at, why })?;
                    continue;
                }
            };
            match parser.parse(line) {
                Ok(Record::Frame(frame)) => each.give(Item::Frame { at, frame })?,
                Ok(Record::Unsupported(what)) => each.give(Item::Unsupported {
                    at,
                    what,
                    detail: Detail::Line(line),
                    timestamp: None,
                    on_bus: None,
                })?,
                Ok(Record::OnBus { timestamp, what }) => each.give(Item::Unsupported {
                    at,
                    what: what.kind(),
                    detail: Detail::Line(line),
                    timestamp,
                    on_bus: Some(what),
                })?,
                Ok(_) => {}
                Err(e) => each.give(Item::Bad {
                    at,
                    why: Bad::Line(e, line),
                })?,
            }
        }
    }
    Ok(Kind::Lines {
        lines: lineno,
        format: parser.format(),
    })
}

/// A frame of a file, owned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timed {
    /// Where it is.
    pub at: At,
    /// Its time, when the trace has one.
    pub timestamp: Option<Timestamp>,
    /// Rx or Tx, when the trace says.
    pub direction: Option<RxTx>,
    /// The frame.
    pub frame: CanFrame,
}

/// Every frame of a file, with what could not be read.
#[derive(Clone, Debug)]
pub struct Frames {
    /// The frames, in file order.
    pub frames: Vec<Timed>,
    /// What the file held, counted.
    pub totals: Totals,
    /// The first line or object that could not be read, as a message
    /// (`line 3: bad identifier: ...`).
    pub first_bad: Option<String>,
    /// The first one read but not decoded, as a message (`line 4: CanFd
    /// not decoded: ...`).
    pub first_unsupported: Option<String>,
}

/// Reads every frame of `input` as `how` says (see [`read`]).
pub fn frames(input: impl Read, how: How, zlib: &mut dyn Inflate) -> io::Result<Frames> {
    let mut frames = Vec::new();
    let mut first_bad = None;
    let mut first_unsupported = None;
    let totals = read(input, how, zlib, |item| {
        match item {
            Item::Frame { at, frame } => frames.push(Timed {
                at,
                timestamp: frame.timestamp,
                direction: frame.direction,
                frame: frame.frame,
            }),
            Item::Bad { at, why } if first_bad.is_none() => {
                first_bad = Some(format!("{at}: {}", Printable(&why)));
            }
            Item::Unsupported {
                at, what, detail, ..
            } if first_unsupported.is_none() => {
                first_unsupported = Some(format!(
                    "{at}: {what:?} not decoded: {}",
                    Printable(&detail)
                ));
            }
            _ => {}
        }
        Ok(())
    })?;
    Ok(Frames {
        frames,
        totals,
        first_bad,
        first_unsupported,
    })
}

#[cfg(test)]
mod tests;
