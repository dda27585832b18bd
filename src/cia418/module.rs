//! A complete CiA 418 battery module: the CiA 301 device core
//! ([`crate::device`]: NMT slave, SDO server, heartbeat, EMCY with 1001h and
//! 1003h, PDOs) with the CiA 418 application objects ([`BatteryObjects`]),
//! the CiA 418 default PDOs and the temperature-sensor fault.
//!
//! # Driving it
//!
//! [`BatteryModule`] (a [`ProfiledDevice`]) implements
//! [`Machine`](crate::machine::Machine), the crate's state-machine
//! contract: `boot` once at power-on, then `handle_frame` /
//! `handle_timeout`, and drain `poll_transmit` after every call. Events
//! ([`BatteryEvent`]) are informational: the queue keeps the latest `Q`
//! (default 16), dropping the oldest and counting what it drops, so an
//! application that never reads them still has a working module.
//!
//! # Behaviour and choices
//!
//! The CiA 301 behaviour (NMT states and resets, SDO in pre-operational and
//! operational only, EMCY not in stopped, TPDOs only in operational, RPDO
//! length check with EMCY 8210h, heartbeat) is the device core's; see
//! [`crate::device`]. What the profile adds:
//!
//! - **Objects**: 1000h is profile 418 with the optional-PDO bits of
//!   [`BatteryModuleConfig::device_type`]; the application objects
//!   6000h-6090h are [`BatteryObjects`]. Reset node (81h) restores the
//!   `rw` ones (6001h, 6052h, 6053h, 6054h, 6080h: what the charger
//!   writes) to their values at boot
//!   ([`BatteryPowerOnValues`](super::BatteryPowerOnValues)); the `ro` ones
//!   are the module's measurements and identity, not parameters (CiA 301
//!   7.3.2.2.1 restores the profile area's parameters), and keep the value
//!   the application last set, so no stale boot-time reading is published
//!   until its next update. Reset communication (82h) keeps them all.
//! - **TPDOs**: the CiA 418 default set ([`DEFAULT_PDOS`]) for the PDOs the
//!   device type declares. CiA 418 v1.0.1 (6.2.5) makes the TPDO COB-IDs
//!   "not valid" (bit 31) by default; with
//!   [`BatteryModuleConfig::enable_tpdos`] (default `true`) the module
//!   clears bit 31 in its power-on configuration, so a module out of the box
//!   transmits its TPDOs every 200 ms once started. With `false` the CiA 418
//!   default is kept and a configuration tool enables them by SDO.
//! - **EMCY**: [`BatteryModule::set_temperature_sensor_fault`] sets 1001h
//!   bits 0 (generic) and 5 (device profile), records 5010h in 1003h and
//!   sends EMCY 5010h (CiA 418 v1.0.1, 6.2.2: the device-profile bit flags
//!   a temperature sensor fault); clearing it clears bit 5 (and bit 0 if no
//!   other bit is left) and sends the error reset 0000h.
//! - Total: no frame, timestamp or call order panics.

use core::time::Duration;

use super::objects::BatteryDictionary;
use super::{
    AmpHours, BatteryParameters, BatteryStatus, BatteryVoltage, ChargeCurrentRequested,
    ChargerStatus, DeviceType, EighthAmpHours, EqualizationDate, PackedStringError,
    PackedStringObject, StateOfCharge, Temperature, WaterLevelStatus, DEFAULT_PDOS,
};
use crate::cob_id::NodeId;
use crate::device::{
    CommObjects, Device, DeviceConfig, DeviceEvent, DeviceSetup, DeviceSpec, ErrorFieldFormat,
    Identity, Policies, PowerOn, Profile, ProfiledDevice, DEFAULT_QUEUE_CAPACITY,
};
use crate::emcy::{Emergency, ErrorCode, ErrorRegister};

use crate::clock::{millis_u16, millis_u32, Timestamp};
use crate::pdo::{
    DefaultPdo, PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoSlot, TransmissionType,
};
use crate::sdo::DEFAULT_TIMEOUT;

/// How a [`BatteryModule`] is set up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatteryModuleConfig {
    /// Node id (CiA 418 v1.0.1, 6.1: the battery module's default node id is 1).
    pub node: NodeId,
    /// 1000h: profile 418 and the optional PDOs (bits 16-19) the module has
    /// (default: none, only the 1st RPDO and 1st TPDO).
    pub device_type: DeviceType,
    /// 1008h manufacturer device name.
    pub device_name: &'static str,
    /// 1018h identity.
    pub identity: Identity,
    /// 1017h producer heartbeat time after boot and resets (default 1000
    /// ms; zero = no heartbeat).
    pub heartbeat: Duration,
    /// Clear bit 31 ("not valid") of the default TPDO COB-IDs at boot and
    /// resets so the module transmits out of the box (default `true`). With
    /// `false` the TPDOs keep CiA 418's default (not valid) until enabled by
    /// SDO.
    pub enable_tpdos: bool,
    /// SDO server timeout (default 2000 ms).
    pub sdo_timeout: Duration,
}

impl BatteryModuleConfig {
    /// The defaults for node `node`.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        BatteryModuleConfig {
            node,
            device_type: DeviceType::cia418(0),
            device_name: "CiA 418 battery module",
            identity: Identity::ZERO,
            heartbeat: Duration::from_millis(1000),
            enable_tpdos: true,
            sdo_timeout: DEFAULT_TIMEOUT,
        }
    }

    /// The device core's configuration for this module (times in the
    /// whole milliseconds the module keeps, see [`BatteryModulePowerOn`]).
    #[must_use]
    pub fn device_config(&self) -> DeviceConfig {
        let (mut comm, mut pdos) = (CommObjects::new(self.node), PdoConfig::new());
        DeviceSetup::write_constants(self, &mut comm);
        let policies = BatteryModulePowerOn::from(*self).restore(&mut comm, &mut pdos);
        DeviceConfig::from_objects(&comm, &pdos, policies)
    }
}

/// The part of a [`BatteryModuleConfig`] the module keeps to rebuild its
/// power-on configuration at boot and at every reset ([`PowerOn`]): the
/// settings an SDO client can change, with the heartbeat in the whole
/// milliseconds of 1017h (saturating at 65 535 ms) and the SDO timeout in
/// whole milliseconds (saturating at `u32::MAX` ms). 1000h device type, 1008h device name and 1018h identity are
/// `const` / `ro` objects nothing on the bus can change: the module writes
/// them into its communication objects once, when it is made, and every
/// reset keeps what they hold ([`PowerOn::restore`] reads them out before
/// it restores the others; the CiA 418 default PDO set follows the 1000h
/// it finds). So the whole configuration is these settings over the live
/// objects: [`config`](Self::config) takes them.
/// ([`PowerOn::power_on_config`] of this alone sees 1000h, 1008h and 1018h
/// empty; [`BatteryModuleConfig::device_config`] is the module's.)
///
/// ```
/// use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig, BatteryModulePowerOn};
/// use canopen_codec::NodeId;
/// use core::time::Duration;
/// let mut config = BatteryModuleConfig::new(NodeId::MIN);
/// config.sdo_timeout = Duration::from_micros(2_500_900);
/// let module = BatteryModule::new(config);
/// let kept = module.device().power_on();
/// assert_eq!(kept.config(module.comm()).sdo_timeout, Duration::from_millis(2500));
/// assert_eq!(kept.config(module.comm()).heartbeat, config.heartbeat);
/// assert_eq!(kept.config(module.comm()).device_name, config.device_name);
/// assert_eq!(*kept, BatteryModulePowerOn::from(config));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatteryModulePowerOn {
    node: NodeId,
    enable_tpdos: bool,
    heartbeat_ms: u16,
    sdo_timeout_ms: u32,
}

impl From<BatteryModuleConfig> for BatteryModulePowerOn {
    fn from(c: BatteryModuleConfig) -> Self {
        BatteryModulePowerOn {
            node: c.node,
            enable_tpdos: c.enable_tpdos,
            heartbeat_ms: millis_u16(c.heartbeat),
            sdo_timeout_ms: millis_u32(c.sdo_timeout),
        }
    }
}

impl BatteryModulePowerOn {
    /// The configuration: the settings kept (times in whole milliseconds)
    /// with 1000h, 1008h and 1018h as `comm` (the module's live objects,
    /// [`BatteryModule::comm`](Device::comm)) holds them.
    #[must_use]
    pub fn config(&self, comm: &CommObjects) -> BatteryModuleConfig {
        BatteryModuleConfig {
            node: self.node,
            device_type: DeviceType::from_raw(comm.device_type),
            device_name: comm.device_name,
            identity: comm.identity,
            heartbeat: Duration::from_millis(u64::from(self.heartbeat_ms)),
            enable_tpdos: self.enable_tpdos,
            sdo_timeout: Duration::from_millis(u64::from(self.sdo_timeout_ms)),
        }
    }
}

impl Default for BatteryModuleConfig {
    /// [`BatteryModuleConfig::new`] for node 1, the CiA 418 default.
    fn default() -> Self {
        Self::new(NodeId::MIN)
    }
}

/// What a [`BatteryModule`] reports: the device core's events.
pub type BatteryEvent = DeviceEvent;

/// The module's core: 3 TPDOs and 3 RPDOs, the ones CiA 418 v1.0.1 (6.2.5)
/// gives a battery module ([`DEFAULT_PDOS`]); 1403h/1803h do not exist.
pub type BatteryModuleDevice<const Q: usize> = Device<BatteryModuleProfile, Q, 3, 3>;

/// The CiA 418 battery module's profile on the device core: its objects
/// ([`BatteryObjects`](super::BatteryObjects)), its events and its configuration; no behaviour
/// or state of its own besides the core's: the temperature sensor fault is
/// 1001h's device-profile bit (CiA 418 v1.0.1, 6.2.2), which both resets
/// clear with 1001h.
#[derive(Debug, Clone, Copy, Default)]
pub struct BatteryModuleProfile;

impl DeviceSpec for BatteryModuleProfile {
    type Objects = BatteryDictionary;
    type Event = BatteryEvent;
    type PowerOn = BatteryModulePowerOn;
}

impl<const Q: usize> Profile<BatteryModuleProfile, Q, 3, 3> for BatteryModuleProfile {}

/// A CiA 418 battery module: [`BatteryModuleProfile`] on its device core.
/// See the module docs for the behaviour. It implements
/// [`Machine`](crate::machine::Machine) and dereferences to its [`Device`]
/// core, whose getters give its objects (`objects()`, `comm()`,
/// `pdo_config()`, `dictionary()`), `nmt_state()` and `error_register()`.
///
/// ```
/// use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig, BatteryStatus, Temperature};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// let mut m = BatteryModule::new(BatteryModuleConfig::new(NodeId::new(1).unwrap()));
/// m.boot(Timestamp::ZERO);
/// assert_eq!(m.poll_transmit().unwrap().to_string(), "701#00");
/// m.set_temperature(Timestamp::ZERO, Temperature::from_celsius(25).unwrap());
/// m.set_battery_status(Timestamp::ZERO, BatteryStatus::READY_TO_CHARGE);
/// // NMT start: TPDO 0 (6010h, 6000h) goes out at once, then every 200 ms.
/// m.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x000, &[0x01, 0x01]).unwrap());
/// assert_eq!(m.poll_transmit().unwrap().to_string(), "181#C80001");
/// assert_eq!(m.poll_timeout(), Some(Timestamp::from_millis(200)));
/// ```
///
/// `Q` is the capacity of its event queue and of its queue of frames to
/// send ([`Device`]'s; default [`DEFAULT_QUEUE_CAPACITY`]): e.g.
/// `BatteryModule::<4>::new`; the firmware builds its module, 2 deep, in
/// place with [`ProfiledDevice::new_in`]:
///
/// ```
/// use core::mem::MaybeUninit;
/// use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{NodeId, Timestamp};
/// let mut slot = MaybeUninit::<BatteryModule<4>>::uninit();
/// let m = BatteryModule::new_in(&mut slot, BatteryModuleConfig::new(NodeId::MIN));
/// m.boot(Timestamp::ZERO);
/// assert_eq!(m.poll_transmit().unwrap().to_string(), "701#00");
/// ```
pub type BatteryModule<const Q: usize = DEFAULT_QUEUE_CAPACITY> =
    ProfiledDevice<BatteryModuleProfile, Q, 3, 3>;

/// A module is made from its configuration: the settings it keeps
/// ([`BatteryModulePowerOn`]), the CiA 418 power-on objects, and 1000h,
/// 1008h and 1018h written once.
impl DeviceSetup<BatteryModuleProfile> for BatteryModuleConfig {
    fn profile(&self) -> BatteryModuleProfile {
        BatteryModuleProfile
    }

    fn write_constants(&self, comm: &mut CommObjects) {
        comm.device_type = self.device_type.raw();
        comm.device_name = self.device_name;
        comm.identity = self.identity;
    }
}

/// The module's [`DeviceConfig`] is made from its configuration (CiA 418
/// default PDOs for its node-ID, so they follow an LSS node-ID change).
impl PowerOn for BatteryModulePowerOn {
    fn restore<const T: usize, const R: usize>(
        &self,
        comm: &mut CommObjects,
        pdos: &mut PdoConfig<T, R>,
    ) -> Policies {
        default_pdo_config(self, DeviceType::from_raw(comm.device_type), pdos);
        comm.reset_keeping_constants(self.node);
        comm.heartbeat_ms = self.heartbeat_ms;
        Policies::of_profile(self.sdo_timeout_ms, ErrorFieldFormat::LittleEndianInfo)
    }

    fn node(&self) -> NodeId {
        self.node
    }

    fn set_node(&mut self, node: NodeId) {
        self.node = node;
    }
}

/// The communication parameters of a row of [`DEFAULT_PDOS`] for a module
/// with `config`: its COB-ID for the node (a TPDO's made valid with
/// `enable_tpdos`), event-driven with its event timer and transmission type.
const fn default_comm(d: &DefaultPdo, node: NodeId, enable_tpdos: bool) -> PdoCommParams {
    let mut cob_id = PdoCobId::from_u32(d.cob_id(node));
    if matches!(d.direction, PdoDirection::Transmit) && enable_tpdos {
        cob_id = cob_id.with_valid(true);
    }
    let mut comm = PdoCommParams::event_driven(cob_id, d.event_timer_ms);
    if let Ok(tt) = TransmissionType::from_u8(d.transmission_type) {
        comm.transmission_type = tt;
    }
    comm
}

// Every row of the table maps validly (what `PdoSlot::from_table` needs):
// checked when the crate compiles, not at every reset.
const _: () = {
    let mut i = 0;
    while i < DEFAULT_PDOS.len() {
        assert!(
            PdoSlot::table_mapping_valid(DEFAULT_PDOS[i].entries),
            "a CiA 418 default PDO maps invalidly"
        );
        i += 1;
    }
};

/// Writes the CiA 418 default PDO set of a module with `config` and
/// `device_type` (its 1000h) into `pdos` (every slot), in place: one pass over the table, each present
/// PDO's slot written from its row (no mapping built and copied).
fn default_pdo_config<const T: usize, const R: usize>(
    config: &BatteryModulePowerOn,
    device_type: DeviceType,
    pdos: &mut PdoConfig<T, R>,
) {
    pdos.clear();
    for d in &DEFAULT_PDOS {
        if !d.is_present(device_type) {
            continue;
        }
        let comm = default_comm(d, config.node, config.enable_tpdos);
        pdos.insert(d.direction, d.number, PdoSlot::from_table(comm, d.entries));
    }
}

macro_rules! setters {
    ($($(#[$doc:meta])* $name:ident => $field:ident: $ty:ty;)*) => {
        $(
            $(#[$doc])*
            pub fn $name(&mut self, now: Timestamp, value: $ty) {
                self.update(now, |o| o.$field = value);
            }
        )*
    };
}

impl<const Q: usize> BatteryModule<Q> {
    // ----- getters ---------------------------------------------------------

    /// The configuration (its node-ID the active one, after an LSS
    /// change).
    #[must_use]
    pub fn config(&self) -> BatteryModuleConfig {
        self.power_on().config(self.comm())
    }

    /// True while the temperature sensor fault is set: 1001h's
    /// device-profile bit (CiA 418 v1.0.1, 6.2.2), which
    /// [`set_temperature_sensor_fault`](Self::set_temperature_sensor_fault)
    /// sets and clears and both resets clear.
    #[must_use]
    pub fn temperature_sensor_fault(&self) -> bool {
        self.error_register()
            .contains(ErrorRegister::DEVICE_PROFILE)
    }

    /// 6001h charger status, as the charger last wrote it.
    #[must_use]
    pub const fn charger_status(&self) -> ChargerStatus {
        self.device().objects().objects().charger_status
    }

    /// 6052h Ah returned during last charge.
    #[must_use]
    pub const fn ah_returned_during_last_charge(&self) -> EighthAmpHours {
        self.device()
            .objects()
            .objects()
            .ah_returned_during_last_charge
    }

    /// 6053h Ah since last equalization.
    #[must_use]
    pub const fn ah_since_last_equalization(&self) -> EighthAmpHours {
        self.device().objects().objects().ah_since_last_equalization
    }

    /// 6054h date of last equalization.
    #[must_use]
    pub const fn date_of_last_equalization(&self) -> EqualizationDate {
        self.device().objects().objects().date_of_last_equalization
    }

    /// 6080h charger state of charge, as the charger last wrote it.
    #[must_use]
    pub const fn charger_state_of_charge(&self) -> StateOfCharge {
        self.device().objects().objects().charger_state_of_charge
    }

    // ----- application commands --------------------------------------------

    setters! {
        /// Sets 6000h battery status.
        set_battery_status => battery_status: BatteryStatus;
        /// Sets 6010h temperature.
        set_temperature => temperature: Temperature;
        /// Sets 6020h battery parameters.
        set_battery_parameters => battery_parameters: BatteryParameters;
        /// Sets 6050h cumulative total Ah charge.
        set_cumulative_total_ah_charge => cumulative_total_ah_charge: AmpHours;
        /// Sets 6051h Ah expended since last charge.
        set_ah_expended_since_last_charge => ah_expended_since_last_charge: EighthAmpHours;
        /// Sets 6052h Ah returned during last charge.
        set_ah_returned_during_last_charge => ah_returned_during_last_charge: EighthAmpHours;
        /// Sets 6053h Ah since last equalization.
        set_ah_since_last_equalization => ah_since_last_equalization: EighthAmpHours;
        /// Sets 6054h date of last equalization.
        set_date_of_last_equalization => date_of_last_equalization: EqualizationDate;
        /// Sets 6060h battery voltage.
        set_battery_voltage => battery_voltage: BatteryVoltage;
        /// Sets 6070h charge current requested.
        set_charge_current_requested => charge_current_requested: ChargeCurrentRequested;
        /// Sets 6081h battery state of charge.
        set_battery_state_of_charge => battery_state_of_charge: StateOfCharge;
        /// Sets 6090h water level status.
        set_water_level => water_level: WaterLevelStatus;
    }

    /// Sets a packed string (6030h, 6031h, 6040h, 6041h).
    pub fn set_text(
        &mut self,
        object: PackedStringObject,
        text: &str,
    ) -> Result<(), PackedStringError> {
        self.device_mut().objects_mut().set_text(object, text)
    }

    /// Sets or clears the temperature sensor fault (CiA 418): on sets 1001h
    /// bits 0 and 5, records 5010h in 1003h and sends EMCY 5010h; off
    /// clears them (bit 0 only if no other bit is left) and sends the error
    /// reset 0000h. Repeating the current state does nothing.
    pub fn set_temperature_sensor_fault(&mut self, now: Timestamp, fault: bool) {
        if fault == self.temperature_sensor_fault() {
            return;
        }
        if fault {
            self.device_mut().raise_error(
                ErrorRegister::DEVICE_PROFILE,
                Emergency {
                    code: ErrorCode::TEMPERATURE_SENSOR_FAULT,
                    register: ErrorRegister::empty(),
                    manufacturer: [0; 5],
                },
            );
        } else {
            self.device_mut().clear_error(ErrorRegister::DEVICE_PROFILE);
        }
        self.device_mut().refresh_tpdos(now);
    }
}

#[cfg(test)]
#[path = "module_tests.rs"]
mod tests;
