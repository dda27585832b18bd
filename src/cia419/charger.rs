//! The charger session: a CiA 419 charger (the Delta-Q IC Series flavour of
//! DIGEST sections 2-4) as a sans-IO state machine.
//!
//! What it does:
//!
//! - **NMT slave** with heartbeat producer (1017h, 1000 ms) and boot-up.
//!   With [`ChargerConfig::self_start`] it enters operational by itself after
//!   boot; otherwise it waits for an NMT start (in the real capture the BMS
//!   sends `000#010A`).
//! - **Heartbeat consumer** of the battery module (1016h, 2000 ms).
//! - **PDO COB-ID configuration** (CiA 419 section 7.2, DIGEST section 4),
//!   when [`ChargerConfig::configure_cob_ids`] is set: on finding the battery
//!   module (its first heartbeat, boot-up, or a heartbeat after a loss) the
//!   charger reads 1000h by SDO; the profile must be 418 (else
//!   [`ChargerEvent::NotABatteryModule`] and EMCY E-0-4-2). For each PDO the
//!   device type declares it reads the module's COB-ID (communication
//!   parameter sub 1) and sets its own paired PDO to the same identifier:
//!   charger TPDO 0 / RPDO 0 always (module RPDO 0 at 1400h, TPDO 0 at
//!   1800h); TPDO 1 / 2 when bits 16 / 17 say the module has RPDO 1 / 2;
//!   RPDO 1 / 2 when bits 18 / 19 say it has TPDO 1 / 2; TPDO 3 only when
//!   Delta-Q's bit 20 asks for it. The settings are volatile. **Choice**
//!   (the documents are silent): a module COB-ID with bit 31 set ("not
//!   valid", CiA 418's TPDO default) is copied by its identifier bits and the
//!   charger's own paired PDO is enabled; enabling the module's TPDOs is the
//!   module's business. Without `configure_cob_ids` the charger uses its own
//!   default COB-IDs (18Ah, 28Ah, 38Ah, 48Ah; 20Ah, 30Ah, 40Ah), as in the
//!   real capture.
//! - **TPDOs** are sent only while configured, NMT operational and the
//!   battery module present, at 200 ms (TPDO 0-2) and 1000 ms (TPDO 3).
//! - **Battery lost** (no heartbeat for the consumer time): EMCY 8130h with
//!   Delta-Q alarm E-0-3-2, error register 01h, as the real capture shows
//!   (`08A#3081012080000000`); the entry goes to 1003h; TPDOs stop and the
//!   configuration is forgotten. A failed configuration (the module's SDO
//!   server aborts or does not answer) raises E-0-3-0 "battery module
//!   communication error" (the capture's `08A#3081011E80000000`). When the
//!   module is back and configured, an error-reset EMCY (code 0000h) clears
//!   the error register.
//! - **EMCY consumer**: the module's EMCYs are decoded and reported with the
//!   reaction of the Delta-Q policy for the operating mode
//!   ([`crate::deltaq::emergency_reaction`]); acting on it (stopping the
//!   charge) is the application's part.
//! - **SDO server** for the charger's own objects ([`ChargerObjects`]),
//!   including the 1003h error history (last 10, newest first, Delta-Q byte
//!   order: high word = the Delta-Q code byte-swapped).

use core::time::Duration;

use super::objects::ChargerObjects;
use crate::bytes::InlineData;
use crate::cia418::DeviceType;
use crate::cob_id::{NodeId, PdoNumber, EMCY_BASE, NMT};
use crate::deltaq::{charger_default_pdo, emergency_reaction, DeltaQCode, OperatingMode, Reaction};
use crate::emcy::{Emergency, ErrorCode, ErrorRegister};
use crate::frame::{CanFrame, CanId};
use crate::heartbeat::{ConsumerEntry, HeartbeatConsumer, HeartbeatEvent, HeartbeatProducer};
use crate::machine::Machine;
use crate::nmt::{NmtCommand, NmtCommandSpecifier, NmtState};
use crate::pdo::{
    receive_rpdo, PdoCobId, PdoCommParams, PdoConfig, PdoDictionary, PdoDirection, PdoSlot,
    RpdoError, TpdoSet,
};
use crate::queue::Queue;
use crate::sdo::{AbortCode, Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent};
use crate::time::Timestamp;

/// How the charger is set up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargerConfig {
    /// The charger's node id (Delta-Q default 10).
    pub node: NodeId,
    /// The battery module's node id (default 1).
    pub battery: NodeId,
    /// Operating mode: decides the reaction to the module's EMCYs.
    pub mode: OperatingMode,
    /// Read the module's PDO COB-IDs and pair the charger's PDOs with them.
    pub configure_cob_ids: bool,
    /// Enter operational after boot without waiting for an NMT start.
    pub self_start: bool,
    /// Heartbeat producer period (1017h), ms.
    pub heartbeat_ms: u16,
    /// Heartbeat consumer time for the battery module (1016h), ms.
    pub battery_timeout_ms: u16,
    /// Event timers of TPDO 0..3, ms.
    pub tpdo_periods_ms: [u16; 4],
    /// SDO timeout of the configuration client.
    pub sdo_timeout: Duration,
    /// 1008h.
    pub device_name: &'static str,
}

impl ChargerConfig {
    /// Delta-Q defaults for charger `node` and battery module `battery`.
    #[must_use]
    pub const fn new(node: NodeId, battery: NodeId) -> Self {
        ChargerConfig {
            node,
            battery,
            mode: OperatingMode::Local,
            configure_cob_ids: true,
            self_start: false,
            heartbeat_ms: 1000,
            battery_timeout_ms: 2000,
            tpdo_periods_ms: [200, 200, 200, 1000],
            sdo_timeout: Duration::from_millis(2000),
            device_name: "canopen-codec charger",
        }
    }
}

/// What the charger reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ChargerEvent {
    /// The charger's NMT state changed.
    NmtStateChanged {
        /// Before.
        from: NmtState,
        /// After.
        to: NmtState,
    },
    /// The battery module was heard (first heartbeat, boot-up, or back after a loss).
    BatteryFound {
        /// The state it reports.
        state: NmtState,
    },
    /// The battery module's heartbeat was lost.
    BatteryLost,
    /// The PDOs are paired and configured; `tpdos` / `rpdos` say which (bit n = PDO n).
    Configured {
        /// Charger TPDOs in use.
        tpdos: u8,
        /// Charger RPDOs in use.
        rpdos: u8,
    },
    /// Reading the module's configuration failed.
    ConfigurationFailed {
        /// Object read.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Abort code.
        code: AbortCode,
    },
    /// 1000h does not name profile 418.
    NotABatteryModule {
        /// The module's 1000h.
        device_type: u32,
    },
    /// The module sent an EMCY; `reaction` is the policy's answer.
    BatteryEmcy {
        /// The emergency.
        emcy: Emergency,
        /// What the charger should do.
        reaction: Reaction,
    },
    /// An RPDO updated the charger's objects.
    RpdoReceived {
        /// Which.
        pdo: PdoNumber,
    },
    /// An RPDO was refused (short: EMCY 8210h sent).
    RpdoRefused {
        /// Which.
        pdo: PdoNumber,
        /// Why.
        error: RpdoError,
    },
    /// An object was written over SDO.
    ObjectWritten {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
}

/// Where the configuration of the PDO pairing stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Link {
    /// Module not heard (or lost).
    Absent,
    /// Reading 1000h.
    DeviceType,
    /// Reading the module's COB-ID of pair `i` (index into PAIRS).
    CobId(usize, DeviceType),
    /// Configured: TPDOs may run.
    Ready,
    /// Configuration failed; waits for the module to come back.
    Failed,
}

/// (module communication index, charger direction, charger PDO, device-type bit or 0 = always)
const PAIRS: [(u16, PdoDirection, PdoNumber, u32); 7] = [
    (0x1400, PdoDirection::Transmit, PdoNumber::P0, 0),
    (0x1800, PdoDirection::Receive, PdoNumber::P0, 0),
    (0x1401, PdoDirection::Transmit, PdoNumber::P1, 1 << 16),
    (0x1402, PdoDirection::Transmit, PdoNumber::P2, 1 << 17),
    (0x1801, PdoDirection::Receive, PdoNumber::P1, 1 << 18),
    (0x1802, PdoDirection::Receive, PdoNumber::P2, 1 << 19),
    (0x1403, PdoDirection::Transmit, PdoNumber::P3, 1 << 20),
];

const PDO_NUMBERS: [PdoNumber; 4] = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3];

type ChargerServer = Server<PdoDictionary<ChargerObjects>>;

/// The charger. See the module docs; the usual poll contract.
///
/// ```
/// use canopen_codec::cia419::{Charger, ChargerConfig};
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// let mut c = Charger::new(ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::new(1).unwrap()));
/// c.boot(Timestamp::ZERO);
/// assert_eq!(c.poll_transmit().unwrap().to_string(), "70A#00");
/// // The battery module's heartbeat: the charger reads its device type.
/// c.handle_frame(Timestamp::from_millis(10), &CanFrame::standard(0x701, &[0x05]).unwrap());
/// assert_eq!(c.poll_transmit().unwrap().to_string(), "601#4000100000000000");
/// ```
#[derive(Debug)]
pub struct Charger {
    config: ChargerConfig,
    state: NmtState,
    server: ChargerServer,
    client: Client<&'static [u8]>,
    heartbeat: HeartbeatProducer,
    consumer: HeartbeatConsumer<1>,
    tpdos: TpdoSet,
    link: Link,
    /// The value of the upload in progress (1000h or a COB-ID: 4 bytes).
    upload_value: [u8; 4],
    /// The battery-lost / configuration error is active (cleared by an error-reset EMCY).
    error_active: bool,
    transmit: Queue<CanFrame, 8>,
    events: Queue<ChargerEvent, 16>,
}

impl Charger {
    /// A charger with `config`, not yet booted.
    #[must_use]
    pub fn new(config: ChargerConfig) -> Self {
        let objects = Self::initial_objects(&config);
        Charger {
            config,
            state: NmtState::BootUp,
            server: Server::new(
                Self::server_config(&config),
                PdoDictionary::new(Self::default_pdos(&config), objects),
            ),
            client: Client::new(ClientConfig {
                timeout: config.sdo_timeout,
                ..ClientConfig::for_server(config.battery)
            }),
            heartbeat: HeartbeatProducer::new(
                config.node,
                Duration::from_millis(u64::from(config.heartbeat_ms)),
            ),
            consumer: HeartbeatConsumer::new(),
            tpdos: TpdoSet::new(),
            link: Link::Absent,
            upload_value: [0; 4],
            error_active: false,
            transmit: Queue::new(CanFrame::EMPTY),
            events: Queue::new(ChargerEvent::BatteryLost),
        }
    }

    fn initial_objects(config: &ChargerConfig) -> ChargerObjects {
        ChargerObjects::new(
            config.device_name,
            config.heartbeat_ms,
            ConsumerEntry {
                node: config.battery.raw(),
                time_ms: config.battery_timeout_ms,
            },
        )
    }

    fn server_config(config: &ChargerConfig) -> ServerConfig {
        ServerConfig {
            timeout: config.sdo_timeout,
            ..ServerConfig::for_node(config.node)
        }
    }

    /// The charger's default PDO set: its published mappings, with COB-IDs
    /// not valid until configured (or valid defaults without configuration).
    fn default_pdos(config: &ChargerConfig) -> PdoConfig {
        let mut pdos = PdoConfig::new();
        for dir in [PdoDirection::Transmit, PdoDirection::Receive] {
            for n in PDO_NUMBERS {
                let d = charger_default_pdo(dir, n);
                let Some(mapping) = d.mapping() else { continue };
                let cob =
                    PdoCobId::from_u32(d.cob_id(config.node)).with_valid(!config.configure_cob_ids);
                let period = match dir {
                    PdoDirection::Transmit => config
                        .tpdo_periods_ms
                        .get(usize::from(n.raw()))
                        .copied()
                        .unwrap_or(0),
                    PdoDirection::Receive => 0,
                };
                pdos.insert(
                    dir,
                    n,
                    PdoSlot::new(PdoCommParams::event_driven(cob, period), &mapping),
                );
            }
        }
        pdos
    }

    // ----- getters -----------------------------------------------------------

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &ChargerConfig {
        &self.config
    }

    /// The NMT state.
    #[must_use]
    pub const fn nmt_state(&self) -> NmtState {
        self.state
    }

    /// True once the PDO pairing is done and the module is present.
    #[must_use]
    pub const fn is_configured(&self) -> bool {
        matches!(self.link, Link::Ready)
    }

    /// The charger's objects.
    #[must_use]
    pub fn objects(&self) -> &ChargerObjects {
        &self.server.od().inner
    }

    /// The PDO configuration (COB-IDs after pairing).
    #[must_use]
    pub fn pdo_config(&self) -> &PdoConfig {
        &self.server.od().config
    }

    /// Changes objects (measurements, status) and refreshes the TPDOs.
    pub fn update(&mut self, now: Timestamp, f: impl FnOnce(&mut ChargerObjects)) {
        f(&mut self.server.od_mut().inner);
        self.refresh_tpdos(now);
    }

    // ----- inputs ------------------------------------------------------------

    /// Boots: boot-up message, default PDOs, pre-operational (or
    /// operational with `self_start`).
    pub fn boot(&mut self, now: Timestamp) {
        let config = self.config;
        self.server = Server::new(
            Self::server_config(&config),
            PdoDictionary::new(Self::default_pdos(&config), Self::initial_objects(&config)),
        );
        self.client = Client::new(ClientConfig {
            timeout: config.sdo_timeout,
            ..ClientConfig::for_server(config.battery)
        });
        self.heartbeat = HeartbeatProducer::new(
            config.node,
            Duration::from_millis(u64::from(config.heartbeat_ms)),
        );
        self.heartbeat.boot(now);
        self.consumer = HeartbeatConsumer::new();
        let entry = self.objects().consumer;
        let _ = self.consumer.set_entry(now, 0, entry);
        self.tpdos = TpdoSet::new();
        self.link = Link::Absent;
        self.error_active = false;
        self.sync_tpdos(now);
        self.set_state(now, NmtState::PreOperational);
        if config.self_start {
            self.set_state(now, NmtState::Operational);
        }
    }

    /// Feeds a received frame.
    pub fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if self.state == NmtState::BootUp || frame.is_remote() {
            return;
        }
        let id = frame.id();
        if id == CanId::Standard(NMT) {
            return self.handle_nmt(now, frame.data());
        }
        if id == CanId::Standard(EMCY_BASE + u16::from(self.config.battery.raw())) {
            if let Ok(emcy) = Emergency::decode(frame.data()) {
                let reaction = emergency_reaction(self.config.mode, &emcy);
                self.push_event(ChargerEvent::BatteryEmcy { emcy, reaction });
            }
            return;
        }
        self.consumer.handle_frame(now, frame);
        self.drain_consumer(now);
        if self.sdo_allowed() {
            self.server.handle_frame(now, frame);
            self.drain_server(now);
            self.client.handle_frame(now, frame);
            self.drain_client(now);
        }
        if self.state == NmtState::Operational {
            self.handle_rpdo(now, frame);
        }
    }

    /// Tells the charger time has passed.
    pub fn handle_timeout(&mut self, now: Timestamp) {
        if self.state == NmtState::BootUp {
            return;
        }
        self.heartbeat.handle_timeout(now);
        self.consumer.handle_timeout(now);
        self.drain_consumer(now);
        self.server.handle_timeout(now);
        self.drain_server(now);
        self.client.handle_timeout(now);
        self.drain_client(now);
        self.refresh_tpdos(now);
        self.tpdos.handle_timeout(now);
    }

    // ----- outputs -----------------------------------------------------------

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
        if let Some(f) = self.client.poll_transmit() {
            return Some(f);
        }
        self.tpdos.poll_transmit()
    }

    /// The next event.
    #[must_use]
    pub fn poll_event(&mut self) -> Option<ChargerEvent> {
        self.events.pop()
    }

    /// When [`handle_timeout`](Self::handle_timeout) must next be called.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Timestamp> {
        if self.state == NmtState::BootUp {
            return None;
        }
        [
            self.heartbeat.poll_timeout(),
            self.consumer.poll_timeout(),
            self.server.poll_timeout(),
            self.client.poll_timeout(),
        ]
        .into_iter()
        .chain([self.tpdos.poll_timeout()])
        .flatten()
        .min()
    }

    // ----- internals ---------------------------------------------------------

    const fn sdo_allowed(&self) -> bool {
        matches!(self.state, NmtState::PreOperational | NmtState::Operational)
    }

    /// Queues an event; when the queue is full the oldest is dropped.
    fn push_event(&mut self, event: ChargerEvent) {
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
                self.set_state(now, NmtState::PreOperational)
            }
            NmtCommandSpecifier::ResetNode | NmtCommandSpecifier::ResetCommunication => {
                self.boot(now);
            }
            NmtCommandSpecifier::Unknown(_) => {}
        }
    }

    fn set_state(&mut self, now: Timestamp, to: NmtState) {
        let from = self.state;
        if from == to {
            return;
        }
        self.state = to;
        self.heartbeat.set_state(now, to);
        self.gate_tpdos(now);
        self.push_event(ChargerEvent::NmtStateChanged { from, to });
    }

    /// TPDOs run only when operational and the link is ready.
    fn gate_tpdos(&mut self, now: Timestamp) {
        let run = self.state == NmtState::Operational && self.link == Link::Ready;
        if run {
            self.refresh_tpdos(now);
        }
        self.tpdos.set_operational(now, run);
    }

    fn send_emcy(&mut self, emcy: Emergency) {
        if !self.sdo_allowed() {
            return;
        }
        let id = CanId::Standard(EMCY_BASE + u16::from(self.config.node.raw()));
        if let Ok(frame) = CanFrame::new(id, &emcy.encode()) {
            let _ = self.transmit.push(frame);
        }
    }

    /// Raises a Delta-Q alarm: EMCY, 1001h, 1003h.
    fn raise(&mut self, code: DeltaQCode) {
        let eec = code.entry().map_or(ErrorCode::GENERIC, |e| e.eec);
        let register = ErrorRegister::GENERIC;
        self.server.od_mut().inner.error_register = register;
        self.server
            .od_mut()
            .inner
            .push_error(code.to_error_field(eec));
        self.error_active = true;
        self.send_emcy(code.to_emergency(eec, register));
    }

    fn clear_error(&mut self) {
        if !core::mem::replace(&mut self.error_active, false) {
            return;
        }
        self.server.od_mut().inner.error_register = ErrorRegister::empty();
        self.send_emcy(Emergency::default());
    }

    fn drain_consumer(&mut self, now: Timestamp) {
        while let Some(e) = self.consumer.poll_event() {
            match e {
                HeartbeatEvent::Lost(_) => self.battery_lost(now),
                HeartbeatEvent::BootUp(_) => self.battery_found(now, NmtState::BootUp, true),
                HeartbeatEvent::Restored { state, .. } => self.battery_found(now, state, true),
                HeartbeatEvent::StateChanged { state, .. } => {
                    if self.link == Link::Absent {
                        self.battery_found(now, state, false);
                    }
                }
            }
        }
        // The first heartbeat starts monitoring without an event.
        if self.link == Link::Absent {
            if let Some(state) = self.consumer.state(self.config.battery) {
                if self.consumer.is_alive(self.config.battery) {
                    self.battery_found(now, state, false);
                }
            }
        }
    }

    fn battery_found(&mut self, now: Timestamp, state: NmtState, again: bool) {
        if !again && self.link != Link::Absent {
            return;
        }
        if again && self.link != Link::Absent && self.link != Link::Failed {
            // A boot-up while configured: the module reset its PDOs; redo it.
            self.forget_pairing(now);
        }
        self.push_event(ChargerEvent::BatteryFound { state });
        if self.config.configure_cob_ids {
            self.link = Link::DeviceType;
            if self.client.start_upload(now, 0x1000, 0).is_err() {
                self.link = Link::Failed;
            }
        } else {
            self.link = Link::Ready;
            self.configured(now);
        }
    }

    fn battery_lost(&mut self, now: Timestamp) {
        self.push_event(ChargerEvent::BatteryLost);
        self.raise(DeltaQCode::HEARTBEAT_LOST);
        let _ = self.client.abort(now, AbortCode::GeneralError);
        while self.client.poll_event().is_some() {}
        self.forget_pairing(now);
        self.link = Link::Absent;
        self.gate_tpdos(now);
    }

    /// Back to the not-valid default COB-IDs (when configuring them).
    fn forget_pairing(&mut self, now: Timestamp) {
        if self.config.configure_cob_ids {
            self.server.od_mut().config = Self::default_pdos(&self.config);
        }
        self.link = Link::Absent;
        self.sync_tpdos(now);
        self.gate_tpdos(now);
    }

    fn configured(&mut self, now: Timestamp) {
        self.sync_tpdos(now);
        let config = &self.server.od().config;
        let mask = |dir| {
            PDO_NUMBERS
                .iter()
                .filter(|n| config.get(dir, **n).is_some_and(PdoSlot::is_valid))
                .fold(0u8, |m, n| m | 1 << n.raw())
        };
        let (tpdos, rpdos) = (mask(PdoDirection::Transmit), mask(PdoDirection::Receive));
        self.push_event(ChargerEvent::Configured { tpdos, rpdos });
        self.clear_error();
        self.gate_tpdos(now);
    }

    fn drain_client(&mut self, now: Timestamp) {
        while let Some(e) = self.client.poll_event() {
            match e {
                ClientEvent::UploadData { offset, data, .. } => self.on_upload_data(offset, data),
                ClientEvent::Uploaded { .. } => self.on_uploaded(now),
                ClientEvent::Aborted {
                    index, sub, code, ..
                } => {
                    if matches!(self.link, Link::DeviceType | Link::CobId(..)) {
                        self.link = Link::Failed;
                        self.push_event(ChargerEvent::ConfigurationFailed { index, sub, code });
                        self.raise(DeltaQCode::BATTERY_MODULE_COMMUNICATION);
                    }
                }
                ClientEvent::Downloaded { .. } => {}
            }
        }
    }

    fn on_upload_data(&mut self, offset: usize, data: InlineData<7>) {
        // Values read here are at most 4 bytes; keep them in the pending slot.
        if offset == 0 {
            self.upload_value = [0; 4];
        }
        for (i, b) in data.as_slice().iter().enumerate() {
            if let Some(slot) = self.upload_value.get_mut(offset + i) {
                *slot = *b;
            }
        }
    }

    fn on_uploaded(&mut self, now: Timestamp) {
        let value = u32::from_le_bytes(self.upload_value);
        match self.link {
            Link::DeviceType => {
                let dt = DeviceType::from_raw(value);
                if !dt.is_cia418() {
                    self.link = Link::Failed;
                    self.push_event(ChargerEvent::NotABatteryModule { device_type: value });
                    self.raise(DeltaQCode::Alarm(42));
                    return;
                }
                self.next_pair(now, 0, dt);
            }
            Link::CobId(i, dt) => {
                if let Some(&(_, dir, n, _)) = PAIRS.get(i) {
                    let module = PdoCobId::from_u32(value);
                    let mine = PdoCobId::from_u32(module.to_u32() & !PdoCobId::NOT_VALID);
                    if let Some(slot) = self.server.od_mut().config.get_mut(dir, n) {
                        slot.comm.cob_id = mine;
                    }
                }
                self.next_pair(now, i + 1, dt);
            }
            _ => {}
        }
    }

    /// Starts reading the next pair the device type declares, or finishes.
    fn next_pair(&mut self, now: Timestamp, from: usize, dt: DeviceType) {
        let next = PAIRS
            .iter()
            .enumerate()
            .skip(from)
            .find(|(_, &(_, dir, n, bit))| {
                (bit == 0 || dt.raw() & bit != 0) && self.server.od().config.get(dir, n).is_some()
            });
        match next {
            Some((i, &(index, ..))) => {
                self.link = Link::CobId(i, dt);
                if self.client.start_upload(now, index, 1).is_err() {
                    self.link = Link::Failed;
                }
            }
            None => {
                self.link = Link::Ready;
                self.configured(now);
            }
        }
    }

    fn drain_server(&mut self, now: Timestamp) {
        let mut written = false;
        while let Some(e) = self.server.poll_event() {
            if let ServerEvent::Downloaded { index, sub, .. } = e {
                written = true;
                match index {
                    0x1017 => {
                        let ms = self.objects().heartbeat_ms;
                        self.heartbeat
                            .set_period(now, Duration::from_millis(u64::from(ms)));
                    }
                    0x1016 => {
                        let entry = self.objects().consumer;
                        let _ = self.consumer.set_entry(now, 0, entry);
                    }
                    _ => {}
                }
                self.push_event(ChargerEvent::ObjectWritten { index, sub });
            }
        }
        if written {
            self.sync_tpdos(now);
            self.refresh_tpdos(now);
        }
    }

    fn handle_rpdo(&mut self, now: Timestamp, frame: &CanFrame) {
        let Some((pdo, result)) = receive_rpdo(self.server.od_mut(), frame) else {
            return;
        };
        match result {
            Ok(_) => self.push_event(ChargerEvent::RpdoReceived { pdo }),
            Err(error) => {
                if let Some(code) = error.emcy_code() {
                    // Delta-Q's E-0-4-6 "invalid PDO length" with EEC 8210h.
                    let register = ErrorRegister::GENERIC | ErrorRegister::COMMUNICATION;
                    self.send_emcy(DeltaQCode::INVALID_PDO_LENGTH.to_emergency(code, register));
                }
                self.push_event(ChargerEvent::RpdoRefused { pdo, error });
            }
        }
        self.refresh_tpdos(now);
    }

    fn refresh_tpdos(&mut self, now: Timestamp) {
        self.tpdos.refresh(now, self.server.od_mut());
    }

    fn sync_tpdos(&mut self, now: Timestamp) {
        self.tpdos.sync(now, &self.server.od().config);
    }
}

impl crate::machine::Machine for Charger {
    type Event = ChargerEvent;
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
    fn poll_event(&mut self) -> Option<ChargerEvent> {
        Self::poll_event(self)
    }
    fn events_dropped(&self) -> u64 {
        0
    }
}
