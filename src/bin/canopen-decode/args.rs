//! The command line, parsed with clap (derive): what each option means is
//! in the module docs of `main.rs` and in `--help`.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, ValueEnum};

use canopen_codec::sdo::SdoChannel;
use canopen_codec::{CanId, NodeId};

use canopen_codec::log::dataset::{self, PartFormat};
use canopen_codec::log::input::{How, FORMAT_NAMES};
use canopen_codec::log::{mappings, signals, Options, Roles};

/// `--format`: the names of [`FORMAT_NAMES`], each with its help.
pub fn format_names() -> impl TypedValueParser<Value = How> {
    let names = FORMAT_NAMES.map(|f| PossibleValue::new(f.name).help(f.help));
    PossibleValuesParser::new(names).map(|name| How::named(&name).unwrap_or_default())
}

/// Output forms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Output {
    /// One line of words per frame.
    Words,
    /// One JSON object per frame.
    Json,
    /// One CSV row per frame.
    Csv,
}

/// What the bundled data can be.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Bundled {
    /// The recorded session of the crate's virtual charger and battery module.
    Session,
}

/// Decodes a CAN trace of a CANopen bus: every frame in words, JSON or CSV,
/// SDO transfers reassembled, and a bus-health summary.
#[derive(Parser, Debug)]
#[command(name = "canopen-decode", version)]
pub struct Cli {
    /// The same as --output json.
    #[arg(long)]
    json: bool,
    /// words (default), json or csv.
    #[arg(long, value_enum)]
    output: Option<Output>,
    /// Treat frames that deviate from CiA 301 as malformed.
    #[arg(long)]
    strict: bool,
    /// The trace format (detected from the content when not given).
    #[arg(long, value_parser = format_names())]
    format: Option<How>,
    /// Print the bus-health summary after the frames.
    #[arg(long)]
    summary: bool,
    /// Print only the summary.
    #[arg(long)]
    summary_only: bool,
    /// Write the summary to PATH (implies --summary). With --output csv and
    /// no file the summary goes to stderr: the CSV stream stays one CSV.
    #[arg(long, value_name = "PATH")]
    summary_file: Option<String>,
    /// Print the summary; exit 3 when a problem is open at the end.
    #[arg(long)]
    check: bool,
    /// The bus's bit rate for the summary's bus load (default 250000, said to be assumed).
    #[arg(long, value_name = "BPS", value_parser = clap::value_parser!(u32).range(1..))]
    bitrate: Option<u32>,
    /// The data phase's bit rate of CAN FD frames with BRS set (default 2000000, said to be assumed).
    #[arg(long, value_name = "BPS", value_parser = clap::value_parser!(u32).range(1..))]
    data_bitrate: Option<u32>,
    /// The Delta-Q charger's node id (Delta-Q names and error labels).
    #[arg(long, value_name = "N", value_parser = parse_node, allow_hyphen_values = true)]
    charger_node: Option<NodeId>,
    /// The CiA 418 battery module's node id.
    #[arg(long, value_name = "N", value_parser = parse_node, allow_hyphen_values = true)]
    battery_node: Option<NodeId>,
    /// The mapping of the PDO on COBID (hex), entries in mapping order.
    #[arg(long, value_name = "COBID=INDEX:SUB:BITS,...")]
    pdo: Vec<String>,
    /// Do not apply the charger's and battery module's default PDOs.
    #[arg(long)]
    no_default_pdos: bool,
    /// The mapping of the real Delta-Q captures (implies --no-default-pdos).
    #[arg(long)]
    pdo_capture_mapping: bool,
    /// An SDO server on other COB-IDs: NODE (decimal), RXID and TXID (hex).
    #[arg(
        long,
        value_name = "NODE=RXID,TXID",
        value_parser = parse_sdo_channel,
        allow_hyphen_values = true
    )]
    sdo: Vec<SdoChannel>,
    /// A node's EDS or DCF.
    #[arg(long, value_name = "NODE=FILE", value_parser = parse_eds, allow_hyphen_values = true)]
    eds: Vec<(NodeId, String)>,
    /// Write the PDO fields as signals to PATH (CSV: one row per PDO frame,
    /// a column per named field, `name [unit]`; PATH.parquet: Parquet, with
    /// feature `parquet`). With several logs PATH is a folder holding one
    /// dataset partitioned by log: PATH/log=NAME/part-0.csv or .parquet.
    /// With it the frames are printed only when --output or --json asks
    /// for them.
    #[arg(long, value_name = "PATH")]
    signals: Option<String>,
    /// With --signals PATH: PATH is a folder holding one dataset
    /// partitioned by log (PATH/log=NAME/part-0.FORMAT), even for one log;
    /// csv or parquet, whatever PATH's name. Logs named by a folder or a
    /// glob make one too, its format from PATH's name.
    #[arg(long, value_name = "FORMAT", requires = "signals",
          value_parser = clap::builder::PossibleValuesParser::new(["csv", "parquet"]))]
    dataset: Option<String>,
    /// Write the PDO mappings in use to PATH as a DBC file. With it the
    /// frames are printed only when --output or --json asks for them.
    #[arg(long, value_name = "PATH")]
    dbc: Option<String>,
    /// Format every line anew instead of repeating the text of an equal
    /// frame (the output is the same; for checking that).
    #[arg(long, hide = true)]
    no_cache: bool,
    /// Write the session as one self-contained HTML page: the summary, a
    /// timeline per node, the bus traffic (load, frames per second per
    /// node) and a plot of every named PDO field. With it the
    /// frames are printed only when --output or --json asks for them.
    #[arg(long, value_name = "FILE.html")]
    report: Option<String>,
    /// Decode bundled data instead of a FILE.
    #[arg(long, value_enum, conflicts_with = "files")]
    bundled: Option<Bundled>,
    /// The trace ('-' for stdin; none: stdin, or the bundled session on a terminal).
    /// Several logs (files, folders: their files, globs such as 'logs/*.log')
    /// are decoded one after the other, each on its own (with --signals,
    /// into one dataset partitioned by log).
    files: Vec<String>,
}

fn parse_node(v: &str) -> Result<NodeId, String> {
    v.parse::<u8>()
        .ok()
        .and_then(NodeId::new)
        .ok_or(format!("'{v}' is not a node id 1..=127"))
}

/// `NODE=RXID,TXID`: the server `NODE` (decimal) receives requests on RXID
/// and answers on TXID (hex COB-IDs, as in its 1200h sub 1 and sub 2).
fn parse_sdo_channel(v: &str) -> Result<SdoChannel, String> {
    let bad = || format!("'{v}' is not NODE=RXID,TXID (e.g. 65=241,1C1)");
    let (node, ids) = v.split_once('=').ok_or_else(bad)?;
    let (rx, tx) = ids.split_once(',').ok_or_else(bad)?;
    let node = parse_node(node)?;
    let id = |s: &str| -> Result<CanId, String> {
        let digits = s.trim_start_matches("0x").trim_start_matches("0X");
        let raw = u32::from_str_radix(digits, 16).map_err(|_| bad())?;
        match u16::try_from(raw).ok().and_then(CanId::standard) {
            Some(id) => Ok(id),
            None => CanId::extended(raw).ok_or_else(bad),
        }
    };
    Ok(SdoChannel {
        node,
        request: id(rx)?,
        response: id(tx)?,
    })
}

/// `NODE=FILE`.
fn parse_eds(v: &str) -> Result<(NodeId, String), String> {
    let (node, path) = v.split_once('=').ok_or(format!("'{v}' is not NODE=FILE"))?;
    Ok((parse_node(node)?, path.to_string()))
}

impl Cli {
    /// The options the program runs with; errors that need more than one
    /// argument (a COB-ID given twice) are found here.
    pub fn options(self) -> Result<Options, String> {
        // With --report, --signals or --dbc the file written is the output:
        // frame lines only when --output or --json asks for them.
        let frames_asked = self.output.is_some()
            || self.json
            || (self.report.is_none() && self.signals.is_none() && self.dbc.is_none());
        let output = self
            .output
            .or(self.json.then_some(Output::Json))
            .unwrap_or(Output::Words);
        let mut pdos = mappings::Mappings {
            given: Vec::new(),
            defaults: !self.no_default_pdos,
        };
        for p in &self.pdo {
            pdos.add(p)?;
        }
        // A Parquet path in a decoder built without the `parquet` feature
        // is an error before the log is read.
        let (files, many) = dataset::logs(&self.files)?;
        let dataset = match (self.dataset.as_deref(), &self.signals) {
            (Some("parquet"), _) => Some(PartFormat::Parquet),
            (Some(_), _) => Some(PartFormat::Csv),
            (None, Some(path)) if many => Some(PartFormat::of(std::path::Path::new(path))),
            (None, _) => None,
        };
        if let Some(path) = &self.signals {
            let parquet = dataset.map_or(signals::is_parquet(std::path::Path::new(path)), |d| {
                d == PartFormat::Parquet
            });
            if parquet && !cfg!(feature = "parquet") {
                return Err(format!(
                    "--signals {path}: Parquet needs the decoder built with the `parquet` feature"
                ));
            }
        }
        let mut roles = Roles {
            charger: self.charger_node,
            battery: self.battery_node,
            // The option names the Delta-Q charger: that is the evidence.
            deltaq: self.charger_node,
        };
        if self.pdo_capture_mapping {
            pdos.add_capture()?;
            roles.demo();
        }
        let how = self.format.unwrap_or_default();
        Ok(Options {
            json: output == Output::Json,
            csv: output == Output::Csv,
            summary: self.summary || self.summary_only || self.check || self.summary_file.is_some(),
            summary_file: self.summary_file,
            frames: !self.summary_only && frames_asked,
            check: self.check,
            bitrate: self.bitrate,
            data_bitrate: self.data_bitrate,
            roles,
            pdos,
            file: files.first().cloned(),
            more_files: files.get(1..).unwrap_or_default().to_vec(),
            bundled: self.bundled.map(|Bundled::Session| "session"),
            format: how.format,
            binary: how.binary,
            delta_times: how.delta_times,
            strict: self.strict,
            sdo_channels: self.sdo,
            eds: self.eds,
            no_cache: self.no_cache,
            signals: self.signals,
            dataset,
            dbc: self.dbc,
            report: self.report,
            ..Options::default()
        })
    }
}
