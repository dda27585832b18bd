//! A complete CiA 418 battery module as one sans-IO state machine: its
//! object dictionary ([`BatteryObjects`] under the PDO objects), SDO server,
//! default PDOs, heartbeat producer, EMCY producer and NMT slave.
//!
//! # Driving it
//!
//! ```text
//! boot(now)                   once, at power-on: boot-up message, pre-operational
//! handle_frame(now, &frame)   every received frame (others' frames are ignored)
//! handle_timeout(now)         whenever poll_timeout's deadline has passed
//! poll_transmit()             send every frame until None
//! poll_event()                drain events until None
//! poll_timeout()              the earliest deadline of all internal timers
//! ```
//!
//! Drain `poll_transmit` after every call. Events are informational: the
//! queue keeps the latest 16 and drops the oldest when full, so an
//! application that never calls `poll_event` still has a working module.
//! The EMCY queue holds 8 frames; more are dropped until it is drained.
//! `poll_transmit` yields the heartbeat / boot-up frames first, then EMCY,
//! then SDO responses, then TPDOs.
//!
//! # Behaviour and choices
//!
//! - **NMT slave** (CiA 301): `000# cs node` for this node or for all (node
//!   0). Start (01h) enters operational, stop (02h) stopped, 80h
//!   pre-operational. Reset node (81h) and reset communication (82h) both
//!   send the boot-up message again, enter pre-operational, restore the PDO
//!   configuration (1400h-1A03h) and 1017h to the configured defaults and
//!   drop any SDO transfer in progress; they are reported as
//!   [`BatteryEvent::Reset`] (the application values 6000h-6090h belong to
//!   the application, which restores its own on a reset node). Before
//!   [`BatteryModule::boot`] every input is ignored.
//! - **SDO** is served in pre-operational and operational, not in stopped
//!   (entering stopped drops a running transfer silently).
//! - **TPDOs**: one [`TpdoProducer`] per TPDO the device type (1000h) declares
//!   (CiA 418 defaults, [`DEFAULT_PDOS`]), active only in operational. CiA 418
//!   makes the TPDO COB-IDs "not valid" (bit 31) by default; with
//!   [`BatteryModuleConfig::enable_tpdos`] (default `true`) the module clears
//!   bit 31 at boot and at every reset, so a module out of the box transmits
//!   its TPDOs every 200 ms once started. With `false` the CiA 418 default is
//!   kept and a configuration tool (or the application, through
//!   [`BatteryModule::pdo_config`]) enables them by SDO. The payload is read
//!   from the objects ([`read_mapped`]) before every transmission; a changed
//!   mapped value is an event (sent at once, subject to the inhibit time).
//! - **RPDOs**: a frame on a valid RPDO COB-ID is written into the mapped
//!   objects ([`write_mapped`]) only in operational. A payload shorter than
//!   the mapping is refused whole and raises EMCY 8210h (register byte: the
//!   current 1001h plus the generic and communication bits; the bits are
//!   not latched into 1001h). Remote frames are ignored.
//! - **EMCY** (0x80 + node): [`BatteryModule::set_temperature_sensor_fault`]
//!   sets 1001h bits 0 (generic) and 5 (device profile) and sends 5010h;
//!   clearing it clears bit 5 (and bit 0 if no other bit is left) and sends
//!   the error reset 0000h. EMCY frames are sent only in pre-operational and
//!   operational (CiA 301: not in stopped); 1001h changes in any state.
//! - **Heartbeat**: 701h-style boot-up at boot and resets, then the state
//!   every 1017h period; an SDO write to 1017h changes the period at once.
//! - Total: no frame, timestamp or call order panics.

use core::time::Duration;

use super::objects::{BatteryObjects, Identity};
use super::{
    AmpHours, BatteryParameters, BatteryStatus, BatteryVoltage, ChargeCurrentRequested,
    ChargerStatus, DeviceType, EighthAmpHours, EqualizationDate, PackedStringError,
    PackedStringObject, StateOfCharge, Temperature, WaterLevelStatus, DEFAULT_PDOS,
};
use crate::cob_id::{NodeId, PdoNumber, EMCY_BASE, NMT};
use crate::emcy::{Emergency, ErrorCode, ErrorRegister};
use crate::frame::{CanFrame, CanId};
use crate::heartbeat::HeartbeatProducer;
use crate::machine::Machine;
use crate::nmt::{NmtCommand, NmtCommandSpecifier, NmtState};
use crate::od::index::PRODUCER_HEARTBEAT_TIME;
use crate::pdo::{
    receive_rpdo, MappingEntry, PdoCobId, PdoCommParams, PdoConfig, PdoDictionary, PdoDirection,
    PdoMapping, PdoSlot, RpdoError, TpdoSet, TransmissionType, MAX_ENTRIES,
};
use crate::queue::Queue;
use crate::sdo::{AbortCode, AbortOrigin, Server, ServerConfig, ServerEvent, DEFAULT_TIMEOUT};
use crate::time::Timestamp;

/// The SYNC identifier (CiA 301).
const SYNC_ID: u16 = 0x080;

/// How a [`BatteryModule`] is set up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatteryModuleConfig {
    /// Node id (default 1, DIGEST section 1).
    pub node: NodeId,
    /// 1000h: profile 418 and the optional PDOs (bits 16-19) the module has
    /// (default: none, only the 1st RPDO and 1st TPDO).
    pub device_type: DeviceType,
    /// 1008h manufacturer device name.
    pub device_name: &'static str,
    /// 1018h identity.
    pub identity: Identity,
    /// 1017h producer heartbeat time in ms after boot and resets (default
    /// 1000; 0 = no heartbeat).
    pub heartbeat_ms: u16,
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
            identity: Identity {
                vendor_id: 0,
                product_code: 0,
                revision_number: 0,
                serial_number: 0,
            },
            heartbeat_ms: 1000,
            enable_tpdos: true,
            sdo_timeout: DEFAULT_TIMEOUT,
        }
    }
}

impl Default for BatteryModuleConfig {
    /// [`BatteryModuleConfig::new`] for node 1, the CiA 418 default.
    fn default() -> Self {
        Self::new(NodeId::MIN)
    }
}

/// What a [`BatteryModule`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BatteryEvent {
    /// The NMT state changed (boot, NMT command or reset).
    NmtStateChanged {
        /// The state before ([`NmtState::BootUp`] before the first boot).
        from: NmtState,
        /// The new state.
        to: NmtState,
    },
    /// An NMT reset was executed (followed by the boot-up message).
    Reset {
        /// `true` for reset node (81h): the application should restore its
        /// own values; `false` for reset communication (82h).
        node: bool,
    },
    /// An SDO download to an object completed.
    ObjectWritten {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
    /// An RPDO was written into the objects.
    RpdoReceived {
        /// The RPDO number (from 0).
        pdo: PdoNumber,
    },
    /// An RPDO was not (fully) processed.
    RpdoRefused {
        /// The RPDO number (from 0).
        pdo: PdoNumber,
        /// Why.
        error: RpdoError,
    },
    /// An SDO transfer ended in an abort.
    SdoAborted {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// The abort code.
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
}

type ModuleServer = Server<PdoDictionary<BatteryObjects>>;

/// A CiA 418 battery module. See the module docs for the driving loop and
/// the behaviour.
///
/// ```
/// use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig, BatteryStatus, Temperature};
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
#[derive(Debug)]
pub struct BatteryModule {
    config: BatteryModuleConfig,
    state: NmtState,
    server: ModuleServer,
    heartbeat: HeartbeatProducer,
    tpdos: TpdoSet,
    transmit: Queue<CanFrame, 8>,
    events: Queue<BatteryEvent, 16>,
    temperature_fault: bool,
}

/// The CiA 418 default PDO set of a module with `config`.
fn default_pdo_config(config: &BatteryModuleConfig) -> PdoConfig {
    let mut pdos = PdoConfig::new();
    for d in DEFAULT_PDOS
        .iter()
        .filter(|d| d.is_present(config.device_type))
    {
        let mut entries = [MappingEntry::default(); MAX_ENTRIES];
        for (e, &(index, sub, bits)) in entries.iter_mut().zip(d.entries) {
            *e = MappingEntry::new(index, sub, bits);
        }
        let mapping = PdoMapping::new(entries.get(..d.entries.len()).unwrap_or(&[]))
            .unwrap_or(PdoMapping::EMPTY);
        let mut cob_id = PdoCobId::from_u32(d.cob_id(config.node));
        if d.direction == PdoDirection::Transmit && config.enable_tpdos {
            cob_id = cob_id.with_valid(true);
        }
        let mut comm = PdoCommParams::event_driven(cob_id, d.event_timer_ms);
        if let Ok(tt) = TransmissionType::from_u8(d.transmission_type) {
            comm.transmission_type = tt;
        }
        pdos.insert(d.direction, d.number, PdoSlot::new(comm, &mapping));
    }
    pdos
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

impl BatteryModule {
    /// A module with `config`, not yet booted (call [`boot`](Self::boot)).
    #[must_use]
    pub fn new(config: BatteryModuleConfig) -> Self {
        let mut objects = BatteryObjects::new(config.node, config.device_name);
        objects.device_type = config.device_type;
        objects.identity = config.identity;
        objects.heartbeat_time_ms = config.heartbeat_ms;
        let od = PdoDictionary::new(default_pdo_config(&config), objects);
        BatteryModule {
            config,
            state: NmtState::BootUp,
            server: Server::new(Self::server_config(&config), od),
            heartbeat: HeartbeatProducer::new(
                config.node,
                Duration::from_millis(u64::from(config.heartbeat_ms)),
            ),
            tpdos: TpdoSet::new(),
            transmit: Queue::new(CanFrame::EMPTY),
            events: Queue::new(BatteryEvent::Reset { node: false }),
            temperature_fault: false,
        }
    }

    fn server_config(config: &BatteryModuleConfig) -> ServerConfig {
        let mut sc = ServerConfig::for_node(config.node);
        sc.timeout = config.sdo_timeout;
        sc
    }

    // ----- getters ---------------------------------------------------------

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &BatteryModuleConfig {
        &self.config
    }

    /// The node id.
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.config.node
    }

    /// The NMT state ([`NmtState::BootUp`] until [`boot`](Self::boot)).
    #[must_use]
    pub const fn nmt_state(&self) -> NmtState {
        self.state
    }

    /// The object values.
    #[must_use]
    pub const fn objects(&self) -> &BatteryObjects {
        &self.server.od().inner
    }

    /// The PDO configuration (1400h-1A03h) as the SDO server sees it.
    #[must_use]
    pub const fn pdo_config(&self) -> &PdoConfig {
        &self.server.od().config
    }

    /// 1001h error register.
    #[must_use]
    pub const fn error_register(&self) -> ErrorRegister {
        self.objects().error_register
    }

    /// True while the temperature sensor fault is set.
    #[must_use]
    pub const fn temperature_sensor_fault(&self) -> bool {
        self.temperature_fault
    }

    /// 6001h charger status, as the charger last wrote it.
    #[must_use]
    pub const fn charger_status(&self) -> ChargerStatus {
        self.objects().charger_status
    }

    /// 6052h Ah returned during last charge.
    #[must_use]
    pub const fn ah_returned_during_last_charge(&self) -> EighthAmpHours {
        self.objects().ah_returned_during_last_charge
    }

    /// 6053h Ah since last equalization.
    #[must_use]
    pub const fn ah_since_last_equalization(&self) -> EighthAmpHours {
        self.objects().ah_since_last_equalization
    }

    /// 6054h date of last equalization.
    #[must_use]
    pub const fn date_of_last_equalization(&self) -> EqualizationDate {
        self.objects().date_of_last_equalization
    }

    /// 6080h charger state of charge, as the charger last wrote it.
    #[must_use]
    pub const fn charger_state_of_charge(&self) -> StateOfCharge {
        self.objects().charger_state_of_charge
    }

    // ----- application commands --------------------------------------------

    /// Changes object values in `f`; mapped values that changed are events
    /// for the event-driven TPDOs, and a changed 1017h re-arms the heartbeat.
    pub fn update(&mut self, now: Timestamp, f: impl FnOnce(&mut BatteryObjects)) {
        let period = self.objects().heartbeat_time_ms;
        f(&mut self.server.od_mut().inner);
        let new_period = self.objects().heartbeat_time_ms;
        if new_period != period {
            self.heartbeat
                .set_period(now, Duration::from_millis(u64::from(new_period)));
        }
        self.refresh_tpdos(now);
    }

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
        self.server.od_mut().inner.set_text(object, text)
    }

    /// Sets or clears the temperature sensor fault (CiA 418): on sets 1001h
    /// bits 0 and 5 and sends EMCY 5010h; off clears them (bit 0 only if no
    /// other bit is left) and sends the error reset 0000h. Repeating the
    /// current state does nothing.
    pub fn set_temperature_sensor_fault(&mut self, now: Timestamp, fault: bool) {
        if fault == self.temperature_fault {
            return;
        }
        self.temperature_fault = fault;
        let reg = &mut self.server.od_mut().inner.error_register;
        let code = if fault {
            *reg |= ErrorRegister::GENERIC | ErrorRegister::DEVICE_PROFILE;
            ErrorCode::TEMPERATURE_SENSOR_FAULT
        } else {
            reg.remove(ErrorRegister::DEVICE_PROFILE);
            if reg.difference(ErrorRegister::GENERIC).is_empty() {
                reg.remove(ErrorRegister::GENERIC);
            }
            ErrorCode::NO_ERROR
        };
        let register = *reg;
        self.send_emcy(code, register);
        self.refresh_tpdos(now);
    }

    /// Boots (or re-boots) the module: boot-up message, default PDO
    /// configuration and 1017h, pre-operational.
    pub fn boot(&mut self, now: Timestamp) {
        self.restart(now);
    }

    // ----- inputs ----------------------------------------------------------

    /// Feeds a received frame: NMT, SYNC, this node's SDO requests and RPDOs;
    /// everything else is ignored.
    pub fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if self.state == NmtState::BootUp || frame.is_remote() {
            return;
        }
        let id = frame.id();
        if id == CanId::Standard(NMT) {
            self.handle_nmt(now, frame.data());
            return;
        }
        if id == CanId::Standard(SYNC_ID) && self.state == NmtState::Operational {
            self.refresh_tpdos(now);
            self.tpdos.handle_sync(now);
        }
        if self.sdo_allowed() {
            self.server.handle_frame(now, frame);
            self.drain_server(now);
        }
        if self.state == NmtState::Operational {
            self.handle_rpdo(now, frame);
        }
    }

    /// Tells the module time has passed: SDO timeout, heartbeat, TPDO timers.
    pub fn handle_timeout(&mut self, now: Timestamp) {
        if self.state == NmtState::BootUp {
            return;
        }
        self.server.handle_timeout(now);
        self.drain_server(now);
        self.heartbeat.handle_timeout(now);
        self.refresh_tpdos(now);
        self.tpdos.handle_timeout(now);
    }

    // ----- outputs ---------------------------------------------------------

    /// The next frame to send.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<CanFrame> {
        if let Some(f) = self.heartbeat.poll_transmit() {
            return Some(f);
        }
        if let Some(f) = self.transmit.pop() {
            return Some(f);
        }
        if let Some(f) = self.server.poll_transmit() {
            return Some(f);
        }
        self.tpdos.poll_transmit()
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<BatteryEvent> {
        self.events.pop()
    }

    /// When [`handle_timeout`](Self::handle_timeout) must next be called:
    /// the minimum over the SDO, heartbeat and TPDO timers.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Timestamp> {
        if self.state == NmtState::BootUp {
            return None;
        }
        [self.server.poll_timeout(), self.heartbeat.poll_timeout()]
            .into_iter()
            .chain([self.tpdos.poll_timeout()])
            .flatten()
            .min()
    }

    // ----- internals -------------------------------------------------------

    const fn sdo_allowed(&self) -> bool {
        matches!(self.state, NmtState::PreOperational | NmtState::Operational)
    }

    /// Queues an event; when the queue is full the oldest is dropped.
    fn push_event(&mut self, event: BatteryEvent) {
        if !self.events.push(event) {
            let _ = self.events.pop();
            let _ = self.events.push(event);
        }
    }

    fn handle_nmt(&mut self, now: Timestamp, data: &[u8]) {
        let Ok(cmd) = NmtCommand::decode(data) else {
            return;
        };
        if !cmd.target.addresses(self.config.node) {
            return;
        }
        match cmd.command {
            NmtCommandSpecifier::Start => self.set_state(now, NmtState::Operational),
            NmtCommandSpecifier::Stop => self.set_state(now, NmtState::Stopped),
            NmtCommandSpecifier::EnterPreOperational => {
                self.set_state(now, NmtState::PreOperational);
            }
            NmtCommandSpecifier::ResetNode => {
                self.push_event(BatteryEvent::Reset { node: true });
                self.restart(now);
            }
            NmtCommandSpecifier::ResetCommunication => {
                self.push_event(BatteryEvent::Reset { node: false });
                self.restart(now);
            }
            NmtCommandSpecifier::Unknown(_) => {}
        }
    }

    /// Reset communication: fresh SDO server, default PDOs and 1017h,
    /// boot-up message, pre-operational.
    fn restart(&mut self, now: Timestamp) {
        self.reset_server(true);
        let period = self.config.heartbeat_ms;
        self.server.od_mut().inner.heartbeat_time_ms = period;
        let send_on_change = self.heartbeat.send_on_change;
        self.heartbeat =
            HeartbeatProducer::new(self.config.node, Duration::from_millis(u64::from(period)));
        self.heartbeat.send_on_change = send_on_change;
        self.heartbeat.boot(now);
        self.tpdos = TpdoSet::new();
        self.refresh_tpdos(now);
        self.sync_tpdos(now);
        self.set_state(now, NmtState::PreOperational);
    }

    /// Replaces the SDO server (dropping a running transfer silently),
    /// optionally restoring the default PDO configuration.
    fn reset_server(&mut self, default_pdos: bool) {
        let config = Self::server_config(&self.config);
        let placeholder =
            PdoDictionary::new(PdoConfig::new(), BatteryObjects::new(self.config.node, ""));
        let old = core::mem::replace(&mut self.server, Server::new(config, placeholder));
        let od = old.into_inner();
        let pdos = if default_pdos {
            default_pdo_config(&self.config)
        } else {
            od.config
        };
        let mut inner = od.inner;
        inner.abort_pending();
        self.server = Server::new(config, PdoDictionary::new(pdos, inner));
    }

    fn set_state(&mut self, now: Timestamp, to: NmtState) {
        let from = self.state;
        if from == to {
            return;
        }
        self.state = to;
        if to == NmtState::Stopped {
            self.reset_server(false);
        }
        self.heartbeat.set_state(now, to);
        let operational = to == NmtState::Operational;
        if operational {
            self.refresh_tpdos(now);
        }
        self.tpdos.set_operational(now, operational);
        self.push_event(BatteryEvent::NmtStateChanged { from, to });
    }

    fn send_emcy(&mut self, code: ErrorCode, register: ErrorRegister) {
        if !self.sdo_allowed() {
            return;
        }
        let emcy = Emergency {
            code,
            register,
            manufacturer: [0; 5],
        };
        let id = CanId::Standard(EMCY_BASE + u16::from(self.config.node.raw()));
        if let Ok(frame) = CanFrame::new(id, &emcy.encode()) {
            let _ = self.transmit.push(frame);
        }
    }

    fn handle_rpdo(&mut self, now: Timestamp, frame: &CanFrame) {
        let Some((pdo, result)) = receive_rpdo(self.server.od_mut(), frame) else {
            return;
        };
        match result {
            Ok(_) => self.push_event(BatteryEvent::RpdoReceived { pdo }),
            Err(error) => {
                if let Some(code) = error.emcy_code() {
                    let register = self.error_register()
                        | ErrorRegister::GENERIC
                        | ErrorRegister::COMMUNICATION;
                    self.send_emcy(code, register);
                }
                self.push_event(BatteryEvent::RpdoRefused { pdo, error });
            }
        }
        self.refresh_tpdos(now);
    }

    /// Hands the SDO server's events on and reacts to written objects.
    fn drain_server(&mut self, now: Timestamp) {
        let mut written = false;
        while let Some(event) = self.server.poll_event() {
            match event {
                ServerEvent::Downloaded { index, sub, .. } => {
                    if index == PRODUCER_HEARTBEAT_TIME {
                        let period = self.objects().heartbeat_time_ms;
                        self.heartbeat
                            .set_period(now, Duration::from_millis(u64::from(period)));
                    }
                    written = true;
                    self.push_event(BatteryEvent::ObjectWritten { index, sub });
                }
                ServerEvent::Aborted {
                    index,
                    sub,
                    code,
                    origin,
                } => self.push_event(BatteryEvent::SdoAborted {
                    index,
                    sub,
                    code,
                    origin,
                }),
                ServerEvent::Uploaded { .. } => {}
            }
        }
        if written {
            self.refresh_tpdos(now);
            self.sync_tpdos(now);
        }
    }

    fn refresh_tpdos(&mut self, now: Timestamp) {
        self.tpdos.refresh(now, self.server.od_mut());
    }

    fn sync_tpdos(&mut self, now: Timestamp) {
        self.tpdos.sync(now, &self.server.od().config);
    }
}

impl crate::machine::Machine for BatteryModule {
    type Event = BatteryEvent;
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        Self::handle_frame(self, now, frame);
    }
    fn handle_timeout(&mut self, now: Timestamp) {
        Self::handle_timeout(self, now);
    }
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        Self::poll_transmit(self)
    }
    fn poll_timeout(&self) -> Option<Timestamp> {
        Self::poll_timeout(self)
    }
    fn poll_event(&mut self) -> Option<BatteryEvent> {
        Self::poll_event(self)
    }
    fn events_dropped(&self) -> u64 {
        0
    }
}

#[cfg(test)]
#[path = "module_tests.rs"]
mod tests;
