//! The test bench of scenario files: a charge session of the Delta-Q
//! charger and the battery module ([`Session`](super::Session)) driven by a
//! [`Script`] of timed actions, reporting what happens ([`BenchEvent`])
//! and checking what must hold at its end ([`Expect`]). The program
//! `canopen-bench` reads the scripts from TOML files (`scenarios/` holds
//! the use cases of "Delta-Q IC Series CANopen interface specification
//! rev 2.0", section 7, in each operating mode); the library reads no
//! TOML: it takes the file as a tree of values with their lines
//! ([`Item`]) and names the line of any unknown key or bad value
//! ([`ScriptError`]). docs/SCENARIOS.md documents every key and action.
//!
//! ```
//! use canopen_codec::sim::bench::{Item, Script, Value};
//!
//! // [charger] mode = "local"; [battery] ...; [run] until = "0:10:00"
//! let table = |line, entries: Vec<(&str, Value)>| Item {
//!     line,
//!     value: Value::Table(
//!         entries
//!             .into_iter()
//!             .map(|(k, value)| (k.to_string(), Item { line, value }))
//!             .collect(),
//!     ),
//! };
//! let text = |t: &str| Value::Text(t.to_string());
//! let root = Item {
//!     line: 1,
//!     value: Value::Table(vec![
//!         ("charger".into(), table(1, vec![("mode", text("local"))])),
//!         ("battery".into(), table(3, vec![
//!             ("chemistry", text("flooded")),
//!             ("cells", Value::Integer(24)),
//!             ("capacity_ah", Value::Integer(100)),
//!             ("soc", Value::Integer(20)),
//!         ])),
//!         ("run".into(), table(8, vec![("until", text("0:10:00"))])),
//!     ]),
//! };
//! let script = Script::from_document(&root).unwrap();
//! let mut lines = Vec::new();
//! let (_session, summary) = script.run(|e| lines.push(e.json())).unwrap();
//! // The module is there from the start: the charger charges in bulk at
//! // 25 A once the BMS starts it (20 ms).
//! assert!(lines.contains(&r#"{"t": 0.02, "event": "state", "state": "bulk"}"#.to_string()));
//! assert!((summary.ah - 25.0 * 600.0 / 3600.0).abs() < 0.01);
//! assert_eq!(lines.iter().filter(|l| l.contains("sample")).count(), 10);
//! assert!(script.expect.check(&summary).is_empty());
//! ```

mod document;
mod run;
mod script;

pub use document::{Item, ScriptError, Value};
pub use run::{apply, BenchEvent, Summary, SAMPLE_EVERY, TICK};
pub use script::{
    parse_code, state_name, Action, Battery, BusSetup, Expect, Script, TimedAction, ACTIONS,
    MAX_RUN, STATES,
};
