//! The CiA 301 device core that every device of the crate is built on: NMT
//! slave, heartbeat producer (1017h) and consumer (1016h), EMCY producer
//! with the error register (1001h) and the error history (1003h), the SDO
//! server over the object dictionary, the TPDOs, RPDO reception and SYNC,
//! and one event queue. A profile (the CiA 418 battery module, the Delta-Q
//! charger) adds only its own objects (`A`, the application dictionary)
//! and behaviour (a [`Profile`]).
//!
//! # Driving it
//!
//! A device is named by one type, its [`DeviceSpec`] (application objects,
//! events, power-on configuration), and its capacities (`Q`, `T`, `R`,
//! with defaults). **Every device is driven one way: as a
//! [`ProfiledDevice`]**, the core and its [`Profile`] as one [`Machine`] of
//! the crate's [state-machine contract](crate::machine): `boot` once at
//! power-on, then `handle_frame` / `handle_timeout`, and drain
//! `poll_transmit` (and `poll_event`) after every call. The CiA 418
//! battery module and the Delta-Q charger (each a profile of its own
//! area, above this layer), a profile of one's own
//! ([`ProfiledDevice::from_parts`]) and the plain CiA 301 slave over any
//! dictionary `A` ([`Cia301Device`], made by [`ProfiledDevice::plain`])
//! are all of that type. Why one way: the core's inputs and outputs need
//! the profile at every call (its hooks see every frame, event and
//! timeout, its frames and deadline join the core's), so a core driven
//! apart from its profile, or a profile's inputs called beside the
//! machine, could miss one; with one driver, one loop (and one test
//! harness) drives any device, and a firmware carries one copy of the
//! plumbing. The core ([`Device`], reached through `Deref`/`DerefMut`)
//! keeps its getters and commands (`update`, `raise_error`,
//! `set_nmt_state`, ...); its per-call plumbing with the profile passed
//! in is private. A profile's own inputs (the charger's power stage) are
//! inherent commands of its `ProfiledDevice`.
//!
//! `poll_transmit` order: heartbeat and boot-up, then EMCY and the
//! profile's queued frames, then SDO responses, then the profile's own
//! machines ([`Profile::poll_transmit`]), then TPDOs.
//!
//! # Behaviour (CiA 301)
//!
//! - **NMT** ([`NmtSlave`](crate::nmt::NmtSlave)): nothing is handled before [`Device::boot`].
//!   Boot and every reset send the boot-up message and enter
//!   pre-operational. **Reset node** (81h) restores every parameter to its
//!   power-on value: the communication objects and the PDO configuration
//!   to the [`DeviceConfig`], the application's parameters to their values
//!   at [`Device::boot`] (what the application set before booting; what
//!   they are is the dictionary's [`PowerOnValues`]: every object an SDO
//!   download or an RPDO can change, the `rw` ones, for the profiles; every
//!   object for `od::MemoryDictionary`). The
//!   application's `ro` objects (its measurements and identity) keep the
//!   value it last set: CiA 301 7.3.2.2.1 restores the parameters of the
//!   profile areas, and a boot-time reading restored would be published
//!   (SDO, TPDOs) until the application's next update. **Reset communication** (82h) restores only
//!   the communication objects (1000h-1FFFh, PDO configuration included)
//!   and keeps the application objects. Both drop a running SDO transfer
//!   silently, restart the heartbeat and are reported as
//!   [`DeviceEvent::Reset`] followed by the state change.
//! - **SDO** is served in pre-operational and operational; entering
//!   stopped drops a running transfer silently (no SDO in stopped).
//! - **EMCY** frames (80h + node) are sent only in pre-operational and
//!   operational; the error register changes in any state.
//!   [`Device::raise_error`] sets bits of 1001h (and the generic bit),
//!   records the error in 1003h ([`ErrorFieldFormat`]) and sends the EMCY;
//!   [`Device::clear_error`] clears bits and sends the error reset (0000h).
//! - **TPDOs** run only in operational and while the profile allows
//!   ([`Device::set_tpdos_enabled`]); their payloads are read from the
//!   mapped objects after every input that may have changed them (with
//!   feature `alloc`, not after an RPDO whose mapped objects already held
//!   its values), and a changed mapped value is an event. **RPDOs** are written into the mapped objects only
//!   in operational; a payload shorter than its mapping is refused whole
//!   with EMCY 8210h ([`Profile::rpdo_emergency`]).
//! - **Heartbeat**: the boot-up message at boot and resets, then the state
//!   every 1017h period; an SDO write to 1017h changes the period at once.
//!   Heartbeats of the nodes in 1016h are supervised; their events are
//!   reported as [`DeviceEvent::Heartbeat`] whether or not events are read
//!   (feature `heartbeat-consumer`).
//! - **Node guarding** ([`GuardingSlave`](crate::nmt::guarding::GuardingSlave),
//!   100Ch, 100Dh): requests are answered in every state once booted, the
//!   toggle from 0 after every reset, but not while 1017h is non-zero (CiA
//!   301: heartbeat and guarding are exclusive; the default 1000 ms means no
//!   guarding); life guarding is [`DeviceEvent::LifeGuarding`]. **SYNC**:
//!   with 1005h's generate bit and a non-zero 1006h the device sends SYNC
//!   (counter of 1019h) in pre-operational and operational; SYNC on 1005h's
//!   identifier, received or its own, runs the synchronous TPDOs; counter
//!   skips and synchronous RPDOs outside the 1007h window are
//!   [`DeviceEvent::Sync`]. **TIME** follows 1012h's bits
//!   ([`DeviceEvent::Time`], [`Device::send_time`]). Both resets restore
//!   these objects.
//! - **Back-pressure** (the crate's one rule, [`crate::machine`]): the
//!   event queue and the queue of frames to send keep the latest `Q` each
//!   (default 16); when one is full its oldest item is dropped and counted
//!   ([`Machine::events_dropped`], [`Machine::frames_dropped`], each
//!   saturating at `u32::MAX`); nothing else depends on them.
//! - **LSS** (CiA 305, optional: [`Device::with_lss`]): the device's
//!   [`LssSlave`] sees every frame from [`Device::boot`] on. A device whose
//!   LSS node-ID is not configured (255) does not boot up: it stays silent
//!   but for LSS until a master configures a node-ID and switches it back
//!   to waiting state; it then performs a reset communication and boots up
//!   under that node-ID. A configured node-ID that differs from the active
//!   one takes effect at the next NMT reset (communication or node).
//! - **Store and restore** (CiA 301 sections 7.5.2.13/7.5.2.14, feature
//!   `store`, [`store`]): with a [`ParameterStorage`]
//!   ([`Device::set_storage`]) "save" to 1010h stores the communication
//!   and/or application parameters as a checked record, loaded at boot
//!   and at every reset that restores them; "load" to 1011h erases it, so
//!   the defaults come back at that reset. The LSS slave's store
//!   configuration is stored and answered through the same storage.
//!   Without a storage (the default) 1010h/1011h read 0 and refuse with
//!   08000020h.
//! - Total: no frame, timestamp or call order panics.
//!
//! # Services a node can leave out (Cargo features, default on)
//!
//! `lss` (the LSS slave), `guarding` (100Ch, 100Dh), `sync-time` (the SYNC
//! producer, 1006h, TIME, 1012h; without it 1005h's generate bit is refused
//! with 06090030h; the SYNC consumer is always there), `sdo-block` (the
//! server's block transfer; without it 05040001h) and `heartbeat-consumer`
//! (1016h and the supervision of other nodes' heartbeats; without it
//! another node's heartbeat changes nothing), `store` (1010h, 1011h and
//! the [`ParameterStorage`]; without it an LSS store request is the
//! application's). An object of a service left out does not exist
//! (06020000h). Costs: the README's "Firmware".
//!
//! # Communication objects ([`CommObjects`])
//!
//! | index | object | type | access |
//! |---|---|---|---|
//! | 1000h | device type | U32 | const |
//! | 1001h | error register | U8 | ro |
//! | 1003h | pre-defined error field: sub 0 the number of entries (rw; only 0 may be written, which clears the history, else 06090030h), sub 1-10 the entries, newest first (ro; an empty entry reads 08000024h) | ARRAY of U32 | |
//! | 1005h | COB-ID SYNC: bit 30 generate, bits 0-10 (or 0-28 with bit 29) the identifier (rw; moving the identifier while generating, or an invalid one, is 06090030h) | U32 | rw |
//! | 1006h | communication cycle period, µs (0: no SYNC produced) | U32 | rw |
//! | 1007h | synchronous window length, µs (0: no window) | U32 | rw |
//! | 1008h | manufacturer device name | VISIBLE_STRING | const |
//! | 100Ch | guard time, ms | U16 | rw |
//! | 100Dh | life time factor | U8 | rw |
//! | 1010h | store parameters: sub 0 = 3 (const), sub 1 all, 2 communication, 3 application: reads the capability (1: on command; 0 without a storage), "save" (65766173h) stores, another value 08000020h; a failing storage 06060000h (feature `store`) | ARRAY of U32 | rw |
//! | 1011h | restore default parameters: the same subs, "load" (64616F6Ch) erases the stored group, the defaults come back at the next reset that restores it | ARRAY of U32 | rw |
//! | 1012h | COB-ID TIME: bit 31 consume, bit 30 produce (an invalid identifier is 06090030h) | U32 | rw |
//! | 1016h | consumer heartbeat time: sub 0 the number of entries (const), sub 1..n node (bits 23-16) and time in ms (bits 15-0) (rw; an enabled entry for a node another entry watches is 06040043h) | ARRAY of U32 | (only with entries; feature `heartbeat-consumer`) |
//! | 1017h | producer heartbeat time, ms | U16 | rw |
//! | 1018h | identity: sub 0 = 4 (ro), vendor-ID, product code, revision, serial number | RECORD of U32 | ro |
//! | 1019h | synchronous counter overflow value: 0 or 2..=240 (1 and 241..=255 are 06090030h; while 1006h is non-zero 08000022h) | U8 | rw |
//! | 1200h | SDO server parameter: sub 0 = 2, 600h + node, 580h + node | RECORD of U32 | ro |
//!
//! Objects the table does not name are passed to the application's
//! dictionary, which may add communication objects of its own; the PDO
//! objects (1400h-1A03h) are served by [`PdoDictionary`] above both.

mod config;
#[cfg(feature = "heartbeat-consumer")]
mod consumer;
mod dispatch;
#[cfg(feature = "lss")]
mod lss;
mod nmt_reset;
mod objects;
#[cfg(feature = "store")]
mod parameters;
mod profile;
mod profiled;
#[cfg(feature = "program-download")]
mod program_objects;
mod services;
mod snapshot;
#[cfg(feature = "store")]
pub mod store;

/// The program download definitions, at their home [`crate::program`]
/// (below the SDO layer, whose master uses them too).
pub use crate::program;
pub use config::{DeviceConfig, Policies, PowerOn};
#[cfg(feature = "heartbeat-consumer")]
pub use objects::MAX_CONSUMERS;
pub use objects::{CommObjects, DeviceObjects, ErrorFieldFormat, Identity, ERROR_HISTORY_LEN};
pub use profile::{DeviceEvent, DeviceSpec, Profile};
pub use profiled::{Cia301, Cia301Device, DeviceSetup, ProfiledDevice};
#[cfg(feature = "program-download")]
pub use program_objects::{ProgramObjects, ProgramStoreRef};
pub use snapshot::PowerOnValues;
#[cfg(feature = "store")]
pub use store::{
    ParameterGroup, ParameterStorage, RamStorage, RecordError, StorageError, StorageEvent,
};

use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::emcy::{Emergency, ErrorCode, ErrorRegister};
use crate::frame::CanFrame;
#[cfg(feature = "lss")]
use crate::lss::LssSlave;
#[cfg(doc)]
use crate::machine::Machine;
#[cfg(feature = "heartbeat-consumer")]
use crate::nmt::heartbeat::HeartbeatConsumer;
use crate::nmt::heartbeat::HeartbeatProducer;
use crate::nmt::{NmtCore, NmtState, ResetKind};

use crate::pdo::{PdoConfig, PdoDictionary, RpdoReceiver, TpdoSet};
use crate::queue::EventQueue;
use crate::sdo::{Server, EVENTS_PER_CALL};

/// The dictionary the SDO server serves: PDO objects, communication
/// objects, application objects.
pub type Dictionary<A, const T: usize = 4, const R: usize = 4> =
    PdoDictionary<DeviceObjects<A>, T, R>;

/// What a restart gives back: what loading the stored records did
/// (feature `store`; nothing without it).
#[cfg(feature = "store")]
type Restarted = parameters::StorageReport;
#[cfg(not(feature = "store"))]
type Restarted = ();

/// The capacity of a device's event queue and of its queue of frames to
/// send, unless its type says otherwise (the `Q` of [`Device`]).
pub const DEFAULT_QUEUE_CAPACITY: usize = 16;

/// The CiA 301 device core. See the [module docs](self).
///
/// A core is driven with its profile, as a [`ProfiledDevice`] (see the
/// [module docs](self) and [`Cia301Device`] for a plain one).
///
/// `A` is the application's dictionary; what reset node restores of it is
/// its [`PowerOnValues`] (taken at [`boot`](Self::boot)).
///
/// `Q` is the capacity of the event queue and of the queue of frames to
/// send (default [`DEFAULT_QUEUE_CAPACITY`]): a node that drains both after
/// every call, as the contract says, can make it small (the firmware uses
/// 4); what happens when one is full is the back-pressure rule in the
/// module docs. `C` is what the power-on configuration is made from
/// ([`PowerOn`]; default: the stored [`DeviceConfig`]). `T` and `R` are
/// its numbers of TPDOs and RPDOs (at most 4 each, default 4 and 4;
/// [`PdoConfig`]): the objects of a PDO past them do not exist.
pub struct Device<
    S: DeviceSpec,
    const Q: usize = DEFAULT_QUEUE_CAPACITY,
    const T: usize = 4,
    const R: usize = 4,
> {
    /// Where the power-on configuration comes from.
    config: S::PowerOn,
    /// The active node-ID (the configuration's).
    node: NodeId,
    /// How an EMCY is recorded in 1003h (the configuration's).
    error_field: ErrorFieldFormat,
    /// The NMT slave without a queue: each call returns the one event it
    /// makes, handled at once ([`nmt_event`](Self::nmt_event)).
    nmt: NmtCore,
    /// The state the boot after a reset changes from (to pre-operational),
    /// held while the profile sees the reset: reported after it, or before
    /// a state change the profile makes then (`set_nmt_state`, the Delta-Q
    /// charger starts itself), so the order is that of the NMT slave's own
    /// queue (tests/devices/event_capacity.rs).
    nmt_boot: Option<NmtState>,
    heartbeat: HeartbeatProducer,
    /// The heartbeat consumer (consumer.rs): its events are reported as
    /// they are made, so it keeps none.
    #[cfg(feature = "heartbeat-consumer")]
    consumer: consumer::DeviceConsumer,
    /// Its events are read after every call: the capacity one call needs.
    server: Server<Dictionary<S::Objects, T, R>, EVENTS_PER_CALL>,
    tpdos: TpdoSet<T>,
    rpdos: RpdoReceiver<R>,
    /// The profile allows TPDOs (besides NMT operational).
    tpdos_enabled: bool,
    /// The objects may have changed since the TPDOs last read them (set by
    /// every mutable access to the dictionary, see
    /// [`od_mut`](Self::od_mut), and by an RPDO unless its mapped objects
    /// already held its values, feature `alloc`): the refresh after an
    /// input reads them again only then.
    tpdos_stale: bool,
    /// The application's power-on values, taken at boot (restored by
    /// reset node).
    power_on: <S::Objects as PowerOnValues>::Snapshot,
    /// The profile's frames and EMCYs: a full queue drops its oldest
    /// frame and counts it ([`Machine::frames_dropped`]).
    transmit: EventQueue<CanFrame, Q>,
    events: EventQueue<S::Event, Q>,
    /// The optional LSS slave (CiA 305).
    #[cfg(feature = "lss")]
    lss: Option<LssSlave>,
    /// [`Device::boot`] was called (a device waiting for its LSS node-ID
    /// is powered but not running).
    #[cfg(feature = "lss")]
    powered: bool,
    /// Node guarding, SYNC and TIME (services.rs).
    services: services::Services,
    /// Where 1010h stores (parameters.rs; feature `store`).
    #[cfg(feature = "store")]
    storage: parameters::Storage,
}

impl<S, const Q: usize, const T: usize, const R: usize> core::fmt::Debug for Device<S, Q, T, R>
where
    S: DeviceSpec,
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Device")
            .field("power_on", &self.config)
            .field("node", &self.node)
            .field("nmt_state", &self.nmt.state())
            .field("comm", self.comm())
            .field("objects", self.objects())
            .finish_non_exhaustive()
    }
}

impl<S, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R>
where
    S: DeviceSpec<PowerOn = DeviceConfig>,
{
    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &DeviceConfig {
        &self.config
    }
}

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// A device with `config` (a [`DeviceConfig`], or what one is rebuilt
    /// from: [`PowerOn`]) over the application objects `app`, not yet
    /// booted.
    pub fn new(config: S::PowerOn, app: S::Objects) -> Self {
        let mut device = Self::blank(config, app);
        device.load_power_on();
        device
    }

    /// The device before its power-on values are loaded: constants where
    /// [`load_power_on`](Self::load_power_on) writes the values (the
    /// communication objects, the PDO configuration, the SDO server's
    /// channel, the heartbeat), so that their code exists once, in the
    /// reset path.
    #[inline]
    pub(crate) fn blank(config: S::PowerOn, app: S::Objects) -> Self {
        let node = config.node();
        let power_on = app.snapshot();
        Device {
            config,
            node,
            error_field: ErrorFieldFormat::LittleEndianInfo,
            nmt: NmtCore::new(node),
            nmt_boot: None,
            heartbeat: HeartbeatProducer::with_period_ms(node, 0),
            #[cfg(feature = "heartbeat-consumer")]
            consumer: HeartbeatConsumer::new(),
            server: Server::unconfigured(PdoDictionary::new(
                PdoConfig::empty(),
                DeviceObjects {
                    comm: CommObjects::new(node),
                    app,
                },
            )),
            tpdos: TpdoSet::empty(),
            rpdos: RpdoReceiver::empty(),
            tpdos_enabled: true,
            tpdos_stale: true,
            power_on,
            transmit: EventQueue::new(CanFrame::EMPTY),
            events: EventQueue::new(<S::Event>::from(DeviceEvent::Reset { node: true })),
            #[cfg(feature = "lss")]
            lss: None,
            #[cfg(feature = "lss")]
            powered: false,
            services: services::Services::new(node),
            #[cfg(feature = "store")]
            storage: None,
        }
    }

    /// The communication objects as they are, nothing put into effect: for
    /// a profile's constructor that writes its constants (1000h, 1008h,
    /// 1018h) into the blank before [`load_power_on`](Self::load_power_on)
    /// reads them.
    pub(crate) fn comm_before_power_on(&mut self) -> &mut CommObjects {
        &mut self.od_mut().inner.comm
    }

    /// Writes the power-on values of the communication objects and the PDO
    /// configuration into the dictionary in place ([`PowerOn::restore`]),
    /// and starts the SDO server and the heartbeat producer over on them:
    /// what [`new`](Self::new) and every reset do (the same path, no
    /// second dictionary or server built and moved).
    pub(crate) fn load_power_on(&mut self) {
        self.tpdos_stale = true;
        let od = self.server.od_mut();
        let policies = self.config.restore(&mut od.inner.comm, &mut od.config);
        let period_ms = od.inner.comm.heartbeat_ms;
        self.error_field = policies.error_field;
        self.server.restart(policies.server_config(self.node));
        self.heartbeat = HeartbeatProducer::with_period_ms(self.node, period_ms);
        self.heartbeat.send_on_change = policies.heartbeat_on_change;
        // The power-on values made the objects anew: 1010h/1011h's
        // capability follows the storage.
        #[cfg(feature = "store")]
        self.mark_storable();
    }

    // ----- getters ---------------------------------------------------------

    /// What the power-on configuration is made from (see [`PowerOn`]).
    #[must_use]
    pub const fn power_on(&self) -> &S::PowerOn {
        &self.config
    }

    /// The node id.
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.node
    }

    /// The NMT state ([`NmtState::BootUp`] until [`boot`](Self::boot)).
    #[must_use]
    pub const fn nmt_state(&self) -> NmtState {
        self.nmt.state()
    }

    /// True once booted.
    #[must_use]
    pub const fn is_running(&self) -> bool {
        self.nmt.is_running()
    }

    /// The whole dictionary the SDO server serves.
    #[must_use]
    pub const fn dictionary(&self) -> &Dictionary<S::Objects, T, R> {
        self.server.od()
    }

    /// The application objects.
    #[must_use]
    pub const fn objects(&self) -> &S::Objects {
        &self.server.od().inner.app
    }

    /// The communication objects.
    #[must_use]
    pub const fn comm(&self) -> &CommObjects {
        &self.server.od().inner.comm
    }

    /// The PDO configuration (1400h-1A03h) as the SDO server sees it.
    #[must_use]
    pub const fn pdo_config(&self) -> &PdoConfig<T, R> {
        &self.server.od().config
    }

    /// 1001h error register.
    #[must_use]
    pub const fn error_register(&self) -> ErrorRegister {
        self.comm().error_register
    }

    // ----- commands --------------------------------------------------------

    /// Boots the device (power-on): boot-up message, pre-operational. The
    /// profile sees the state change: what [`Profile::boot`] does (a
    /// device is booted by [`ProfiledDevice::boot`]).
    pub fn boot<P: Profile<S, Q, T, R>>(&mut self, now: Timestamp, profile: &mut P) {
        // The application's parameters as they are now are the power-on
        // values reset node restores.
        self.power_on = self.objects().snapshot();
        // The LSS configuration stored (CiA 305) is the slave's at power-on.
        #[cfg(all(feature = "lss", feature = "store"))]
        if let Some(event) = self.load_lss() {
            self.emit(now, DeviceEvent::Storage(event), profile);
        }
        #[cfg(feature = "lss")]
        {
            self.powered = true;
            if self.lss.as_ref().is_some_and(|l| l.node_id().is_none()) {
                // No node-ID: silent but for LSS until one is configured
                // (then a reset communication starts it: the application
                // parameters stored are loaded now).
                #[cfg(feature = "store")]
                if let Some(event) = self.load_group(store::ParameterGroup::Application) {
                    self.emit(now, DeviceEvent::Storage(event), profile);
                }
                return;
            }
        }
        #[cfg(feature = "store")]
        {
            let stored = self.restart(now, ResetKind::Node);
            self.report_storage(now, stored, profile);
        }
        #[cfg(not(feature = "store"))]
        self.restart(now, ResetKind::Node);
        self.report_nmt_boot(now, profile);
    }

    /// Changes application objects in `f`; mapped values that changed are
    /// events for the event-driven TPDOs.
    pub fn update(&mut self, now: Timestamp, f: impl FnOnce(&mut S::Objects)) {
        f(&mut self.od_mut().inner.app);
        self.refresh_tpdos(now);
    }

    /// [`update`](Self::update) for an `f` that says whether it changed
    /// anything (an application that writes its whole state every time,
    /// most of it as it was): the mapped objects are read again only when
    /// it did, or when something else changed the objects since the TPDOs
    /// last read them.
    pub fn update_changed(&mut self, now: Timestamp, f: impl FnOnce(&mut S::Objects) -> bool) {
        self.tpdos_stale |= f(&mut self.server.od_mut().inner.app);
        self.refresh_stale_tpdos(now);
    }

    /// Changes communication objects in `f` (the application's own
    /// changes; no SDO rules applied): a changed 1017h re-arms the
    /// heartbeat, changed 1016h entries restart their supervision.
    pub fn update_comm(&mut self, now: Timestamp, f: impl FnOnce(&mut CommObjects)) {
        f(&mut self.od_mut().inner.comm);
        self.apply_heartbeat_period(now);
        #[cfg(feature = "heartbeat-consumer")]
        self.apply_consumers();
        self.apply_services(now);
        self.refresh_tpdos(now);
    }

    /// Changes the PDO configuration in `f` (no SDO rules applied) and puts
    /// it into effect.
    pub fn update_pdos(&mut self, now: Timestamp, f: impl FnOnce(&mut PdoConfig<T, R>)) {
        f(&mut self.od_mut().config);
        self.reconfigure_pdos(now);
    }

    /// Mutable access to the application objects without side effects
    /// (for the profile's own bookkeeping).
    pub fn objects_mut(&mut self) -> &mut S::Objects {
        &mut self.od_mut().inner.app
    }

    /// Whether the TPDOs may run besides NMT operational (the profile's
    /// condition; default true).
    pub fn set_tpdos_enabled(&mut self, now: Timestamp, enabled: bool) {
        self.tpdos_enabled = enabled;
        self.gate_pdos(now);
    }

    /// Enters `state` by the device's own decision (e.g. a charger that
    /// starts itself), as an NMT command would.
    pub fn set_nmt_state<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        state: NmtState,
        profile: &mut P,
    ) {
        if self.nmt.is_running() && !matches!(state, NmtState::BootUp) {
            self.report_nmt_boot(now, profile);
            if let Some(event) = self.nmt.set_state(state) {
                self.nmt_event(now, event, profile);
            }
        }
    }

    /// Sets `bits` (and the generic bit) in 1001h, records `emcy` in 1003h
    /// and sends it with the new register value.
    pub fn raise_error(&mut self, bits: ErrorRegister, mut emcy: Emergency) {
        let entry = self.error_field.entry(&emcy);
        let comm = &mut self.od_mut().inner.comm;
        comm.error_register |= bits | ErrorRegister::GENERIC;
        comm.push_error(entry);
        emcy.register = comm.error_register;
        self.send_emergency(&emcy);
    }

    /// Clears `bits` of 1001h and sends the error reset EMCY (0000h) with
    /// the new register value. The generic bit follows CiA 301 (set while
    /// any error is signalled): it is cleared when no other bit is left and
    /// kept, even when `bits` names it, while one is. Does nothing when none
    /// of `bits` is set.
    pub fn clear_error(&mut self, bits: ErrorRegister) {
        let reg = &mut self.od_mut().inner.comm.error_register;
        if !reg.intersects(bits) {
            return;
        }
        reg.remove(bits);
        let others = !reg.difference(ErrorRegister::GENERIC).is_empty();
        reg.set(ErrorRegister::GENERIC, others);
        let register = *reg;
        self.send_emergency(&Emergency {
            code: ErrorCode::NO_ERROR,
            register,
            manufacturer: [0; 5],
        });
    }

    /// Sends an EMCY as it is (no change to 1001h or 1003h); only in
    /// pre-operational and operational.
    pub fn send_emergency(&mut self, emcy: &Emergency) {
        if !self.nmt.sdo_allowed() {
            return;
        }
        self.send(emcy.to_frame(self.node));
    }

    /// Queues a frame of the profile's (sent after EMCYs, before SDO
    /// responses).
    pub fn send(&mut self, frame: CanFrame) {
        self.transmit.push(frame);
    }

    /// Queues an event of the profile's.
    pub fn push_event(&mut self, event: S::Event) {
        self.events.push(event);
    }

    /// Re-reads the TPDO payloads from the objects now (the device does
    /// after every input that may have changed them: an application whose
    /// objects change by themselves, a live reading in its dictionary's
    /// `read`, calls this when they do).
    pub fn refresh_tpdos(&mut self, now: Timestamp) {
        self.tpdos_stale = false;
        self.tpdos.refresh(now, self.server.od_mut());
    }

    /// [`refresh_tpdos`](Self::refresh_tpdos) if anything may have changed
    /// the objects since the last one: re-reading unchanged objects would
    /// give the same payloads, which are no event.
    fn refresh_stale_tpdos(&mut self, now: Timestamp) {
        if self.tpdos_stale {
            self.refresh_tpdos(now);
        }
    }

    /// The dictionary, mutably: whatever is done through it may change a
    /// mapped object, so the TPDOs read them again at the next refresh.
    fn od_mut(&mut self) -> &mut Dictionary<S::Objects, T, R> {
        self.tpdos_stale = true;
        self.server.od_mut()
    }
}

#[cfg(test)]
mod tests;
