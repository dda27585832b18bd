//! One decoding run's state, fed frame by frame whatever the trace format
//! (text lines or BLF objects): the SDO observer, the roles, the PDO
//! mappings learned, the summary and the output not written yet.

use std::io::{self, Read, Write};
use std::prelude::rust_2021::*;

use crate::sdo::Observed;
use crate::trace::candump::LogLine;
use crate::trace::{OnBus, RxTx, Unsupported};
use crate::Timestamp;
use crate::{CanId, Message};

use crate::log::dataset::{self, PartFormat};
use crate::log::input::{self, Item, Kind, Printable};
use crate::log::summary::Decoded;
use crate::log::{
    csv, dbc, is_default, json, line_cache, load_eds, mappings, page_transfer, pdo_learn, report,
    sdo, signals, summary, time_column, transfer, words, BlockSegment, FrameLine, Notes, Options,
    Outcome, Roles,
};

/// The output is appended to a text and written in blocks of about this
/// many bytes (one write per block, no copy per line).
const PAGE: usize = 64 * 1024;

/// What a run carries from frame to frame.
pub struct Decoding<'o> {
    opts: &'o Options,
    roles: Roles,
    summary: summary::Summary,
    /// The summary is collected (for `--summary` or the report's page).
    collect: bool,
    page: Option<report::Collector>,
    /// Bad lines (or objects) so far.
    pub bad: usize,
    text: String,
    times: time_column::TimeColumn,
    sdo: sdo::Tracker,
    learned: pdo_learn::Learned,
    cache: line_cache::LineCache,
    signals: Option<signals::Signals>,
    dbc: Option<dbc::Dbc>,
    /// Nodes with a node-guarding request not answered yet.
    guarding: [bool; 128],
    /// Frames decoded: a log none of whose lines is a frame is an error.
    pub frames: usize,
    /// Read but not decoded: CAN FD frames, error frames, other events,
    /// CAN XL frames, packets of another link type.
    unsupported: [usize; 5],
}

impl<'o> Decoding<'o> {
    /// A run with the roles, EDS files, SDO channels and outputs `opts`
    /// give (what `--eds` took said on `diag`).
    pub fn new(opts: &'o Options, diag: &mut impl Write) -> io::Result<Self> {
        let mut roles = opts.roles;
        let mut sdo = sdo::Tracker::default();
        let mut learned = pdo_learn::Learned::default();
        for (node, path) in &opts.eds {
            load_eds(*node, path, &mut roles, &mut sdo, &mut learned, diag)?;
        }
        for &channel in &opts.sdo_channels {
            sdo.add_channel(channel)
                .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, format!("--sdo: {e}")))?;
        }
        let signals = opts
            .signals
            .as_deref()
            .map(signals::Signals::create)
            .transpose()?;
        let mut text = String::with_capacity(2 * PAGE);
        if opts.csv {
            text.push_str(csv::HEADER);
            text.push('\n');
        }
        Ok(Decoding {
            opts,
            roles,
            summary: summary::Summary::with_bitrates(opts.bitrate, opts.data_bitrate),
            // The report's page starts with the summary: collected for either.
            collect: opts.summary || opts.report.is_some(),
            page: opts
                .report
                .as_ref()
                .map(|_| report::Collector::with_bitrate(opts.bitrate)),
            bad: 0,
            text,
            times: time_column::TimeColumn::new(if opts.json || opts.csv { 0 } else { 10 }),
            sdo,
            learned,
            cache: line_cache::LineCache::new(!opts.no_cache),
            signals,
            dbc: opts.dbc.as_ref().map(|_| dbc::Dbc::default()),
            guarding: [false; 128],
            frames: 0,
            unsupported: [0; 5],
        })
    }

    /// A frame or event read but not decoded (CAN FD, error frames, other
    /// events), said on `diag` at `at` and counted for the end of the run;
    /// CAN FD frames (`on_bus`: when the reader gives them) and error
    /// frames go to the bus load at `t` (`None`: the last frame's time).
    pub fn unsupported(
        &mut self,
        at: &dyn std::fmt::Display,
        what: Unsupported,
        (t, on_bus): (Option<Timestamp>, Option<&OnBus>),
        detail: &dyn std::fmt::Display,
        diag: &mut impl Write,
    ) {
        let _ = writeln!(diag, "{at}: {what:?} not decoded: {}", Printable(detail));
        if self.collect {
            let bus = match (on_bus, what) {
                (Some(w), _) => Some(*w),
                (None, Unsupported::ErrorFrame) => Some(OnBus::ErrorFrame),
                (None, Unsupported::CanFd) => {
                    self.summary.fd_frame_not_read();
                    None
                }
                _ => None,
            };
            if let Some(w) = bus {
                let bit_times = self.summary.on_bus(t, &w);
                let id = match w {
                    OnBus::Fd(f) => Some(f.id()),
                    _ => None,
                };
                if let Some(page) = self.page.as_mut() {
                    page.bus_frame(t, id, bit_times);
                }
            }
        }
        let slot = match what {
            Unsupported::CanFd => 0,
            Unsupported::ErrorFrame => 1,
            Unsupported::CanXl => 3,
            Unsupported::LinkType => 4,
            _ => 2,
        };
        if let Some(n) = self.unsupported.get_mut(slot) {
            *n += 1;
        }
    }

    /// Decodes one frame (`at` names its place in the trace for `diag`;
    /// `direction` is what the trace says of it, Rx or Tx, if anything).
    pub fn frame(
        &mut self,
        at: &dyn std::fmt::Display,
        parsed: &LogLine<'_>,
        direction: Option<RxTx>,
        out: &mut impl Write,
        diag: &mut impl Write,
    ) -> io::Result<()> {
        self.frames += 1;
        let Decoding {
            opts,
            roles,
            summary,
            collect,
            page,
            bad,
            text,
            times,
            sdo,
            learned,
            cache,
            signals,
            dbc,
            guarding,
            frames: _,
            unsupported: _,
        } = self;
        let (opts, collect) = (*opts, *collect);
        if collect {
            let bit_times = summary.bus_frame(parsed.timestamp, &parsed.frame);
            if let Some(page) = page.as_mut() {
                page.bus_frame(parsed.timestamp, Some(parsed.frame.id()), bit_times);
            }
        }
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
            let _ = writeln!(diag, "{at}: frame {} does not decode: {e}", parsed.frame);
            *bad += 1;
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
        let seen = decoded.as_ref().ok().map(|msg| Decoded {
            t: parsed.timestamp,
            cob_id: parsed.frame.id().raw(),
            frame: &parsed.frame,
            msg,
            guard_reply,
            roles,
        });
        if let (true, Some(seen)) = (collect, &seen) {
            summary.frame(seen);
        }
        if signals.is_some() || dbc.is_some() {
            let applied = decoded
                .as_ref()
                .ok()
                .and_then(|m| opts.pdos.mapping(&parsed.frame, m, roles, learned));
            if let (Some((source, catalogue, mapping)), CanId::Standard(id)) =
                (applied, parsed.frame.id())
            {
                if let Some(s) = signals.as_mut() {
                    let fields = catalogue.decode(&mapping, parsed.frame.data());
                    s.frame(parsed.timestamp, id, catalogue, &fields)?;
                }
                if let Some(note) = dbc
                    .as_mut()
                    .and_then(|d| d.frame(id, source, catalogue, mapping))
                {
                    let _ = writeln!(diag, "{note}");
                }
            }
        }
        if let (Some(page), Some(seen)) = (page.as_mut(), &seen) {
            let fields = match seen.msg {
                Message::Tpdo { .. } | Message::Rpdo { .. } => {
                    opts.pdos.fields(&parsed.frame, seen.msg, roles, learned)
                }
                _ => None,
            };
            page.frame(seen, fields.as_ref().map(|(_, f)| f));
        }
        if opts.frames {
            if opts.csv {
                csv::time(text, times, parsed.timestamp);
            } else if opts.json {
                json::time(text, times, parsed.timestamp);
                // Before the cached text: the same frame may come either way.
                json::rxtx(text, direction);
            } else {
                words::time(text, times, parsed.timestamp);
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
            if !(cacheable && cache.get(&parsed.frame, text)) {
                let start = text.len();
                let fields = decoded
                    .as_ref()
                    .ok()
                    .and_then(|m| opts.pdos.fields(&parsed.frame, m, roles, learned));
                let line = FrameLine {
                    log: parsed,
                    decoded: &decoded,
                    roles,
                    fields: fields.as_ref(),
                    notes: &notes,
                };
                if opts.csv {
                    csv::rest(text, &line);
                } else if opts.json {
                    json::rest(text, &line);
                } else {
                    words::rest(text, &line);
                }
                if cacheable {
                    cache.put(&parsed.frame, text.get(start..).unwrap_or(""));
                }
            }
            text.push('\n');
        }
        for report in sdo
            .has_reports()
            .then(|| sdo.reports())
            .into_iter()
            .flatten()
        {
            if collect {
                summary.transfer(&report);
            }
            if let Some(page) = page.as_mut() {
                page_transfer(page, &report, roles, learned);
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
            let eds = learned.catalogue(report.node);
            transfer(text, &report, opts.json, roles, eds, pdo_note.as_deref());
            if let Some(said) = role_learned {
                let what = if opts.json {
                    format!(
                            "{{\"kind\":\"role\",\"node\":{},\"role\":{},\"deltaq\":{},\"text\":\"node {} is {said}\"}}",
                            report.node,
                            roles
                                .role(Some(report.node))
                                .map_or("null".to_string(), |r| format!("\"{r}\"")),
                            roles.deltaq == Some(report.node),
                            report.node
                        )
                } else {
                    format!("node {} is {said}", report.node)
                };
                text.push_str(&what);
                text.push('\n');
            }
        }
        if text.len() >= PAGE {
            out.write_all(text.as_bytes())?;
            text.clear();
        }
        Ok(())
    }

    /// Ends the run: the transfers still open, the summary, the report,
    /// the signals and the DBC; returns the number of bad lines and whether
    /// the summary found a problem still open at the end.
    pub fn finish(self, out: &mut impl Write, diag: &mut impl Write) -> io::Result<(usize, bool)> {
        let Decoding {
            opts,
            roles,
            mut summary,
            mut page,
            bad,
            mut text,
            mut sdo,
            learned,
            signals,
            dbc,
            unsupported,
            ..
        } = self;
        let [fd, errors, events, xl, links] = unsupported;
        if fd + errors + events + xl + links > 0 {
            let mut more = String::new();
            if xl > 0 {
                more += &format!(", {xl} CAN XL frame(s)");
            }
            if links > 0 {
                more += &format!(", {links} packet(s) of another link type than SocketCAN");
            }
            let _ = writeln!(
                diag,
                "canopen-decode: read, not decoded: {fd} CAN FD frame(s), {errors} error frame(s), {events} other event(s){more}"
            );
        }
        for report in sdo.finish() {
            summary.transfer(&report);
            if let Some(page) = page.as_mut() {
                page_transfer(page, &report, &roles, &learned);
            }
            if opts.frames && !opts.csv {
                let eds = learned.catalogue(report.node);
                transfer(&mut text, &report, opts.json, &roles, eds, None);
            }
        }
        let mut open = false;
        // The summary follows the frames in words and JSON; it never enters a
        // CSV stream (stderr then), and `--summary-file` takes it in any form.
        let mut report = String::new();
        if let (Some(page), Some(path)) = (&page, &opts.report) {
            let mut words = String::new();
            open = summary.words(&mut words, &roles);
            let silences = summary.silences();
            let title = opts
                .file
                .as_deref()
                .or(opts.bundled.map(|_| "the bundled session"))
                .unwrap_or("stdin");
            let html = page.page(title, &words, &silences, &roles);
            std::fs::write(path, html.as_bytes())
                .map_err(|e| io::Error::new(e.kind(), format!("--report {path}: {e}")))?;
        }
        if opts.summary {
            if opts.json {
                open = summary.json(&mut report, &roles);
                report.push('\n');
            } else {
                open = summary.words(&mut report, &roles);
            }
        }
        match (&opts.summary_file, opts.csv) {
            (Some(path), _) => {
                std::fs::write(path, report.as_bytes())
                    .map_err(|e| io::Error::new(e.kind(), format!("--summary-file {path}: {e}")))?;
            }
            (None, true) => diag.write_all(report.as_bytes())?,
            (None, false) => text.push_str(&report),
        }
        out.write_all(text.as_bytes())?;
        out.flush()?;
        if let Some(s) = signals {
            let (rows, columns) = s.finish(opts.parquet)?;
            let _ = writeln!(
                diag,
                "canopen-decode: --signals: {rows} row(s), {columns} signal(s)"
            );
        }
        if let (Some(mut d), Some(path)) = (dbc, &opts.dbc) {
            for (id, mapping) in &opts.pdos.given {
                let catalogue = mappings::catalogue_of(
                    crate::cob_id::classify_standard(*id).node(),
                    &roles,
                    &learned,
                );
                d.given(*id, catalogue, *mapping);
            }
            let (messages, text) = d.text();
            std::fs::write(path, text)
                .map_err(|e| io::Error::new(e.kind(), format!("--dbc {path}: {e}")))?;
            let _ = writeln!(diag, "canopen-decode: --dbc: {messages} message(s)");
        }
        Ok((bad, open))
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
    run_with(|h, z, each| input::read(input, h, z, each), out, diag, opts)
}

/// [`run`] on the file at `path` (an error opening it names it), read so
/// that an MF4 file is read in place ([`input::read_seekable`]), its
/// memory constant in its size: the programs' way with a file.
pub fn run_path(
    path: &str,
    out: &mut impl Write,
    diag: &mut impl Write,
    opts: &Options,
) -> io::Result<Outcome> {
    let file =
        std::fs::File::open(path).map_err(|e| io::Error::new(e.kind(), format!("{path}: {e}")))?;
    run_with(
        |h, z, e| input::read_seekable(file, h, z, e),
        out,
        diag,
        opts,
    )
}

/// The items a reading gives.
type Each<'e> = &'e mut dyn FnMut(Item<'_>) -> io::Result<()>;

/// [`run`] with the reading of the input given.
fn run_with(
    read: impl FnOnce(input::How, &mut dyn input::Inflate, Each<'_>) -> io::Result<input::Totals>,
    out: &mut impl Write,
    diag: &mut impl Write,
    opts: &Options,
) -> io::Result<Outcome> {
    let mut run = crate::log::decoding::Decoding::new(opts, diag)?;
    let how = input::How {
        format: opts.format,
        binary: opts.binary,
        delta_times: opts.delta_times,
        find_newline: opts.find_newline,
    };
    let mut zlib = opts.inflater.map_or_else(
        || Box::new(input::NoInflate) as Box<dyn input::Inflate>,
        |make| make(),
    );
    let totals = read(how, zlib.as_mut(), &mut |item| match item {
        Item::Frame { at, frame } => {
            let line = LogLine {
                timestamp: frame.timestamp,
                interface: frame.channel,
                frame: frame.frame,
            };
            run.frame(&at, &line, frame.direction, out, diag)
        }
        Item::Unsupported {
            at,
            what,
            detail,
            timestamp,
            on_bus,
        } => {
            run.unsupported(&at, what, (timestamp, on_bus.as_ref()), &detail, diag);
            Ok(())
        }
        Item::Bad { at, why } => {
            let _ = writeln!(diag, "{at}: {}", Printable(&why));
            run.bad += 1;
            Ok(())
        }
    })?;
    if let Kind::Binary {
        binary, skipped, ..
    } = totals.kind
    {
        if skipped > 0 {
            let _ = writeln!(
                diag,
                "canopen-decode: {skipped} other {} {} skipped (not CAN frames)",
                binary.name().to_uppercase(),
                binary.units()
            );
        }
    }
    let (bad, open) = run.finish(out, diag)?;
    let no_frame = match totals.kind {
        _ if totals.frames > 0 => false,
        // An empty input (a 0-byte file, a pipe closed before its first
        // line) is read as nothing: said, never a silent empty summary.
        Kind::Lines { lines: 0, .. } => {
            let _ = writeln!(
                diag,
                "canopen-decode: the input is empty: no line, no frame"
            );
            true
        }
        kind @ Kind::Lines { lines, .. } => {
            let _ = writeln!(
                diag,
                "canopen-decode: none of the {lines} line(s) is a CAN frame ({kind}; --format names one)"
            );
            true
        }
        kind @ Kind::Binary { objects, .. } => {
            let _ = writeln!(
                diag,
                "canopen-decode: none of the {objects} {} is a CAN frame ({kind})",
                kind.units()
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

/// Decodes several logs (or one as a dataset): [`Options::file`] then
/// [`Options::more_files`], each on its own with [`run`], one after the
/// other, its name on `diag` and its frames on `out`. With
/// [`Options::signals`] the signals of all of them form one dataset
/// partitioned by log ([`dataset::parts`](crate::log::dataset::parts); Parquet parts when the folder's name or
/// [`Options::dataset`] says so). How they all ended ([`Outcome::and`]); an
/// error for stdin among them, for `--dbc` (the mappings of several logs
/// may differ), for a partition that cannot be made, and for a log that
/// cannot be opened (naming it).
///
/// ```
/// use canopen_codec::log::{run_each, Options};
///
/// let dir = std::env::temp_dir().join(format!("canopen-run-each-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let (a, b) = (dir.join("a.log"), dir.join("b.log"));
/// std::fs::write(&a, "(1.000000) can0 70A#05\n")?;
/// std::fs::write(&b, "(2.000000) can0 70A#7F\nnot a frame\n")?;
/// let opts = Options {
///     file: Some(a.display().to_string()),
///     more_files: vec![b.display().to_string()],
///     ..Options::default()
/// };
/// let (mut out, mut diag) = (Vec::new(), Vec::new());
/// let outcome = run_each(&opts, &mut out, &mut diag)?;
/// assert_eq!(outcome.bad, 1);
/// assert_eq!(String::from_utf8_lossy(&out).lines().count(), 2);
/// let stdin = Options { more_files: vec!["-".into()], ..opts };
/// assert!(run_each(&stdin, &mut out, &mut diag).is_err());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), std::io::Error>(())
/// ```
pub fn run_each(
    opts: &Options,
    out: &mut impl Write,
    diag: &mut impl Write,
) -> io::Result<Outcome> {
    let mut files = vec![opts.file.clone().unwrap_or_default()];
    files.extend(opts.more_files.iter().cloned());
    if files.iter().any(|f| f == "-" || f.is_empty()) {
        return Err(io::Error::other(
            "stdin cannot be one of several logs nor a dataset",
        ));
    }
    if opts.dbc.is_some() {
        return Err(io::Error::other(
            "--dbc takes one log (the mappings of several may differ)",
        ));
    }
    // Each log's partition, its name unique and free of path separators.
    let parts = match &opts.signals {
        Some(dir) => {
            let root = std::path::Path::new(dir);
            let format = opts.dataset.unwrap_or(PartFormat::of(root));
            let parts = dataset::parts(root, &files, format).map_err(io::Error::other)?;
            parts
                .iter()
                .map(|p| Some(p.display().to_string()))
                .collect()
        }
        None => vec![None; files.len()],
    };
    let mut all = Outcome::default();
    for (file, part) in files.iter().zip(parts) {
        let mut one = opts.clone();
        one.file = Some(file.clone());
        one.more_files.clear();
        one.signals = part;
        writeln!(diag, "canopen-decode: {file}")?;
        all = all.and(run_path(file, out, diag, &one)?);
    }
    Ok(all)
}
