//! The boot process of one slave (CiA 302-2 "Network management", section
//! 4.4, "boot NMT slave"), driven by the [`BootManager`](super::BootManager)
//! that owns it: its SDO client (CiA 301 default channel 600h/580h + node),
//! its error control (heartbeat consumer time, or node guarding) and the
//! frames it sends. Its software check and update are in [`software`].

mod software;

use super::config::{ManagerConfig, NmtStartup, NodeConfig};
use super::error::{BootError, BootEvent, ConfigurationFailure, IdentityCheck, SoftwareCheck};
use crate::abort::AbortCode;
use crate::clock::{earliest, micros_of, timer_kind, Timers, Timestamp};
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::nmt::guarding::{GuardingMaster, MasterGuardingEvent};
use crate::nmt::{
    error_control_id, Heartbeat, NmtCommand, NmtCommandSpecifier, NmtState, NmtTarget,
};
use crate::od::ConciseEntries;
use crate::queue::{EventQueue, FrameQueue};
use crate::sdo::{
    AbortOrigin, Client, ClientConfig, ClientEvent, ProgramDownload, TransferEnd, EVENTS_PER_CALL,
};
use crate::wire::Codec;

/// Object 1000h "device type" (CiA 301 section 7.5.2.1).
const DEVICE_TYPE: u16 = 0x1000;
/// Object 1018h "identity object" (CiA 301 section 7.5.2.30).
const IDENTITY: u16 = 0x1018;

/// Where a slave's boot process is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BootPhase {
    /// The manager has not started.
    Idle,
    /// Its communication was reset: the boot-up message is awaited.
    AwaitBootUp,
    /// Reading 1000h.
    DeviceType,
    /// Reading 1018h at this sub-index.
    Identity(u8),
    /// A keep-alive slave's state is checked (1F81h bit 4): its heartbeat
    /// is awaited.
    NodeState,
    /// Reading the object of this comparison of the software check
    /// (1F81h bit 5): 1F56h sub 1, 1F52h sub 1 or 2.
    Software(SoftwareCheck),
    /// Downloading the program into the slave (1F81h bit 6): stop, clear,
    /// 1F50h, 1F57h, 1F56h, start (CiA 302-3).
    SoftwareUpdate,
    /// Writing this entry (0-based) of its concise DCF.
    Configuration(u32),
    /// Starting error control: the first heartbeat or guarding reply is
    /// awaited.
    ErrorControl,
    /// Booted, waiting for its start.
    Booted,
    /// Started: under error control.
    Operational,
    /// The boot process failed; the next boot-up message starts it again.
    Failed(BootError),
}

timer_kind! {
    /// A slave's own deadlines (its SDO client and its guarding master keep
    /// theirs).
    enum SlaveTimer {
        /// The end of the boot-up wait, or of the start of error control.
        Phase,
        /// The heartbeat consumer time, while supervising.
        Heartbeat,
        /// The asynchronous retry after an error B.
        Retry,
    }
}

/// One slave under the manager.
#[derive(Debug)]
pub(crate) struct BootSlave<'a> {
    config: NodeConfig<'a>,
    manager: ManagerConfig,
    /// The heartbeat consumer time in µs, when the slave produces one.
    consumer_us: Option<u64>,
    client: Client<&'a [u8], EVENTS_PER_CALL>,
    guard: GuardingMaster,
    phase: BootPhase,
    /// Tries of the read of 1000h made so far.
    tries: u8,
    /// The value being read (4 bytes at most are kept).
    value: [u8; 4],
    /// 1000h as read.
    device_type: u32,
    /// The entries of its concise DCF still to write.
    entries: Option<ConciseEntries<'a>>,
    /// Its first boot process has ended (booted or failed).
    settled: bool,
    /// Error control reported it lost.
    lost: bool,
    /// A keep-alive slave whose state is still to be checked after its
    /// identity (once per [`start`](Self::start)).
    check_state: bool,
    /// The state check found it operational (**L**): it is not configured
    /// and not started again.
    initially_operational: bool,
    /// The program download of a software update, while it runs.
    update: Option<ProgramDownload<&'a [u8]>>,
    /// The program was downloaded in this boot process: a software check
    /// that still differs is I, not a second download.
    updated: bool,
    timers: Timers<SlaveTimer, 3>,
    out: FrameQueue<4>,
}

impl<'a> BootSlave<'a> {
    pub(crate) fn new(config: NodeConfig<'a>, manager: ManagerConfig) -> Self {
        let mut sdo = ClientConfig::for_server(config.node);
        sdo.timeout = manager.sdo_timeout;
        let assignment = config.assignment;
        BootSlave {
            consumer_us: config
                .heartbeat
                .filter(|p| !p.is_zero())
                .map(|p| micros_of(manager.consumer_time(p))),
            client: Client::with_event_capacity(sdo),
            guard: GuardingMaster::new(
                config.node,
                assignment.guard_time(),
                assignment.retry_factor(),
            ),
            config,
            manager,
            phase: BootPhase::Idle,
            tries: 0,
            value: [0; 4],
            device_type: 0,
            entries: None,
            settled: false,
            lost: false,
            check_state: false,
            initially_operational: false,
            update: None,
            updated: false,
            timers: Timers::new(),
            out: FrameQueue::empty(),
        }
    }

    pub(crate) const fn config(&self) -> &NodeConfig<'a> {
        &self.config
    }

    pub(crate) const fn phase(&self) -> BootPhase {
        self.phase
    }

    pub(crate) const fn settled(&self) -> bool {
        self.settled
    }

    /// The manager's start-up: reset the slave's communication (unless
    /// `reset_sent`: one command to all nodes went out, or keep alive)
    /// and wait for its boot-up.
    pub(crate) fn start<const E: usize>(
        &mut self,
        now: Timestamp,
        reset_sent: bool,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        self.settled = false;
        self.initially_operational = false;
        self.updated = false;
        self.check_state = self.config.assignment.keeps_alive();
        if self.check_state {
            return self.begin(now, events);
        }
        if !reset_sent {
            self.nmt(NmtCommandSpecifier::ResetCommunication, false);
        }
        self.await_boot_up(now);
    }

    /// Waits for the slave's boot-up message, or
    /// [`boot_up_wait`](ManagerConfig::boot_up_wait) without one.
    fn await_boot_up(&mut self, now: Timestamp) {
        self.stop_all_timers();
        self.phase = BootPhase::AwaitBootUp;
        let wait = micros_of(self.manager.boot_up_wait);
        self.timers
            .set(SlaveTimer::Phase, Some(now.add_micros(wait)));
    }

    /// Starts the slave with its own NMT command.
    /// (Not one found operational at its state check: it runs already.)
    pub(crate) fn start_node<const E: usize>(&mut self, events: &mut EventQueue<BootEvent, E>) {
        if !self.initially_operational {
            self.nmt(NmtCommandSpecifier::Start, false);
        }
        self.started(events);
    }

    /// The slave was started by an NMT command to all nodes.
    pub(crate) fn started<const E: usize>(&mut self, events: &mut EventQueue<BootEvent, E>) {
        self.phase = BootPhase::Operational;
        events.push(BootEvent::Operational {
            node: self.config.node,
        });
    }

    fn nmt(&mut self, command: NmtCommandSpecifier, all: bool) {
        let target = if all {
            NmtTarget::All
        } else {
            NmtTarget::Node(self.config.node)
        };
        self.out.push(NmtCommand::new(command, target).to_frame());
    }

    fn stop_all_timers(&mut self) {
        self.client.reset();
        self.guard.stop();
        self.update = None;
        self.timers.clear();
        self.lost = false;
    }

    /// The boot process from its first step.
    fn begin<const E: usize>(&mut self, now: Timestamp, events: &mut EventQueue<BootEvent, E>) {
        self.stop_all_timers();
        self.tries = 0;
        self.initially_operational = false;
        if self.config.assignment.may_boot() {
            self.read(now, BootPhase::DeviceType, events);
        } else {
            self.start_error_control(now, events);
        }
    }

    fn read<const E: usize>(
        &mut self,
        now: Timestamp,
        phase: BootPhase,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        let (index, sub) = match phase {
            BootPhase::Identity(sub) => (IDENTITY, sub),
            BootPhase::Software(check) => check.address(),
            _ => (DEVICE_TYPE, 0),
        };
        self.phase = phase;
        self.value = [0; 4];
        if self.client.start_upload(now, index, sub).is_err() {
            // Never busy here (every step starts after the last ended):
            // reported as the step's failure all the same.
            let code = AbortCode::GeneralError;
            return self.step_failed(now, code, AbortOrigin::Local, events);
        }
        self.pump();
    }

    /// The next 1018h sub to check after `sub`, if any.
    fn next_identity(&self, sub: u8) -> Option<u8> {
        (sub.saturating_add(1)..=4).find(|s| self.config.expected.identity(*s) != 0)
    }

    fn value_read(&self) -> u32 {
        u32::from_le_bytes(self.value)
    }

    fn uploaded<const E: usize>(&mut self, now: Timestamp, events: &mut EventQueue<BootEvent, E>) {
        let read = self.value_read();
        let expected = self.config.expected;
        if let BootPhase::Software(check) = self.phase {
            return self.software_read(now, check, read, events);
        }
        let (check, want, done_sub) = match self.phase {
            BootPhase::DeviceType => (IdentityCheck::DeviceType, expected.device_type, 0),
            BootPhase::Identity(sub) => (
                IdentityCheck::of_identity_sub(sub),
                expected.identity(sub),
                sub,
            ),
            _ => return,
        };
        if want != 0 && want != read {
            return self.fail(
                BootError::Identity {
                    check,
                    expected: want,
                    read: Some(read),
                },
                events,
            );
        }
        if check == IdentityCheck::DeviceType {
            self.device_type = read;
        }
        match self.next_identity(done_sub) {
            Some(sub) => self.read(now, BootPhase::Identity(sub), events),
            None => {
                events.push(BootEvent::Identified {
                    node: self.config.node,
                    device_type: self.device_type,
                });
                if core::mem::replace(&mut self.check_state, false) {
                    return self.check_node_state(now);
                }
                self.check_software(now, events);
            }
        }
    }

    /// A keep-alive slave's "check node state" step (CiA 302-2 section 4.4,
    /// after the identity, as lely-core orders it): its next heartbeat
    /// says whether it is operational already (**L**: it is neither
    /// configured nor reset, and keeps running), or not (its communication
    /// is reset and its boot goes on as any slave's). No heartbeat within
    /// the consumer time: **E**. A slave without a heartbeat has no state
    /// to check here: it is reset.
    fn check_node_state(&mut self, now: Timestamp) {
        let Some(us) = self.consumer_us else {
            self.nmt(NmtCommandSpecifier::ResetCommunication, false);
            return self.await_boot_up(now);
        };
        self.phase = BootPhase::NodeState;
        self.timers.set(SlaveTimer::Phase, Some(now.add_micros(us)));
    }

    /// The heartbeat seen at a keep-alive slave's state check.
    fn node_state<const E: usize>(
        &mut self,
        now: Timestamp,
        state: NmtState,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        if state != NmtState::Operational {
            self.nmt(NmtCommandSpecifier::ResetCommunication, false);
            return self.await_boot_up(now);
        }
        self.initially_operational = true;
        events.push(BootEvent::InitiallyOperational {
            node: self.config.node,
        });
        self.booted(events);
    }

    /// Starts the configuration download from its first entry.
    fn configure<const E: usize>(&mut self, now: Timestamp, events: &mut EventQueue<BootEvent, E>) {
        self.entries = self.config.configuration.map(|dcf| dcf.iter());
        self.write_next(now, 0, events);
    }

    /// Writes entry `n` of the concise DCF, or, when all are written,
    /// starts error control (CiA 302-2 section 4.4: the configuration
    /// download comes after the identity check and before error control).
    fn write_next<const E: usize>(
        &mut self,
        now: Timestamp,
        n: u32,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        let Some(entry) = self.entries.as_mut().and_then(Iterator::next) else {
            if self.config.configuration.is_some() {
                events.push(BootEvent::ConfigurationWritten {
                    node: self.config.node,
                    entries: n,
                });
            }
            return self.start_error_control(now, events);
        };
        self.phase = BootPhase::Configuration(n);
        let (index, sub) = (entry.addr.index, entry.addr.sub);
        if let Err(error) = self.client.start_download(now, index, sub, entry.data) {
            let failure = ConfigurationFailure::Refused(error);
            return self.fail(
                BootError::Configuration {
                    index,
                    sub,
                    failure,
                },
                events,
            );
        }
        self.pump();
    }

    fn step_failed<const E: usize>(
        &mut self,
        now: Timestamp,
        code: AbortCode,
        origin: AbortOrigin,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        match self.phase {
            BootPhase::DeviceType => {
                let timed_out =
                    origin == AbortOrigin::Local && code == AbortCode::SdoProtocolTimedOut;
                if timed_out && self.tries < self.manager.retries {
                    self.tries += 1;
                    return self.read(now, BootPhase::DeviceType, events);
                }
                self.fail(BootError::NoResponse { code }, events);
                let retry = micros_of(self.manager.retry_interval);
                if retry != 0 {
                    let at = now.add_micros(retry);
                    self.timers.set(SlaveTimer::Retry, Some(at));
                }
            }
            BootPhase::Identity(sub) => {
                let check = IdentityCheck::of_identity_sub(sub);
                let expected = self.config.expected.identity(sub);
                self.fail(
                    BootError::Identity {
                        check,
                        expected,
                        read: None,
                    },
                    events,
                );
            }
            BootPhase::Software(check) => {
                self.fail(BootError::SoftwareUnreadable { check, code }, events);
            }
            _ => {}
        }
    }

    fn start_error_control<const E: usize>(
        &mut self,
        now: Timestamp,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        self.phase = BootPhase::ErrorControl;
        if let Some(us) = self.consumer_us {
            self.timers.set(SlaveTimer::Phase, Some(now.add_micros(us)));
        } else if !self.config.assignment.guard_time().is_zero() {
            self.guard.start(now);
            self.pump();
        } else {
            self.booted(events);
        }
    }

    fn booted<const E: usize>(&mut self, events: &mut EventQueue<BootEvent, E>) {
        self.timers.set(SlaveTimer::Phase, None);
        self.phase = BootPhase::Booted;
        self.settled = true;
        self.updated = false;
        events.push(BootEvent::Booted {
            node: self.config.node,
        });
    }

    fn fail<const E: usize>(&mut self, error: BootError, events: &mut EventQueue<BootEvent, E>) {
        self.stop_all_timers();
        self.phase = BootPhase::Failed(error);
        self.settled = true;
        self.updated = false;
        events.push(BootEvent::Error {
            node: self.config.node,
            error,
        });
    }

    /// Error control lost the slave after its boot.
    fn lose<const E: usize>(&mut self, error: BootError, events: &mut EventQueue<BootEvent, E>) {
        if core::mem::replace(&mut self.lost, true) {
            return;
        }
        events.push(BootEvent::Lost {
            node: self.config.node,
            error,
        });
        let stop_all = self.manager.startup.contains(NmtStartup::STOP_ALL);
        if stop_all && self.config.assignment.is_mandatory() {
            self.nmt(NmtCommandSpecifier::Stop, true);
        }
    }

    fn restore<const E: usize>(&mut self, events: &mut EventQueue<BootEvent, E>) {
        if core::mem::replace(&mut self.lost, false) {
            events.push(BootEvent::Restored {
                node: self.config.node,
            });
        }
    }

    /// Moves the client's and the guarding master's frames to the slave's
    /// queue, so none replaces another.
    fn pump(&mut self) {
        while let Some(frame) = self.client.poll_transmit() {
            self.out.push(frame);
        }
        while let Some(frame) = self.guard.poll_transmit() {
            self.out.push(frame);
        }
        while let Some(frame) = self.update.as_mut().and_then(Machine::poll_transmit) {
            self.out.push(frame);
        }
    }

    /// The client's events move the boot process on.
    fn drain_client<const E: usize>(
        &mut self,
        now: Timestamp,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        self.pump();
        while let Some(event) = self.client.poll_event() {
            match event {
                ClientEvent::UploadData { offset, data, .. } => {
                    for (i, b) in data.as_slice().iter().enumerate() {
                        if let Some(slot) =
                            offset.checked_add(i).and_then(|at| self.value.get_mut(at))
                        {
                            *slot = *b;
                        }
                    }
                }
                ClientEvent::Ended(TransferEnd::Uploaded { .. }) => self.uploaded(now, events),
                ClientEvent::Ended(TransferEnd::Downloaded { .. }) => {
                    if let BootPhase::Configuration(n) = self.phase {
                        self.write_next(now, n.saturating_add(1), events);
                    }
                }
                ClientEvent::Ended(TransferEnd::Aborted {
                    index,
                    sub,
                    code,
                    origin,
                }) => {
                    if let BootPhase::Configuration(_) = self.phase {
                        let failure = ConfigurationFailure::Aborted { code, origin };
                        let error = BootError::Configuration {
                            index,
                            sub,
                            failure,
                        };
                        self.fail(error, events);
                    } else {
                        self.step_failed(now, code, origin, events);
                    }
                }
            }
            self.pump();
        }
    }

    /// The guarding master's events: its first reply ends the start of
    /// error control; lost is F.
    fn drain_guard<const E: usize>(&mut self, events: &mut EventQueue<BootEvent, E>) {
        self.pump();
        while let Some(event) = self.guard.poll_event() {
            match (event, self.phase) {
                (MasterGuardingEvent::Lost(_), BootPhase::ErrorControl) => {
                    self.fail(BootError::GuardingLost, events);
                }
                (MasterGuardingEvent::Lost(_), BootPhase::Booted | BootPhase::Operational) => {
                    self.lose(BootError::GuardingLost, events);
                }
                (MasterGuardingEvent::Restored { .. }, _) => self.restore(events),
                _ => {}
            }
        }
        if self.phase == BootPhase::ErrorControl && self.guard.state().is_some() {
            self.booted(events);
        }
    }

    pub(crate) fn handle_frame<const E: usize>(
        &mut self,
        now: Timestamp,
        frame: &CanFrame,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        if self.phase == BootPhase::Idle {
            return;
        }
        // The SDO answers go to the program download while it runs, else
        // to the client (never both: an answer that ends one step must not
        // be taken for the first answer of the next).
        if let Some(update) = self.update.as_mut() {
            update.handle_frame(now, frame);
            self.drain_update(now, events);
        } else {
            self.client.handle_frame(now, frame);
            self.drain_client(now, events);
        }
        if frame.is_remote() || frame.id() != error_control_id(self.config.node) {
            return;
        }
        let Ok(beat) = Heartbeat::parse_frame(frame) else {
            return;
        };
        if beat.is_boot_up() && !beat.toggle {
            events.push(BootEvent::BootUp {
                node: self.config.node,
            });
            // A read of 1000h already outstanding is the first step of the
            // process this boot-up starts (a boot-up sent before the
            // manager's reset, then the one after it): a second request
            // would leave the answer to the first on the one SDO channel
            // (CiA 301 section 7.2.4), taken for the answer to the next step.
            // A slave whose program is being downloaded may restart into
            // its boot loader: the download goes on.
            if matches!(
                self.phase,
                BootPhase::DeviceType | BootPhase::SoftwareUpdate
            ) {
                return;
            }
            return self.begin(now, events);
        }
        if self.guard.is_running() {
            self.guard.handle_frame(now, frame);
            return self.drain_guard(events);
        }
        let Some(us) = self.consumer_us else { return };
        match self.phase {
            BootPhase::NodeState => {
                self.node_state(now, beat.state, events);
                if self.phase == BootPhase::AwaitBootUp {
                    return;
                }
            }
            BootPhase::ErrorControl => {
                self.booted(events);
            }
            BootPhase::Booted | BootPhase::Operational => self.restore(events),
            _ => return,
        }
        self.timers
            .set(SlaveTimer::Heartbeat, Some(now.add_micros(us)));
    }

    pub(crate) fn handle_timeout<const E: usize>(
        &mut self,
        now: Timestamp,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        self.client.handle_timeout(now);
        self.drain_client(now, events);
        self.guard.handle_timeout(now);
        self.drain_guard(events);
        if let Some(update) = self.update.as_mut() {
            update.handle_timeout(now);
            self.drain_update(now, events);
        }
        if self.timers.expire(SlaveTimer::Phase, now) {
            match self.phase {
                BootPhase::AwaitBootUp => self.begin(now, events),
                BootPhase::ErrorControl => self.fail(BootError::ErrorControlStart, events),
                BootPhase::NodeState => self.fail(BootError::HeartbeatLost, events),
                _ => {}
            }
        }
        if self.timers.expire(SlaveTimer::Heartbeat, now) {
            self.lose(BootError::HeartbeatLost, events);
        }
        if self.timers.expire(SlaveTimer::Retry, now) {
            self.begin(now, events);
        }
    }

    pub(crate) fn poll_timeout(&self) -> Option<Timestamp> {
        earliest([
            self.timers.next(),
            self.client.poll_timeout(),
            self.guard.poll_timeout(),
            self.update.as_ref().and_then(Machine::poll_timeout),
        ])
    }

    pub(crate) fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.out.pop()
    }

    pub(crate) fn frames_dropped(&self) -> u64 {
        self.out.dropped()
    }
}
