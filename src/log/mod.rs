//! Log analysis (feature `log`): what `canopen-decode` and
//! `canopen-replay` do with a CAN trace, as a library. Read a recording in
//! any trace format, follow every SDO transfer, name the objects, learn the
//! PDO mappings the log configures, and write the frames in words, JSON
//! lines or CSV, the bus-health summary, the PDO signals, a DBC of the
//! mappings in use and an HTML report page.
//!
//! The two programs in `src/bin/` are this module plus argument parsing
//! (clap) and the outputs that need a dependency of their own (Parquet);
//! whatever they print, a Rust tool gets from here.
//!
//! ```
//! use canopen_codec::log::{run, Options, Roles};
//! use canopen_codec::NodeId;
//!
//! // A candump -L log: the Delta-Q charger 10 boots, its heartbeat says
//! // pre-operational, and a client reads its device type (1000h) by SDO.
//! let log = "\
//! (1700000000.000000) can0 70A#00
//! (1700000000.100000) can0 70A#7F
//! (1700000000.200000) can0 60A#4000100000000000
//! (1700000000.201000) can0 58A#43001000A3010000
//! ";
//! let opts = Options {
//!     roles: Roles { charger: NodeId::new(10), ..Roles::default() },
//!     ..Options::default()
//! };
//! let mut out = Vec::new();
//! let outcome = run(log.as_bytes(), &mut out, &mut std::io::sink(), &opts)?;
//! assert!(!outcome.failed());
//! let text = String::from_utf8(out).unwrap();
//! for line in text.lines() {
//!     println!("{line}");
//! }
//! assert!(text.contains("boot-up"));
//! assert!(text.contains("SDO upload 1000h:00 from node 10"));
//! assert!(text.contains("(device type"));
//! # Ok::<(), std::io::Error>(())
//! ```
//!
//! ## Where do I look for X
//!
//! | I want to ... | Look in |
//! |---|---|
//! | read a trace file (candump, screen, PCAN, ASC, CSV, BLF) item by item, or all its frames | [`input`] ([`input::read`], [`input::frames`]; BLF zlib through [`input::Inflate`]) |
//! | decode a whole log as the program does | [`run`] with [`Options`] (what `canopen-decode` prints), [`Decoding`] frame by frame, several logs or a dataset with [`run_each`] |
//! | which node is the charger, the battery module, a Delta-Q device | [`Roles`] (given, or learned from 1000h/1018h in the log) |
//! | reassemble SDO transfers from frames | [`sdo`] ([`sdo::Tracker`] over [`crate::sdo::Observer`], one [`sdo::Report`] per transfer) |
//! | name an object and interpret its value | [`naming`] (the CiA 301 area, the profiles' catalogues, an EDS's names) |
//! | a frame or a transfer in words | [`words`] |
//! | ... as a JSON object, or a CSV row | [`json`], [`csv`] |
//! | the PDO mappings a frame decodes with (given, defaults, learned) | [`mappings`] (`--pdo` syntax in [`pdo_syntax`]), [`pdo_learn`] (from SDO writes, from an EDS) |
//! | the bus-health summary | [`summary`] |
//! | PDO fields as signal columns, a DBC of the mappings | [`signals`], [`dbc`] |
//! | the HTML report page | [`report`] |
//! | CiA 301 dates (TIME, 1020h) as UTC | [`calendar`] |
//! | boot a network from DCFs and report each node's boot as a JSON line (`canopen-boot`) | [`boot`] ([`boot::BootNode`], [`boot::BootRun`], [`boot::event_json`]) |
//! | split a recording into the frames to play and those to expect, play it into a device on your clock, and diff the device's traffic against it (`canopen-replay`) | [`replay`], [`replay::player`], [`replay::diff`] |
//!
//! ## Why a module, and its dependencies
//!
//! A module of this crate behind the feature `log` (= `std` and every
//! device service), not a crate of its own: the repository's layout keeps
//! one crate, and the analysis uses the codec's own types throughout. It
//! adds no dependency: the JSON it writes is written by hand (checked
//! against serde_json by `tests/decoder/log_json.rs`), a text trace's line ends
//! are found by the caller's [`input::FindNewline`] (by default
//! `<[u8]>::iter().position`; the programs pass memchr's SIMD search,
//! which is a few per cent faster on a whole log), and BLF zlib containers
//! are inflated by the caller's [`input::Inflate`] (the programs pass
//! flate2's). What needs a dependency stays in the programs: argument
//! parsing (clap), the line search (memchr), zlib (flate2), Parquet (the
//! `parquet` crate, through [`Options::parquet`]) and the replay's report
//! (serde_json).
//!
//! It reads and writes the files its [`Options`] name (`eds`, `signals`,
//! `dbc`, `report`, `summary_file`) with `std::fs`; the trace itself and
//! the output streams are the caller's `Read` and `Write`. Nothing in it
//! panics on any input.
//!
//! The log module sits at the programs' level: it may use every layer
//! and profile of the crate, and nothing below it uses it
//! (`tests/meta/layering.rs`).

pub mod boot;
pub mod bus_load;
pub mod calendar;
mod comm_objects;
pub mod csv;
pub mod dataset;
pub mod dbc;
mod decoding;
pub mod frame_bits;
mod frame_line;
pub mod input;
pub mod json;
mod line_cache;
mod manager_objects;
pub mod mappings;
pub mod naming;
pub mod pdo_learn;
pub mod pdo_syntax;
mod pipeline;
pub mod replay;
pub mod report;
mod roles;
pub mod sdo;
mod sdo_value;
pub mod signals;
pub mod summary;
mod time_column;
pub mod words;

pub use decoding::{run, run_each, run_path, Decoding};
pub use frame_line::{is_default, BlockSegment, FrameLine, Notes};
pub use line_cache::LineCache;
pub use pipeline::{load_eds, page_transfer, transfer, Options, Outcome};
pub use roles::Roles;
pub use time_column::TimeColumn;
