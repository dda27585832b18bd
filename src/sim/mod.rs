//! Models for simulation (feature `sim`): a battery pack ([`Pack`]), the
//! charger's power stage ([`PowerStageModel`]), a BMS policy for the
//! battery module ([`BmsPolicy`]), and whole charge sessions of the
//! Delta-Q charger and the CiA 418 battery module on a simulated bus
//! ([`Session`], [`Scenario`]: every use case of "Delta-Q IC Series CANopen
//! interface specification rev 2.0", section 7).
//!
//! The charger's behaviour (modes, handshake, set points, algorithms,
//! status) is protocol logic and lives in [`crate::deltaq`]; this module
//! holds only the physics and the test bench around it: one simulated
//! bus ([`bus::Bus`]: any number of machines, latency, faults, loss,
//! bus-off) that sessions, tests, benches and fuzz targets all run on.
//!
//! ```
//! use canopen_codec::cia418::Chemistry;
//! use canopen_codec::deltaq::OperatingMode;
//! use canopen_codec::deltaq::charge::ChargePhase;
//! use canopen_codec::sim::{Session, SessionConfig};
//! use canopen_codec::Timestamp;
//!
//! let config = SessionConfig::new(OperatingMode::Remote, Chemistry::LeadAcid, 100.0, 0.5).unwrap();
//! let mut session = Session::new(&config);
//! session.start();
//! session.run_until(Timestamp::from_millis(60_000));
//! // The BMS asked for 25 A; the charger delivers it.
//! assert_eq!(session.phase(), ChargePhase::Remote);
//! assert!((session.stage.current_a - 25.0).abs() < 0.1);
//! assert!(session.result().ah > 0.3);
//! ```

pub mod bench;
mod bms;
pub mod bus;
pub mod module_link;
mod pack;
mod power_stage;
mod scenario;
mod session;

pub use bms::{BmsPolicy, BmsRequest};
pub use pack::{cell_model, CellModel, Pack, PackError, PackSpec};
pub use power_stage::PowerStageModel;
pub use scenario::{Scenario, ScenarioOptions};
pub use session::{
    AlarmChange, BmsMaster, Logged, Session, SessionConfig, SessionResult, CHARGER_NODE,
    DEFAULT_SEED, LOG_EPOCH, MODULE_NODE,
};
