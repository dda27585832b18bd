//! A whole charge session in simulated time: the Delta-Q charger
//! ([`Charger`], with its [`ChargeControl`](crate::deltaq::charge::ChargeControl))
//! and the CiA 418 battery module ([`BatteryModule`]) on one simulated
//! bus of the caller's clock, the pack and the power stage between them,
//! and the BMS's SDO client for the writes a BMS makes (2241h, 2250h,
//! 2271h, the charger's TPDO 3). Hours of charge run in milliseconds;
//! the same inputs give the same log.
//!
//! The nodes run on the library's simulated bus ([`Bus`]): every frame is
//! delivered to the other nodes one [`SessionConfig::bus_latency`] after it
//! is sent (none by default) unless the bus loses it
//! ([`SessionConfig::bus_loss`], seeded: the same configuration loses the
//! same frames; [`Session::set_loss`]) or is off ([`Session::bus_off`]),
//! and every frame that reached the bus is kept in [`Session::log`]. The
//! bus models each node's CAN controller ([`Bus::confine_errors`]): a bus
//! that is off takes a node that sends to bus-off, a heavy loss takes it
//! error passive, and the charger's application reports its controller's
//! state to it as a real one reads its CAN controller's status (Delta-Q
//! E-0-2-9 while not error active). The physics runs every
//! [`SessionConfig::tick`]: the power stage follows the charger's set
//! points, the pack takes its current, the charger gets the measurements
//! and the module's objects (6000h, 6010h, 6060h, 6070h, 6081h) come from
//! the pack and the [`BmsPolicy`]. The module's side is the NMT master, as
//! the BMS in the real ICL1500 capture: it starts every node at 20 ms and
//! starts the charger again whenever its heartbeat says pre-operational
//! (the charger leaves operational when it takes the module as gone); on
//! the bus that BMS is one more machine ([`BmsMaster`]), on the CAN bus
//! exactly when the module is.

use alloc::vec::Vec;
use core::time::Duration;

use super::bus::{Bus, ControllerState, Handle, Sent};
use super::{BmsPolicy, Pack, PackSpec, PowerStageModel};
use crate::cia418::{BatteryModule, BatteryModuleConfig, Chemistry, DeviceType};
use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::deltaq::charge::{ChargeEvent, ChargePhase};
use crate::deltaq::{Charger, ChargerConfig, ChargerEvent, DeltaQCode, OperatingMode};
use crate::emcy::{Emergency, ErrorCode, ErrorRegister};
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::nmt::{Heartbeat, NmtCommand, NmtCommandSpecifier, NmtState, NmtTarget};
use crate::queue::FrameSlot;
use crate::sdo::{Client, ClientConfig};
use crate::wire::Codec;

/// The charger's node id (Delta-Q default).
pub const CHARGER_NODE: NodeId = match NodeId::new(10) {
    Some(n) => n,
    None => NodeId::MIN,
};

/// The battery module's node id (CiA 418 default).
pub const MODULE_NODE: NodeId = NodeId::MIN;

/// How a session is set up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SessionConfig {
    /// The charger's configuration (node 10, battery node 1, its mode and
    /// its charge control's algorithms).
    pub charger: ChargerConfig,
    /// The module's configuration (node 1, every optional PDO).
    pub module: BatteryModuleConfig,
    /// The pack.
    pub pack: PackSpec,
    /// State of charge at the start, 0..=1.
    pub start_soc: f64,
    /// The most the module asks for (6020h sub 3), A.
    pub max_current_a: f64,
    /// The physics step.
    pub tick: Duration,
    /// The module is on the CAN bus from the start.
    pub module_on_can: bool,
    /// How long a frame takes from its sender to the other nodes.
    pub bus_latency: Duration,
    /// The probability that a frame is lost on the bus (0: none), drawn
    /// from a generator seeded with [`bus_seed`](Self::bus_seed): the same
    /// configuration loses the same frames.
    pub bus_loss: f64,
    /// The seed of the bus's loss.
    pub bus_seed: u64,
}

impl SessionConfig {
    /// A 48 V session in `mode`: a pack of `chemistry` (24 lead-acid, 40
    /// nickel or 13 lithium-ion cells, [`PackSpec::cells_for`]) of
    /// `capacity_ah`, at `start_soc`; the rest as [`for_pack`](Self::for_pack).
    pub fn new(
        mode: OperatingMode,
        chemistry: Chemistry,
        capacity_ah: f64,
        start_soc: f64,
    ) -> Result<Self, super::PackError> {
        let cells = PackSpec::cells_for(chemistry, 48.0).max(1);
        let pack = PackSpec::new(chemistry, cells, capacity_ah)?;
        Ok(Self::for_pack(mode, pack, start_soc))
    }

    /// A session in `mode` of `pack` at `start_soc`, the module asking up
    /// to 25 A, a 250 ms physics step. The charger has no permanent
    /// algorithm: as a Delta-Q charger on a CANopen battery it charges
    /// with the algorithm of its table for the battery the module reports
    /// in 6020h ([`Identification`](crate::deltaq::charge::Identification);
    /// none fits: none, E-0-2-0 in local mode). Its no-CAN algorithm (the
    /// default without a module, or when the 6020h read fails; what a
    /// monitoring charger runs) is the table's for `pack`
    /// ([`select`](crate::deltaq::charge::algorithm::select) on its type
    /// and cells, as the installer sets it for the fleet's battery), none
    /// when none fits.
    #[must_use]
    pub fn for_pack(mode: OperatingMode, pack: PackSpec, start_soc: f64) -> Self {
        let mut charger = ChargerConfig::new(CHARGER_NODE, MODULE_NODE);
        let table = charger.charge.algorithms;
        let fits =
            crate::deltaq::charge::algorithm::select(table, pack.battery_type.into(), pack.cells);
        charger.mode = mode;
        charger.charge.permanent_algorithm = None;
        charger.charge.no_can_algorithm = fits.map(|a| a.id);
        let mut module = BatteryModuleConfig::new(MODULE_NODE);
        module.device_type = DeviceType::cia418(
            DeviceType::RPDO_2ND
                | DeviceType::RPDO_3RD
                | DeviceType::TPDO_2ND
                | DeviceType::TPDO_3RD,
        );
        module.device_name = "canopen-codec battery module";
        SessionConfig {
            charger,
            module,
            pack,
            start_soc,
            max_current_a: 25.0,
            tick: Duration::from_millis(250),
            module_on_can: true,
            bus_latency: Duration::ZERO,
            bus_loss: 0.0,
            bus_seed: DEFAULT_SEED,
        }
    }
}

/// The seed of a session's lossy bus unless its configuration says
/// otherwise.
pub const DEFAULT_SEED: u64 = 0x5EED_CA11;

/// The wall-clock time a session's log starts at when written
/// ([`Session::candump`]): 2026-01-01 00:00:00 UTC in microseconds, so the
/// times read as dates.
pub const LOG_EPOCH: Timestamp = Timestamp::from_micros(1_767_225_600_000_000);

/// One frame on the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Logged {
    /// When it was sent.
    pub at: Timestamp,
    /// The frame.
    pub frame: CanFrame,
}

/// The BMS as the NMT master (as in the real ICL1500 capture): it hears
/// the charger's heartbeat and starts the charger again whenever it says
/// pre-operational. A machine on the session's bus, connected exactly
/// when the battery module is.
#[derive(Debug)]
pub struct BmsMaster {
    out: FrameSlot,
}

impl BmsMaster {
    const fn new() -> Self {
        BmsMaster {
            out: FrameSlot::new(),
        }
    }
}

impl Machine for BmsMaster {
    type Event = core::convert::Infallible;

    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        let charger_heartbeat = 0x700 + u32::from(CHARGER_NODE.raw());
        if frame.identity() == charger_heartbeat
            && Heartbeat::parse_frame(frame) == Ok(Heartbeat::new(NmtState::PreOperational))
        {
            let start = NmtCommand::new(NmtCommandSpecifier::Start, NmtTarget::Node(CHARGER_NODE));
            self.out.push(start.to_frame());
        }
    }

    fn handle_timeout(&mut self, _now: Timestamp) {}

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    crate::machine::queued_outputs!(frames: out, events: none);
}

/// The figures of a session.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionResult {
    /// State of charge at the start and now, 0..=1.
    pub start_soc: f64,
    /// State of charge now.
    pub end_soc: f64,
    /// How long the session ran.
    pub duration: Duration,
    /// Every phase the charge control entered, with its time.
    pub phases: Vec<(Timestamp, ChargePhase)>,
    /// Charge into the pack, Ah.
    pub ah: f64,
    /// Energy into the pack, Wh.
    pub wh: f64,
    /// The charger's Delta-Q alarms and faults, as its EMCYs sent them.
    pub errors: Vec<(Timestamp, DeltaQCode)>,
    /// The pack's highest temperature, degC.
    pub max_pack_temperature_c: f64,
}

/// Same-instant bus steps after which a session moves its clock on by a
/// microsecond: a deadline a machine keeps re-arming in the past cannot
/// hold the clock.
const MAX_STEPS_AT_ONE_INSTANT: u32 = 100_000;

/// A charger and a battery module on a simulated bus (see the module docs).
#[derive(Debug)]
pub struct Session {
    next_tick: Timestamp,
    tick: Duration,
    bus: Bus,
    charger: Handle<Charger>,
    module: Handle<BatteryModule>,
    master: Handle<BmsMaster>,
    tool: Handle<Client<Vec<u8>>>,
    /// The pack.
    pub pack: Pack,
    /// The power stage.
    pub stage: PowerStageModel,
    /// The module's charge policy.
    pub bms: BmsPolicy,
    /// Enable the charger's TPDO 3 (0x48A: 2002h, 2100h, 2006h) by SDO
    /// once the charger is configured, as a monitoring BMS does.
    pub enable_charger_tpdo3: bool,
    pending_writes: Vec<(u16, u8, Vec<u8>)>,
    log: Vec<Logged>,
    /// The bus's log of the last step, read into [`log`](Self::log) (its
    /// storage kept from step to step).
    sent: Vec<Sent>,
    phases: Vec<(Timestamp, ChargePhase)>,
    start_soc: f64,
    ah: f64,
    wh: f64,
    max_temperature: f64,
    bus_seed: u64,
    /// The charger's CAN controller's state as last reported to it.
    controller: ControllerState,
    /// The charger's alarms and faults active now, in the order raised.
    active: Vec<DeltaQCode>,
    /// Every raise and clear of them.
    alarm_changes: Vec<AlarmChange>,
}

/// A Delta-Q alarm or fault of the charger raised or cleared ("Delta-Q IC
/// Series CANopen interface specification rev 2.0", section 4.4.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlarmChange {
    /// When.
    pub at: Timestamp,
    /// The alarm or fault.
    pub code: DeltaQCode,
    /// Raised (`true`) or cleared.
    pub raised: bool,
}

impl Session {
    /// The two nodes of `config`, not yet booted: set the pack, the stage
    /// and the BMS as the session begins, then [`start`](Self::start) it.
    #[must_use]
    pub fn new(config: &SessionConfig) -> Self {
        let pack = Pack::new(config.pack, config.start_soc);
        let mut bms = BmsPolicy::for_pack(&config.pack, config.max_current_a);
        bms.ends_charge = matches!(config.charger.mode, OperatingMode::Remote);
        let mut module = BatteryModule::new(config.module);
        let spec = config.pack;
        let max_current = config.max_current_a;
        module.update(Timestamp::ZERO, |o| {
            o.battery_parameters.battery_type = spec.battery_type;
            o.battery_parameters.ah_capacity = spec.capacity_ah.round().clamp(0.0, 65535.0) as u16;
            o.battery_parameters.max_charge_current =
                max_current.round().clamp(0.0, 65535.0) as u16;
            o.battery_parameters.number_of_cells = spec.cells;
        });
        let mut bus = Bus::new(config.bus_latency);
        bus.set_loss(config.bus_loss, config.bus_seed);
        bus.confine_errors(true);
        let charger = bus.add("Charger", Charger::new(config.charger));
        let module = bus.add("Module", module);
        let master = bus.add("BMS", BmsMaster::new());
        let tool = bus.add("Tool", Client::new(ClientConfig::for_server(CHARGER_NODE)));
        // The module's and the tool's events are of no use to the session.
        bus.set_drain_events(module, false);
        bus.set_drain_events(tool, false);
        let mut s = Session {
            next_tick: Timestamp::ZERO,
            tick: config.tick.max(Duration::from_millis(1)),
            bus,
            charger,
            module,
            master,
            tool,
            pack,
            stage: PowerStageModel::new(f64::from(config.charger.charge.max_power_w)),
            bms,
            enable_charger_tpdo3: true,
            pending_writes: Vec::new(),
            log: Vec::new(),
            sent: Vec::new(),
            phases: Vec::from([(Timestamp::ZERO, ChargePhase::Idle)]),
            start_soc: pack.soc(),
            ah: 0.0,
            wh: 0.0,
            max_temperature: pack.temperature_c(),
            bus_seed: config.bus_seed,
            controller: ControllerState::ErrorActive,
            active: Vec::new(),
            alarm_changes: Vec::new(),
        };
        s.set_module_on_can(config.module_on_can);
        s
    }

    /// Boots both nodes at time zero with the first measurements; the BMS
    /// (the module's side) starts every node with NMT at 20 ms, as in the
    /// real ICL1500 capture.
    pub fn start(&mut self) {
        let _ = self.bus.with(self.charger, |c, now| c.boot(now));
        let _ = self.bus.with(self.module, |m, now| m.boot(now));
        self.physics(0.0);
        self.next_tick = Timestamp::ZERO.add_duration(self.tick);
        self.run_until(Timestamp::from_millis(20));
        let start_all = NmtCommand::new(NmtCommandSpecifier::Start, NmtTarget::All);
        self.inject(start_all.to_frame());
    }

    /// The time now.
    #[must_use]
    pub const fn now(&self) -> Timestamp {
        self.bus.now()
    }

    /// The charger (`None` never: the session's bus holds it from
    /// [`new`](Self::new) on).
    #[must_use]
    pub fn charger(&self) -> Option<&Charger> {
        self.bus.machine(self.charger)
    }

    /// The battery module (`None` never, as [`charger`](Self::charger)).
    #[must_use]
    pub fn module(&self) -> Option<&BatteryModule> {
        self.bus.machine(self.module)
    }

    /// The simulated bus the nodes run on (its own log is taken into
    /// [`log`](Self::log) as the session runs).
    #[must_use]
    pub const fn bus(&self) -> &Bus {
        &self.bus
    }

    /// Every frame that reached the bus so far.
    #[must_use]
    pub fn log(&self) -> &[Logged] {
        &self.log
    }

    /// The log as candump log lines (`(seconds) INTERFACE ID#DATA`), times
    /// from [`LOG_EPOCH`].
    pub fn candump<'a>(
        &'a self,
        interface: &'a str,
    ) -> impl Iterator<Item = crate::trace::candump::LogLineDisplay<'a>> + 'a {
        self.log
            .iter()
            .map(move |l| crate::trace::candump::LogLineDisplay {
                timestamp: Timestamp::from_micros(LOG_EPOCH.as_micros() + l.at.as_micros()),
                interface,
                frame: &l.frame,
            })
    }

    /// Every phase the charge control entered so far, with its time.
    #[must_use]
    pub fn phases(&self) -> &[(Timestamp, ChargePhase)] {
        &self.phases
    }

    /// The phase the charge control is in.
    #[must_use]
    pub fn phase(&self) -> ChargePhase {
        self.charger()
            .map_or(ChargePhase::Idle, |c| c.charge_control().phase())
    }

    /// Puts `frame` on the bus now (another node's: an NMT master's).
    pub fn inject(&mut self, frame: CanFrame) {
        self.bus.inject(frame);
        self.settle();
    }

    /// The module joins (`true`) or leaves the CAN bus: its frames stop
    /// reaching anyone (its heartbeat is lost) and nothing reaches it; the
    /// BMS's NMT master goes with it.
    pub fn set_module_on_can(&mut self, on: bool) {
        self.bus.set_connected(self.module, on);
        self.bus.set_connected(self.master, on);
    }

    /// The charger's CAN controller's state now (ISO 11898-1 fault
    /// confinement, on the session's bus): what its application reports
    /// to it (E-0-2-9 while not error active).
    #[must_use]
    pub fn charger_controller(&self) -> ControllerState {
        self.bus.controller_state(self.charger)
    }

    /// From now on each frame is lost with `probability` (0: none), drawn
    /// from the generator of the configuration's
    /// [`bus_seed`](SessionConfig::bus_seed).
    pub fn set_loss(&mut self, probability: f64) {
        self.bus.set_loss(probability, self.bus_seed);
    }

    /// The bus is off for `duration` from now (a CAN bus error: shorted
    /// or open lines): nothing is sent or delivered. A node that tries to
    /// send fails every retransmission, and the error counters of ISO
    /// 11898-1 take its controller to bus-off until the bus is back and it
    /// has recovered; the charger's reports it (Delta-Q E-0-2-9) from its
    /// first frame in the window until then.
    pub fn bus_off(&mut self, duration: Duration) {
        let now = self.now();
        self.bus.bus_off(now, now.add_duration(duration));
        self.settle();
    }

    /// The charger's alarms and faults active now, in the order raised
    /// (from its events and the EMCYs it sent, whether or not they reached
    /// the bus).
    #[must_use]
    pub fn active_alarms(&self) -> &[DeltaQCode] {
        &self.active
    }

    /// Every raise and clear of the charger's alarms and faults so far.
    #[must_use]
    pub fn alarm_changes(&self) -> &[AlarmChange] {
        &self.alarm_changes
    }

    /// The battery module signals `code` by EMCY (CiA 301 section 7.2.7;
    /// CiA 418's codes): 5010h is its temperature sensor fault (6010h no
    /// longer valid); any other code is recorded in its 1003h with its
    /// 1001h bit (current, voltage, temperature, communication, else
    /// manufacturer) and sent; 0000h clears them all (the error reset).
    /// Sent only while the module is on the bus, as its other frames.
    pub fn module_emcy(&mut self, code: u16) {
        let _ = self.bus.with(self.module, |m, now| match code {
            0 => {
                m.set_temperature_sensor_fault(now, false);
                m.device_mut().clear_error(ErrorRegister::all());
            }
            0x5010 => m.set_temperature_sensor_fault(now, true),
            _ => {
                let bits = match code >> 12 {
                    2 => ErrorRegister::CURRENT,
                    3 => ErrorRegister::VOLTAGE,
                    4 => ErrorRegister::TEMPERATURE,
                    8 => ErrorRegister::COMMUNICATION,
                    _ => ErrorRegister::MANUFACTURER,
                };
                let emcy = Emergency {
                    code: ErrorCode(code),
                    register: ErrorRegister::empty(),
                    manufacturer: [0; 5],
                };
                m.device_mut().raise_error(bits, emcy);
            }
        });
        self.settle();
    }

    /// AC on or off at the charger.
    pub fn set_ac(&mut self, on: bool) {
        self.stage.set_ac(on);
        self.physics(0.0);
        self.settle();
    }

    /// The mains at the charger is `volts` RMS (0: off; Delta-Q section
    /// 4.4.1: too high raises E-0-2-3).
    pub fn set_ac_voltage(&mut self, volts: f64) {
        self.stage.set_ac_voltage(volts);
        self.physics(0.0);
        self.settle();
    }

    /// The battery's leads are connected the wrong way round (`true`) or
    /// the right way.
    pub fn set_reverse_polarity(&mut self, reversed: bool) {
        self.stage.set_reverse_polarity(reversed);
        self.physics(0.0);
        self.settle();
    }

    /// The power stage's monitoring reports hardware `fault` (F-0-0-1..6)
    /// from now on (`true`) or no longer.
    pub fn inject_fault(&mut self, fault: crate::deltaq::charge::StageFaults, on: bool) {
        self.stage.inject_fault(fault, on);
        self.physics(0.0);
        self.settle();
    }

    /// The battery's DC leads connected to the charger or not.
    pub fn set_battery_connected(&mut self, on: bool) {
        self.stage.battery_connected = on;
        self.physics(0.0);
        self.settle();
    }

    /// The BMS writes `value` to the charger's `index`/`sub` by SDO
    /// (queued behind the writes before it).
    pub fn write_charger(&mut self, index: u16, sub: u8, value: &[u8]) {
        self.pending_writes.push((index, sub, value.to_vec()));
        self.start_next_write();
        self.settle();
    }

    fn start_next_write(&mut self) {
        let idle = self.bus.machine(self.tool).is_some_and(|t| !t.is_busy());
        if idle && !self.pending_writes.is_empty() {
            let (index, sub, data) = self.pending_writes.remove(0);
            let _ = self
                .bus
                .with(self.tool, |t, now| t.start_download(now, index, sub, data));
        }
    }

    /// Runs until `end`: the bus's deliveries and timers, and the physics
    /// every tick (after the bus at the same instant).
    pub fn run_until(&mut self, end: Timestamp) {
        let mut same = 0u32;
        loop {
            self.after_step();
            let now = self.bus.now();
            let due = self.bus.next_due();
            let back = self.bus.recovers_at(self.charger);
            let Some(next) = crate::clock::earliest([due, Some(self.next_tick), back]) else {
                break;
            };
            if !end.has_reached(next) {
                self.bus.advance(end);
                break;
            }
            if let Some(back) = back.filter(|b| next.has_reached(*b)) {
                self.bus.advance(back);
                continue;
            }
            if due.is_some_and(|d| self.next_tick.has_reached(d)) {
                same = if now.has_reached(next) { same + 1 } else { 0 };
                if same > MAX_STEPS_AT_ONE_INSTANT {
                    same = 0;
                    self.bus.advance(now.add_micros(1));
                }
                let _ = self.bus.step(next.max(self.bus.now()));
            } else {
                self.bus.advance(self.next_tick);
                while self.bus.now().has_reached(self.next_tick) {
                    let dt = self.tick.as_secs_f64();
                    self.next_tick = self.next_tick.add_duration(self.tick);
                    self.physics(dt);
                }
            }
        }
        self.after_step();
    }

    /// Runs while `condition` holds, at most until `limit`, checking every
    /// simulated second; returns whether it stopped on the condition.
    pub fn run_while(
        &mut self,
        limit: Timestamp,
        mut condition: impl FnMut(&Session) -> bool,
    ) -> bool {
        while self.now() < limit {
            if !condition(self) {
                return true;
            }
            let step = self.now().add_millis(1000).min(limit);
            self.run_until(step);
        }
        !condition(self)
    }

    /// The figures so far.
    #[must_use]
    pub fn result(&self) -> SessionResult {
        let charger_emcy = 0x080 + u32::from(CHARGER_NODE.raw());
        let errors = self
            .log
            .iter()
            .filter(|l| l.frame.identity() == charger_emcy)
            .filter_map(|l| {
                let e = Emergency::parse_frame(&l.frame).ok()?;
                (e.code != ErrorCode::NO_ERROR).then(|| (l.at, DeltaQCode::from_emergency(&e)))
            })
            .collect();
        SessionResult {
            start_soc: self.start_soc,
            end_soc: self.pack.soc(),
            duration: self.now().saturating_duration_since(Timestamp::ZERO),
            phases: self.phases.clone(),
            ah: self.ah,
            wh: self.wh,
            errors,
            max_pack_temperature_c: self.max_temperature,
        }
    }

    /// One physics step of `dt` seconds (0: just the measurements).
    fn physics(&mut self, dt: f64) {
        let Some(set) = self.charger().map(Charger::set_points) else {
            return;
        };
        self.stage.step(dt, set, &self.pack);
        let current = self.stage.current_a;
        let volts = self.pack.terminal_voltage(current);
        self.pack.step(dt, current);
        self.ah += current * dt / 3600.0;
        self.wh += current * volts * dt / 3600.0;
        self.max_temperature = self.max_temperature.max(self.pack.temperature_c());
        let measured = self.stage.measure(&self.pack);
        let _ = self
            .bus
            .with(self.charger, |c, now| c.handle_power_stage(now, measured));
        let request = self.bms.request(&self.pack);
        let pack = self.pack;
        let _ = self.bus.with(self.module, |m, now| {
            m.update(now, |o| {
                super::module_link::publish(o, &pack, current, request);
            });
        });
    }

    /// Runs what is due now on the bus (the answers to what was just put
    /// on it), so a command's effects are there when it returns.
    fn settle(&mut self) {
        let now = self.bus.now();
        self.run_until(now);
    }

    /// After a bus step: the frames that reached the bus into the log, the
    /// charger's phases, and the BMS's writes (the next one started once
    /// the tool is idle; 1803h queued when the charger is configured).
    fn after_step(&mut self) {
        let state = self.bus.controller_state(self.charger);
        if state != self.controller {
            self.controller = state;
            let error = state != ControllerState::ErrorActive;
            let _ = self
                .bus
                .with(self.charger, |c, now| c.set_bus_error(now, error));
        }
        let charger_emcy = 0x080 + u32::from(CHARGER_NODE.raw());
        let mut log = core::mem::take(&mut self.sent);
        self.bus.take_log_into(&mut log);
        for sent in log.drain(..) {
            if sent.from == "Charger" && sent.frame.identity() == charger_emcy {
                if let Ok(e) = Emergency::parse_frame(&sent.frame) {
                    match DeltaQCode::from_emergency(&e) {
                        DeltaQCode::NONE => self.clear_alarms(sent.at, |_| true),
                        code => self.raise_alarm(sent.at, code),
                    }
                }
            }
            if sent.fate.reached_the_bus() {
                self.log.push(Logged {
                    at: sent.at,
                    frame: sent.frame,
                });
            }
        }
        self.sent = log;
        for (at, e) in self.bus.take_events(self.charger) {
            match e {
                ChargerEvent::Charge(ChargeEvent::Phase { to, .. }) => {
                    self.phases.push((at, to));
                }
                ChargerEvent::Charge(ChargeEvent::Alarm { alarm, active }) => {
                    let code = alarm.code();
                    if active {
                        self.raise_alarm(at, code);
                    } else {
                        self.clear_alarms(at, |c| c == code);
                    }
                }
                ChargerEvent::Configured { .. } => {
                    // The module is back and paired: its communication
                    // alarms are over (section 7.1.7).
                    self.clear_alarms(at, |c| {
                        matches!(
                            c,
                            DeltaQCode::HEARTBEAT_LOST | DeltaQCode::BATTERY_MODULE_COMMUNICATION
                        )
                    });
                    if self.enable_charger_tpdo3 {
                        // 1803h sub 1: TPDO 3 valid on 48Ah + node.
                        let cob = 0x480 + u32::from(CHARGER_NODE.raw());
                        self.pending_writes
                            .push((0x1803, 1, cob.to_le_bytes().to_vec()));
                    }
                }
                _ => {}
            }
        }
        // Their queues are left undrained: keep them from filling.
        if let Some(m) = self.bus.machine_mut(self.module) {
            while m.poll_event().is_some() {}
        }
        if let Some(t) = self.bus.machine_mut(self.tool) {
            while t.poll_event().is_some() {}
        }
        self.start_next_write();
    }

    fn raise_alarm(&mut self, at: Timestamp, code: DeltaQCode) {
        if !self.active.contains(&code) {
            self.active.push(code);
            self.alarm_changes.push(AlarmChange {
                at,
                code,
                raised: true,
            });
        }
    }

    fn clear_alarms(&mut self, at: Timestamp, which: impl Fn(DeltaQCode) -> bool) {
        let changes = &mut self.alarm_changes;
        self.active.retain(|&code| {
            let cleared = which(code);
            if cleared {
                changes.push(AlarmChange {
                    at,
                    code,
                    raised: false,
                });
            }
            !cleared
        });
    }
}
