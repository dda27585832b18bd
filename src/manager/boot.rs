//! [`BootManager`]: the NMT master's start-up and the boot process of every
//! assigned slave (CiA 302-2 "Network management", sections 4.3 "NMT
//! master start-up" and 4.4 "boot NMT slave").

use super::config::{ManagerConfig, NmtStartup, NodeConfig};
use super::error::{BootError, BootEvent};
use super::slave::{BootPhase, BootSlave};
use crate::clock::{earliest, Timestamp};
use crate::cob_id::NodeId;
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::nmt::{NmtCommand, NmtCommandSpecifier, NmtTarget};
use crate::queue::{EventQueue, FrameQueue};

/// Why a slave could not be added.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum ManagerError {
    /// Every one of the manager's `N` places is taken.
    #[error("the manager manages {capacity} slaves already")]
    Full {
        /// `N`.
        capacity: usize,
    },
    /// The node is managed already.
    #[error("node {0} is managed already")]
    Duplicate(NodeId),
    /// Its 1F81h assignment does not make it a slave (bit 0 clear).
    #[error("node {0} is not a slave (1F81h bit 0 clear)")]
    NotSlave(NodeId),
    /// The manager has started: slaves are added before [`BootManager::start`].
    #[error("slaves are added before the manager starts")]
    Started,
    /// [`BootManager::start_node`] of a node the manager does not manage.
    #[error("node {0} is not managed")]
    NotManaged(NodeId),
    /// [`BootManager::start_node`] of a slave that has not booted (or is
    /// started already).
    #[error("node {0} has not booted")]
    NotBooted(NodeId),
}

/// The boot-up manager: the NMT master start-up and the boot process of up
/// to `N` slaves, each with its own SDO client; `E` events are kept (the
/// oldest dropped and counted beyond; one call makes at most 4 per slave
/// and 2 of the network, so 4 x `N` + 2 is enough for a caller that reads
/// them after every call). See the [module docs](super) for the process
/// and an example.
///
/// Poll order after every `handle_*` call and [`start`](Self::start):
/// [`poll_transmit`](Machine::poll_transmit) until `None` (the NMT
/// commands to all nodes first, then each slave's frames in the order of
/// [`add_node`](Self::add_node)), then [`poll_event`](Machine::poll_event)
/// and [`poll_timeout`](Machine::poll_timeout).
#[derive(Debug)]
pub struct BootManager<'a, const N: usize, const E: usize = 32> {
    config: ManagerConfig,
    slaves: [Option<BootSlave<'a>>; N],
    started: bool,
    network_started: bool,
    /// When 1F89h, the boot time, ends (armed by [`start`](Self::start)).
    boot_deadline: Option<Timestamp>,
    /// NMT commands to all nodes.
    out: FrameQueue<2>,
    events: EventQueue<BootEvent, E>,
}

impl<'a, const N: usize, const E: usize> BootManager<'a, N, E> {
    /// A manager with no slave, not started.
    #[must_use]
    pub fn new(config: ManagerConfig) -> Self {
        BootManager {
            config,
            slaves: [const { None }; N],
            started: false,
            network_started: false,
            boot_deadline: None,
            out: FrameQueue::empty(),
            events: EventQueue::new(BootEvent::NetworkStarted),
        }
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &ManagerConfig {
        &self.config
    }

    /// Adds a slave (its 1F81h bit 0 must be set), before
    /// [`start`](Self::start).
    pub fn add_node(&mut self, node: NodeConfig<'a>) -> Result<(), ManagerError> {
        if self.started {
            return Err(ManagerError::Started);
        }
        if !node.assignment.is_slave() {
            return Err(ManagerError::NotSlave(node.node));
        }
        if self.slave(node.node).is_some() {
            return Err(ManagerError::Duplicate(node.node));
        }
        let free = self.slaves.iter_mut().find(|s| s.is_none());
        let Some(free) = free else {
            return Err(ManagerError::Full { capacity: N });
        };
        *free = Some(BootSlave::new(node, self.config));
        Ok(())
    }

    /// Where `node`'s boot process is (`None`: not managed).
    #[must_use]
    pub fn phase(&self, node: NodeId) -> Option<BootPhase> {
        self.slave(node).map(BootSlave::phase)
    }

    /// True once the network was started ([`BootEvent::NetworkStarted`]).
    #[must_use]
    pub const fn network_started(&self) -> bool {
        self.network_started
    }

    fn slave(&self, node: NodeId) -> Option<&BootSlave<'a>> {
        self.slaves
            .iter()
            .flatten()
            .find(|s| s.config().node == node)
    }

    /// The NMT master start-up (CiA 302-2 section 4.3): every slave's
    /// communication is reset (one NMT command to all nodes with 1F80h
    /// [`RESET_ALL`](NmtStartup::RESET_ALL), else one per slave; none for
    /// a keep-alive slave) and its boot process starts with its boot-up
    /// message, or after [`ManagerConfig::boot_up_wait`] without one.
    /// Calling it again starts everything over.
    pub fn start(&mut self, now: Timestamp) {
        self.started = true;
        self.network_started = false;
        let boot_time = crate::clock::micros_of(self.config.boot_time);
        self.boot_deadline = (boot_time != 0).then(|| now.add_micros(boot_time));
        let reset_all = self.config.startup.contains(NmtStartup::RESET_ALL);
        if reset_all {
            self.nmt_all(NmtCommandSpecifier::ResetCommunication);
        }
        for slave in self.slaves.iter_mut().flatten() {
            slave.start(now, reset_all, &mut self.events);
        }
        self.auto_start();
    }

    /// The application starts `node` (for 1F80h
    /// [`NO_SLAVE_START`](NmtStartup::NO_SLAVE_START), CiA 302-2 section
    /// 4.3: the application, not the manager, starts the slaves): one NMT
    /// "start remote node" to it and [`BootEvent::Operational`]. The slave
    /// must have [`Booted`](BootPhase::Booted).
    pub fn start_node(&mut self, now: Timestamp, node: NodeId) -> Result<(), ManagerError> {
        let _ = now;
        let mut slaves = self.slaves.iter_mut().flatten();
        let Some(slave) = slaves.find(|s| s.config().node == node) else {
            return Err(ManagerError::NotManaged(node));
        };
        if slave.phase() != BootPhase::Booted {
            return Err(ManagerError::NotBooted(node));
        }
        slave.start_node(&mut self.events);
        Ok(())
    }

    /// The application starts the network now (1F80h
    /// [`NO_SLAVE_START`](NmtStartup::NO_SLAVE_START), or to start without
    /// the mandatory slaves that are missing): [`BootEvent::NetworkStarted`],
    /// then every booted slave is started as the manager would (one NMT
    /// command to all nodes with [`START_ALL`](NmtStartup::START_ALL)).
    /// Slaves that boot afterwards are started by the manager, unless
    /// `NO_SLAVE_START` leaves that to [`start_node`](Self::start_node).
    pub fn start_network(&mut self, now: Timestamp) {
        let _ = now;
        self.launch();
    }

    fn nmt_all(&mut self, command: NmtCommandSpecifier) {
        self.out
            .push(NmtCommand::new(command, NmtTarget::All).to_frame());
    }

    /// Starts the network once every mandatory slave has booted and every
    /// slave's first boot process has ended; afterwards starts each slave
    /// that boots.
    fn auto_start(&mut self) {
        if !self.started || self.config.startup.contains(NmtStartup::NO_SLAVE_START) {
            return;
        }
        if !self.network_started {
            let ready = self.slaves.iter().flatten().all(|s| {
                s.settled()
                    && (!s.config().assignment.is_mandatory() || s.phase() == BootPhase::Booted)
            });
            if ready {
                self.launch();
            }
            return;
        }
        self.start_booted();
    }

    /// The network's start: [`BootEvent::NetworkStarted`] and every booted
    /// slave started.
    fn launch(&mut self) {
        self.network_started = true;
        self.boot_deadline = None;
        self.events.push(BootEvent::NetworkStarted);
        if !self.config.startup.contains(NmtStartup::START_ALL) {
            return self.start_booted();
        }
        self.nmt_all(NmtCommandSpecifier::Start);
        for slave in self.slaves.iter_mut().flatten() {
            if slave.phase() == BootPhase::Booted {
                slave.started(&mut self.events);
            }
        }
    }

    /// Starts each booted slave with its own NMT command.
    fn start_booted(&mut self) {
        for slave in self.slaves.iter_mut().flatten() {
            if slave.phase() == BootPhase::Booted {
                slave.start_node(&mut self.events);
            }
        }
    }

    /// 1F89h passed: each mandatory slave not booted is reported.
    fn boot_time_elapsed(&mut self, now: Timestamp) {
        if self.boot_deadline.is_none_or(|at| now < at) {
            return;
        }
        self.boot_deadline = None;
        for slave in self.slaves.iter().flatten() {
            let missing = slave.phase() != BootPhase::Booted;
            if missing && slave.config().assignment.is_mandatory() {
                self.events.push(BootEvent::BootTimeElapsed {
                    node: slave.config().node,
                });
            }
        }
    }

    /// Runs `f` on every slave, reporting a mandatory slave's failure that
    /// holds the network start.
    fn each_slave(&mut self, mut f: impl FnMut(&mut BootSlave<'a>, &mut EventQueue<BootEvent, E>)) {
        for slave in self.slaves.iter_mut().flatten() {
            let before = slave.phase();
            f(slave, &mut self.events);
            let failed = matches!(slave.phase(), BootPhase::Failed(_))
                && !matches!(before, BootPhase::Failed(_));
            if failed && !self.network_started && slave.config().assignment.is_mandatory() {
                self.events.push(BootEvent::StartHeld {
                    node: slave.config().node,
                });
            }
        }
        self.auto_start();
    }

    /// A boot-up message of a node that is not a slave: error status A.
    fn unlisted_boot_up(&mut self, frame: &CanFrame) {
        let CanId::Standard(raw) = frame.id() else {
            return;
        };
        if frame.is_remote() || raw & 0x780 != 0x700 || frame.data() != [0] {
            return;
        }
        let Some(node) = NodeId::new((raw & 0x7F) as u8) else {
            return;
        };
        if self.slave(node).is_none() {
            self.events.push(BootEvent::Error {
                node,
                error: BootError::NotListed,
            });
        }
    }
}

impl<const N: usize, const E: usize> Machine for BootManager<'_, N, E> {
    type Event = BootEvent;

    /// Each slave takes its SDO answers, its heartbeats, guarding replies
    /// and boot-up message (which starts its boot process again).
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if !self.started {
            return;
        }
        self.each_slave(|s, events| s.handle_frame(now, frame, events));
        self.unlisted_boot_up(frame);
    }

    /// SDO timeouts and retries, the boot-up wait, the start of error
    /// control, heartbeat supervision and guarding requests.
    fn handle_timeout(&mut self, now: Timestamp) {
        if !self.started {
            return;
        }
        self.each_slave(|s, events| s.handle_timeout(now, events));
        self.boot_time_elapsed(now);
    }

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        if let Some(frame) = self.out.pop() {
            return Some(frame);
        }
        self.slaves
            .iter_mut()
            .flatten()
            .find_map(BootSlave::poll_transmit)
    }

    /// The earliest deadline of every slave.
    fn poll_timeout(&self) -> Option<Timestamp> {
        let slaves = self.slaves.iter().flatten().map(BootSlave::poll_timeout);
        earliest(slaves.chain([self.boot_deadline]))
    }

    fn poll_event(&mut self) -> Option<BootEvent> {
        self.events.pop()
    }

    fn events_dropped(&self) -> u64 {
        self.events.dropped()
    }

    fn frames_dropped(&self) -> u64 {
        self.slaves
            .iter()
            .flatten()
            .fold(self.out.dropped(), |n, s| {
                n.saturating_add(s.frames_dropped())
            })
    }
}
