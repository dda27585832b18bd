//! `--signals FILE.parquet` (feature `parquet`): the signals of
//! [`canopen_codec::log::signals`] as typed Parquet columns, written with the parquet
//! crate's own column writer (no arrow: the arrow crates would add a large
//! build for nothing the decoder needs).
//!
//! Columns: `time` (DOUBLE, seconds; null when the line has none),
//! `cob_id` (INT32), then a column per signal with the CSV's header as its
//! name: DOUBLE when every cell of the signal is a number (nulls where the
//! CSV cell is empty), else a UTF-8 string. Rows are written in row groups
//! of [`ROWS_PER_GROUP`], so memory stays bounded by the number of signals.

use std::fs::File;
use std::io;
use std::sync::Arc;

use parquet::basic::{Compression, LogicalType, Repetition, Type as Physical};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int32Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;

use canopen_codec::log::signals::{at_path, Signals};

/// Rows per row group.
pub const ROWS_PER_GROUP: usize = 65_536;

/// One column's cells of the row group being filled.
enum Cells {
    Number(Vec<f64>, Vec<i16>),
    Text(Vec<ByteArray>, Vec<i16>),
}

impl Cells {
    fn push(&mut self, cell: &str) -> Result<(), String> {
        match self {
            Cells::Number(values, defs) => {
                if cell.is_empty() {
                    defs.push(0);
                } else {
                    let v: f64 = cell
                        .parse()
                        .map_err(|_| format!("'{cell}' is not a number"))?;
                    values.push(v);
                    defs.push(1);
                }
            }
            Cells::Text(values, defs) => {
                if cell.is_empty() {
                    defs.push(0);
                } else {
                    values.push(ByteArray::from(cell));
                    defs.push(1);
                }
            }
        }
        Ok(())
    }

    fn clear(&mut self) {
        match self {
            Cells::Number(v, d) => {
                v.clear();
                d.clear();
            }
            Cells::Text(v, d) => {
                v.clear();
                d.clear();
            }
        }
    }
}

fn column(name: &str, physical: Physical, repetition: Repetition, text: bool) -> Arc<Type> {
    let mut b = Type::primitive_type_builder(name, physical).with_repetition(repetition);
    if text {
        b = b.with_logical_type(Some(LogicalType::String));
    }
    Arc::new(
        b.build()
            .unwrap_or_else(|e| unreachable!("a valid column: {e}")),
    )
}

/// Writes the signals as Parquet: returns the number of rows and of signals.
pub fn write(mut signals: Signals) -> io::Result<(usize, usize)> {
    let path = signals.path().to_path_buf();
    let err = |e: parquet::errors::ParquetError| at_path(&path, e);
    let headers = signals.headers();
    let mut fields = vec![
        column("time", Physical::DOUBLE, Repetition::OPTIONAL, false),
        column("cob_id", Physical::INT32, Repetition::REQUIRED, false),
    ];
    let mut cells = vec![
        Cells::Number(Vec::new(), Vec::new()),
        Cells::Number(Vec::new(), Vec::new()),
    ];
    for (h, c) in headers.iter().zip(signals.columns()) {
        if c.numeric {
            fields.push(column(h, Physical::DOUBLE, Repetition::OPTIONAL, false));
            cells.push(Cells::Number(Vec::new(), Vec::new()));
        } else {
            fields.push(column(h, Physical::BYTE_ARRAY, Repetition::OPTIONAL, true));
            cells.push(Cells::Text(Vec::new(), Vec::new()));
        }
    }
    let schema = Type::group_type_builder("signals")
        .with_fields(fields)
        .build()
        .map_err(err)?;
    let props = WriterProperties::builder()
        .set_compression(Compression::SNAPPY)
        .build();
    let file = File::create(&path).map_err(|e| at_path(&path, e))?;
    let mut writer =
        SerializedFileWriter::new(file, Arc::new(schema), Arc::new(props)).map_err(err)?;
    let mut in_group = 0;
    let flush = |cells: &mut Vec<Cells>,
                 writer: &mut SerializedFileWriter<File>|
     -> parquet::errors::Result<()> {
        let mut group = writer.next_row_group()?;
        let mut i = 0;
        while let Some(mut col) = group.next_column()? {
            match cells.get(i) {
                // The COB-ID column is required: no definition levels.
                Some(Cells::Number(values, _)) if i == 1 => {
                    let ids: Vec<i32> = values.iter().map(|v| *v as i32).collect();
                    col.typed::<Int32Type>().write_batch(&ids, None, None)?;
                }
                Some(Cells::Number(values, defs)) => {
                    col.typed::<DoubleType>()
                        .write_batch(values, Some(defs), None)?;
                }
                Some(Cells::Text(values, defs)) => {
                    col.typed::<ByteArrayType>()
                        .write_batch(values, Some(defs), None)?;
                }
                None => {}
            }
            col.close()?;
            i += 1;
        }
        group.close()?;
        cells.iter_mut().for_each(Cells::clear);
        Ok(())
    };
    let mut bad = None;
    let rows = signals.rows(|row| {
        for (i, (c, cell)) in cells.iter_mut().zip(row).enumerate() {
            // The COB-ID cell is hex.
            let cell = if i == 1 {
                u16::from_str_radix(cell, 16)
                    .map(|v| v.to_string())
                    .unwrap_or_default()
            } else {
                (*cell).to_string()
            };
            if let Err(e) = c.push(&cell) {
                bad.get_or_insert(e);
                return Err(at_path(&path, "a row was changed"));
            }
        }
        in_group += 1;
        if in_group == ROWS_PER_GROUP {
            flush(&mut cells, &mut writer).map_err(|e| at_path(&path, e))?;
            in_group = 0;
        }
        Ok(())
    })?;
    if in_group > 0 {
        flush(&mut cells, &mut writer).map_err(err)?;
    }
    writer.close().map_err(err)?;
    Ok((rows, headers.len()))
}
