//! `--signals FILE.csv`: the PDO fields of the log as signals, one row per
//! PDO frame, a column per named field.
//!
//! Columns: `time` (seconds with microseconds, empty when the line has
//! none), `cob_id` (hex, 3 digits), then one column per signal, headed
//! `name [unit]` (`name` when the object has no unit; `XXXXh:SS raw` for an
//! object the node's dictionary does not name). A signal is one object of
//! one PDO: its COB-ID, index and sub-index. Where two signals would get
//! the same header (the charging current in the charger's TPDO and in the
//! battery's RPDO), each of them gets its COB-ID after it:
//! `charging current [A] (18Ah)`.
//!
//! The column set is the set of signals the log shows: every PDO frame the
//! decoder has a mapping for (`--pdo`, the capture mapping, a role's
//! defaults, an EDS, or a mapping learned from SDO transfers in the log)
//! adds the signals of its mapping when they are new. So that a signal
//! first seen late in the log still gets its column, and nothing is held
//! per frame, the rows go to a file beside the output while the log is
//! read (`FILE.rows`, removed after), and the output is written at the end:
//! the header, then every row, padded to the full column set. Memory is
//! bounded by the number of signals, not by the log's length.
//!
//! A cell holds what `--json` gives as the field's `value`: the exact
//! decimal number of a scaled value (`19.453125`), the words of a bit field
//! or code; for an object the dictionary does not name (`kind` `raw` in
//! JSON) the raw integer; empty for an invalid or no-value marker, a field
//! past the end of the frame, or a frame that does not map that signal.
//! Padding has no column.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::prelude::rust_2021::*;

use crate::pdo::{
    Catalogue, FieldValue, Interpretation, MappingEntry, NamedField, NamedFields, Unit,
};
use crate::Timestamp;

use crate::log::time_column::TimeColumn;

/// What a PDO field is as a signal, from the mapping entry and the
/// catalogue entry of its object: the one description `--signals` and
/// `--dbc` share.
#[derive(Clone, Copy, Debug)]
pub struct Signal {
    /// The object's name (`"unknown object"` where the dictionary has none).
    pub name: &'static str,
    /// The unit, where the object has one.
    pub unit: Option<Unit>,
    /// Two's complement.
    pub signed: bool,
    /// Fractional bits: the value is `raw / 2^frac_bits`.
    pub frac_bits: u8,
    /// The object is known to the dictionary.
    pub known: bool,
}

/// The signal a mapping entry carries, or `None` for padding.
pub fn describe(catalogue: Catalogue, entry: MappingEntry) -> Option<Signal> {
    if entry.is_dummy() {
        return None;
    }
    let unknown = Signal {
        name: "unknown object",
        unit: None,
        signed: false,
        frac_bits: 0,
        known: false,
    };
    let Some(def) = catalogue.lookup(entry.index, entry.sub) else {
        return Some(unknown);
    };
    let (signed, frac_bits, unit) = match def.interpretation {
        Interpretation::Padding => return None,
        Interpretation::Unsigned {
            frac_bits, unit, ..
        } => (false, frac_bits, unit),
        Interpretation::Signed { frac_bits, unit } => (true, frac_bits, unit),
        _ => (false, 0, None),
    };
    Some(Signal {
        name: def.short,
        unit,
        signed,
        frac_bits,
        known: true,
    })
}

/// Appends the cell of `field`: the JSON output's `value` (the raw integer
/// for an object the dictionary does not name), empty where that is null.
pub fn cell(out: &mut String, field: &NamedField) {
    let words = |out: &mut String, v: &FieldValue| {
        let _ = write!(out, "{v}");
    };
    let unnamed = matches!(field.value, FieldValue::Raw | FieldValue::WrongWidth { .. });
    if !crate::log::json::field_value(out, &field.value, words) && unnamed {
        let _ = write!(out, "{}", field.raw);
    }
}

/// One column.
pub struct Column {
    cob_id: u16,
    entry: MappingEntry,
    signal: Signal,
    /// Every cell so far is a number (or empty): a DOUBLE column in Parquet.
    pub numeric: bool,
}

/// Separates the cells of a row in the rows file: no cell holds it (values
/// are numbers and words; `Chars` escapes control characters).
pub const SEP: char = '\x1f';

impl Column {
    /// The header without the COB-ID.
    fn header(&self) -> String {
        match (self.signal.known, self.signal.unit) {
            (false, _) => format!("{:04X}h:{:02X} raw", self.entry.index, self.entry.sub),
            (true, Some(u)) => format!("{} [{}]", self.signal.name, u.symbol()),
            (true, None) => self.signal.name.to_string(),
        }
    }
}

/// The signals file being written.
pub struct Signals {
    path: PathBuf,
    rows_path: PathBuf,
    rows: BufWriter<File>,
    columns: Vec<Column>,
    by_key: HashMap<(u16, u16, u8), usize>,
    times: TimeColumn,
    /// One row, reused.
    row: String,
    /// The cells of one row by column, reused.
    cells: Vec<(usize, String)>,
}

fn at(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("--signals {}: {e}", path.display()))
}

impl Signals {
    /// Starts `path` (the rows go to `path` + `.rows` until [`Self::finish`]).
    pub fn create(path: &str) -> io::Result<Self> {
        let path = PathBuf::from(path);
        let mut rows_path = path.clone().into_os_string();
        rows_path.push(".rows");
        let rows_path = PathBuf::from(rows_path);
        let rows = File::create(&rows_path).map_err(|e| at(&rows_path, e))?;
        Ok(Signals {
            path,
            rows_path,
            rows: BufWriter::with_capacity(64 * 1024, rows),
            columns: Vec::new(),
            by_key: HashMap::new(),
            times: TimeColumn::new(0),
            row: String::new(),
            cells: Vec::new(),
        })
    }

    /// Adds the row of one PDO frame on `cob_id`.
    pub fn frame(
        &mut self,
        timestamp: Option<Timestamp>,
        cob_id: u16,
        catalogue: Catalogue,
        fields: &NamedFields,
    ) -> io::Result<()> {
        self.cells.clear();
        for f in fields.iter() {
            let Some(signal) = describe(catalogue, f.entry) else {
                continue;
            };
            let key = (cob_id, f.entry.index, f.entry.sub);
            let next = self.columns.len();
            let column = *self.by_key.entry(key).or_insert(next);
            if column == next {
                self.columns.push(Column {
                    cob_id,
                    entry: f.entry,
                    signal,
                    numeric: true,
                });
            }
            let mut text = String::new();
            cell(&mut text, f);
            if let Some(c) = self.columns.get_mut(column) {
                c.numeric &= !matches!(
                    f.value,
                    FieldValue::Flags(_) | FieldValue::Formatted(_) | FieldValue::Chars(_)
                );
            }
            self.cells.push((column, text));
        }
        self.cells.sort_by_key(|(c, _)| *c);
        self.row.clear();
        // The number of signal cells the row holds, for padding it at the end.
        let width = self.cells.last().map_or(0, |(c, _)| c + 1);
        let _ = write!(self.row, "{width}|");
        if let Some(t) = timestamp {
            self.times.write(&mut self.row, t);
        }
        let _ = write!(self.row, "{SEP}{cob_id:03X}");
        let mut next = 0;
        for (column, text) in &self.cells {
            while next <= *column {
                self.row.push(SEP);
                next += 1;
            }
            self.row.push_str(text);
        }
        self.row.push('\n');
        self.rows
            .write_all(self.row.as_bytes())
            .map_err(|e| at(&self.rows_path, e))
    }

    /// The headers of the signal columns, each unique.
    pub fn headers(&self) -> Vec<String> {
        let plain: Vec<String> = self.columns.iter().map(Column::header).collect();
        let mut count: HashMap<&str, usize> = HashMap::new();
        for h in &plain {
            *count.entry(h.as_str()).or_default() += 1;
        }
        plain
            .iter()
            .zip(&self.columns)
            .map(|(h, c)| {
                if count.get(h.as_str()).copied().unwrap_or(0) > 1 {
                    format!("{h} ({:03X}h)", c.cob_id)
                } else {
                    h.clone()
                }
            })
            .collect()
    }

    /// The columns, in order.
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// Calls `each` with every row's cells (time, COB-ID, then one per
    /// signal, empty where the row has none), in order; then removes the
    /// rows file. Returns the number of rows.
    pub fn rows(&mut self, mut each: impl FnMut(&[&str]) -> io::Result<()>) -> io::Result<usize> {
        self.rows.flush().map_err(|e| at(&self.rows_path, e))?;
        let rows = File::open(&self.rows_path).map_err(|e| at(&self.rows_path, e))?;
        let total = self.columns.len();
        let mut n = 0;
        for line in BufReader::with_capacity(64 * 1024, rows).lines() {
            let line = line.map_err(|e| at(&self.rows_path, e))?;
            let changed = || {
                at(
                    &self.rows_path,
                    io::Error::new(io::ErrorKind::InvalidData, "a row was changed"),
                )
            };
            let (width, row) = line
                .split_once('|')
                .and_then(|(w, r)| Some((w.parse::<usize>().ok()?, r)))
                .ok_or_else(changed)?;
            let mut cells: Vec<&str> = row.split(SEP).collect();
            if cells.len() != width + 2 || width > total {
                return Err(changed());
            }
            cells.resize(total + 2, "");
            each(&cells)?;
            n += 1;
        }
        std::fs::remove_file(&self.rows_path).map_err(|e| at(&self.rows_path, e))?;
        Ok(n)
    }

    /// Writes the output file (CSV, or Parquet for a `.parquet` path,
    /// written by `parquet`: this crate has no Parquet writer, the program
    /// has one): returns the number of rows and of signals.
    pub fn finish(self, parquet: Option<ParquetWriter>) -> io::Result<(usize, usize)> {
        if is_parquet(&self.path) {
            return match parquet {
                Some(write) => write(self),
                None => Err(at_path(&self.path, "no Parquet writer given")),
            };
        }
        self.finish_csv()
    }

    /// Writes the CSV: the header, then the rows padded to every column.
    fn finish_csv(mut self) -> io::Result<(usize, usize)> {
        let mut header = String::from("time,cob_id");
        for h in self.headers() {
            header.push(',');
            crate::log::csv::field(&mut header, &h);
        }
        header.push('\n');
        let path = self.path.clone();
        let out = File::create(&path).map_err(|e| at(&path, e))?;
        let mut out = BufWriter::with_capacity(64 * 1024, out);
        out.write_all(header.as_bytes()).map_err(|e| at(&path, e))?;
        let mut line = String::new();
        let n = self.rows(|cells| {
            line.clear();
            for (i, c) in cells.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                crate::log::csv::field(&mut line, c);
            }
            line.push('\n');
            out.write_all(line.as_bytes()).map_err(|e| at(&path, e))
        })?;
        out.flush().map_err(|e| at(&path, e))?;
        Ok((n, self.columns.len()))
    }

    /// The output's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for Signals {
    /// A run that stops on an error leaves no rows file behind (after
    /// [`Signals::rows`] it is gone already).
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.rows_path);
    }
}

/// True for a path the signals go to as Parquet.
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// Writes [`Signals`] as Parquet (the rows through [`Signals::rows`]):
/// returns the number of rows and of signals.
pub type ParquetWriter = fn(Signals) -> io::Result<(usize, usize)>;

/// An error of the signals file `path`: `--signals PATH: why`.
pub fn at_path(path: &Path, e: impl std::fmt::Display) -> io::Error {
    io::Error::other(format!("--signals {}: {e}", path.display()))
}
