//! Node guarding and life guarding (CiA 301 "CANopen application layer and
//! communication profile", section 7.2.8.3.2.1 "Node guarding protocol"),
//! both sides, as sans-IO state machines.
//!
//! The NMT master sends a remote frame on 700h + node every *guard time*
//! (object 100Ch, ms); the slave answers with one byte: bit 7 a toggle bit,
//! bits 6-0 its NMT state. The toggle is 0 in the first reply after boot-up
//! or reset communication and alternates with every reply. The *node life
//! time* is guard time x *life time factor* (object 100Dh).
//!
//! - [`GuardingSlave`] answers the requests and, once the first request has
//!   arrived and both 100Ch and 100Dh are non-zero, supervises the master
//!   (life guarding): no request within the node life time is
//!   [`SlaveGuardingEvent::LifeGuardingLost`], reported once; the next
//!   request is [`SlaveGuardingEvent::LifeGuardingResumed`]. **Heartbeat and
//!   guarding are exclusive** (CiA 301 section 7.2.8.3.2 "Error control
//!   protocols": a device with a non-zero producer heartbeat time 1017h uses
//!   the heartbeat): while [`GuardingSlave::set_heartbeat_active`] is true,
//!   remote requests are not answered and life guarding is off.
//! - [`GuardingMaster`] guards one node: a request every guard time, every
//!   reply checked for the toggle and the state. **Lost** means: the last
//!   `life time factor` requests in a row got no valid reply (no reply, or
//!   a reply whose toggle did not alternate), which is CiA 301's node life
//!   time (guard time x life time factor) counted in requests; a factor of
//!   0 counts as 1. A valid reply after [`MasterGuardingEvent::Lost`] is
//!   [`MasterGuardingEvent::Restored`]; lost and restored alternate.
//!
//! Both implement [`Machine`]; an undrained event queue changes nothing
//! (the back-pressure rule of [`crate::machine`]).

use core::time::Duration;

use crate::clock::{timer_kind, Timers, Timestamp};
use crate::cob_id::NodeId;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::nmt::{error_control_id, guard_request, is_guard_request, Heartbeat, NmtState};
use crate::queue::{EventQueue, FrameQueue};
use crate::wire::Codec;

/// The node life time in microseconds: guard time (ms) x life time factor.
const fn life_time_us(guard_time_ms: u16, life_time_factor: u8) -> u64 {
    guard_time_ms as u64 * life_time_factor as u64 * 1000
}

/// What the guarded slave reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum SlaveGuardingEvent {
    /// No remote request within the node life time (guard time x life time
    /// factor) since the last one: the master stopped guarding (CiA 301
    /// "life guarding event"). Reported once per silence.
    LifeGuardingLost,
    /// A remote request arrived after [`LifeGuardingLost`](Self::LifeGuardingLost).
    LifeGuardingResumed,
}

/// The slave side of node guarding: answers remote requests on 700h + node
/// and supervises the master (life guarding). See the [module docs](self).
///
/// ```
/// use canopen_codec::nmt::guarding::{GuardingSlave, SlaveGuardingEvent};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::nmt::NmtState;
/// use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
/// use core::time::Duration;
/// let mut slave = GuardingSlave::new(NodeId::new(10).unwrap());
/// slave.set_life_guarding(Timestamp::ZERO, Duration::from_millis(100), 3);
/// slave.set_state(NmtState::PreOperational);
/// let request = CanFrame::remote(CanId::Standard(0x70A), 1).unwrap();
/// slave.handle_frame(Timestamp::ZERO, &request);
/// assert_eq!(slave.poll_transmit().unwrap().to_string(), "70A#7F"); // toggle 0
/// slave.handle_frame(Timestamp::from_millis(100), &request);
/// assert_eq!(slave.poll_transmit().unwrap().to_string(), "70A#FF"); // toggle 1
/// // The master stops: 300 ms after the last request, life guarding fires.
/// assert_eq!(slave.poll_timeout(), Some(Timestamp::from_millis(400)));
/// slave.handle_timeout(Timestamp::from_millis(400));
/// assert_eq!(slave.poll_event(), Some(SlaveGuardingEvent::LifeGuardingLost));
/// ```
#[derive(Debug, Clone)]
pub struct GuardingSlave {
    node: NodeId,
    state: NmtState,
    toggle: bool,
    guard_time_ms: u16,
    life_time_factor: u8,
    heartbeat_active: bool,
    /// The time of the last request (life guarding runs once there is one).
    last_request: Option<Timestamp>,
    lost: bool,
    timers: Timers<SlaveTimer, 1>,
    out: FrameQueue<2>,
    events: EventQueue<SlaveGuardingEvent, 2>,
}

timer_kind! {
    /// The slave's one timer: the end of the node life time.
    enum SlaveTimer {
        /// The end of the node life time.
        LifeTime,
    }
}

impl GuardingSlave {
    /// A slave for `node`: toggle 0, state boot-up, guard time and life
    /// time factor 0 (no life guarding), heartbeat not active.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        GuardingSlave {
            node,
            state: NmtState::BootUp,
            toggle: false,
            guard_time_ms: 0,
            life_time_factor: 0,
            heartbeat_active: false,
            last_request: None,
            lost: false,
            timers: Timers::new(),
            out: FrameQueue::empty(),
            events: EventQueue::new(SlaveGuardingEvent::LifeGuardingLost),
        }
    }

    /// The node.
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.node
    }

    /// The toggle bit of the next reply.
    #[must_use]
    pub const fn next_toggle(&self) -> bool {
        self.toggle
    }

    /// True while life guarding is running: a request has arrived, guard
    /// time and life time factor are non-zero and no heartbeat is produced.
    #[must_use]
    pub const fn life_guarding_active(&self) -> bool {
        self.last_request.is_some()
            && self.guard_time_ms != 0
            && self.life_time_factor != 0
            && !self.heartbeat_active
    }

    /// True once life guarding reported the master lost (until its next
    /// request).
    #[must_use]
    pub const fn is_master_lost(&self) -> bool {
        self.lost
    }

    /// Boot-up or reset communication: the toggle goes back to 0 and life
    /// guarding waits for the first request again.
    pub fn reset(&mut self) {
        self.toggle = false;
        self.last_request = None;
        self.lost = false;
        self.timers.clear();
    }

    /// The NMT state the replies report.
    pub fn set_state(&mut self, state: NmtState) {
        self.state = state;
    }

    /// Guard time (100Ch, whole milliseconds, saturating at 65535) and
    /// life time factor (100Dh). Either zero stops life guarding; a running
    /// supervision restarts from `now`.
    pub fn set_life_guarding(&mut self, now: Timestamp, guard_time: Duration, factor: u8) {
        self.guard_time_ms = crate::clock::millis_u16(guard_time);
        self.life_time_factor = factor;
        if self.last_request.is_some() {
            self.last_request = Some(now);
        }
        self.arm();
    }

    /// Whether the node produces heartbeats (1017h non-zero): then it does
    /// not answer remote requests and life guarding is off (CiA 301: the
    /// two error-control protocols are exclusive).
    pub fn set_heartbeat_active(&mut self, now: Timestamp, active: bool) {
        if self.heartbeat_active != active {
            self.heartbeat_active = active;
            if self.last_request.is_some() {
                self.last_request = Some(now);
            }
            self.arm();
        }
    }

    fn arm(&mut self) {
        let deadline = match self.last_request {
            Some(at) if self.life_guarding_active() && !self.lost => {
                at.deadline_after(life_time_us(self.guard_time_ms, self.life_time_factor))
            }
            _ => None,
        };
        self.timers.set(SlaveTimer::LifeTime, deadline);
    }
}

impl Machine for GuardingSlave {
    type Event = SlaveGuardingEvent;

    /// A remote frame on 700h + node (any DLC) is a guarding request: it is
    /// answered (unless the heartbeat is active) and restarts the node life
    /// time. Every other frame is ignored.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        if !is_guard_request(frame, self.node) || self.heartbeat_active {
            return;
        }
        let reply = Heartbeat {
            state: self.state,
            toggle: self.toggle,
        };
        self.toggle = !self.toggle;
        self.out.push(reply.to_frame(self.node));
        self.last_request = Some(now);
        if core::mem::replace(&mut self.lost, false) {
            self.events.push(SlaveGuardingEvent::LifeGuardingResumed);
        }
        self.arm();
    }

    /// Reports the life guarding event when the node life time has run out.
    fn handle_timeout(&mut self, now: Timestamp) {
        if self.timers.expire(SlaveTimer::LifeTime, now) {
            self.lost = true;
            self.events.push(SlaveGuardingEvent::LifeGuardingLost);
        }
    }

    // The end of the node life time, while life guarding runs.
    crate::machine::queued_outputs!(timers: timers, frames: out, events: events);
}

/// What the guarding master reports about its node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum MasterGuardingEvent {
    /// `life time factor` requests in a row got no valid reply (CiA 301
    /// "node guarding event"). Reported once; [`Restored`](Self::Restored)
    /// follows the next valid reply.
    Lost(NodeId),
    /// A valid reply after [`Lost`](Self::Lost).
    Restored {
        /// The node.
        node: NodeId,
        /// The state it reports.
        state: NmtState,
    },
    /// A reply whose toggle bit did not alternate: it does not count as a
    /// reply, and the next reply is expected with the other toggle.
    ToggleError {
        /// The node.
        node: NodeId,
        /// The toggle bit received.
        toggle: bool,
    },
    /// The node reports a state other than the expected one
    /// ([`GuardingMaster::set_expected_state`]); reported when the reported
    /// state changes, not on every reply.
    StateMismatch {
        /// The node.
        node: NodeId,
        /// The state the master expects.
        expected: NmtState,
        /// The state the node reports.
        reported: NmtState,
    },
    /// The node sent its boot-up message: the next reply must have toggle 0.
    BootUp(NodeId),
}

/// The master side of node guarding for one node. See the [module
/// docs](self) for what lost means.
///
/// The toggle bit of the first reply after [`start`](Self::start) is taken
/// as it comes (the node may have been guarded before); after the node's
/// boot-up message it must be 0. Replies are taken only while a request is
/// outstanding (a heartbeat is not a reply).
///
/// ```
/// use canopen_codec::nmt::guarding::{GuardingMaster, MasterGuardingEvent};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// use core::time::Duration;
/// let node = NodeId::new(42).unwrap();
/// let mut master = GuardingMaster::new(node, Duration::from_millis(100), 2);
/// master.start(Timestamp::ZERO);
/// let request = master.poll_transmit().unwrap();
/// assert!(request.is_remote());
/// assert_eq!(request.to_string(), "72A#R1");
/// master.handle_frame(Timestamp::from_millis(5), &CanFrame::standard(0x72A, &[0x7F]).unwrap());
/// // No more replies: two requests in a row unanswered.
/// master.handle_timeout(Timestamp::from_millis(100));
/// master.handle_timeout(Timestamp::from_millis(200));
/// assert_eq!(master.poll_event(), None);
/// master.handle_timeout(Timestamp::from_millis(300));
/// assert_eq!(master.poll_event(), Some(MasterGuardingEvent::Lost(node)));
/// ```
#[derive(Debug, Clone)]
pub struct GuardingMaster {
    node: NodeId,
    guard_time_us: u64,
    life_time_factor: u8,
    expected_state: Option<NmtState>,
    expected_toggle: Option<bool>,
    /// A request is outstanding (no valid reply yet).
    awaiting: bool,
    misses: u8,
    lost: bool,
    state: Option<NmtState>,
    running: bool,
    timers: Timers<MasterTimer, 1>,
    out: FrameQueue<2>,
    events: EventQueue<MasterGuardingEvent, 8>,
}

timer_kind! {
    /// The master's one timer: the next request.
    enum MasterTimer {
        /// The next request.
        NextRequest,
    }
}

impl GuardingMaster {
    /// Guards `node` with guard time `guard_time` (whole milliseconds;
    /// zero sends no requests) and life time factor `life_time_factor`,
    /// not started.
    #[must_use]
    pub fn new(node: NodeId, guard_time: Duration, life_time_factor: u8) -> Self {
        GuardingMaster {
            node,
            guard_time_us: u64::from(crate::clock::millis_u16(guard_time)) * 1000,
            life_time_factor,
            expected_state: None,
            expected_toggle: None,
            awaiting: false,
            misses: 0,
            lost: false,
            state: None,
            running: false,
            timers: Timers::new(),
            out: FrameQueue::empty(),
            events: EventQueue::new(MasterGuardingEvent::BootUp(NodeId::MIN)),
        }
    }

    /// The node guarded.
    #[must_use]
    pub const fn node(&self) -> NodeId {
        self.node
    }

    /// The state of the last valid reply.
    #[must_use]
    pub const fn state(&self) -> Option<NmtState> {
        self.state
    }

    /// True between [`MasterGuardingEvent::Lost`] and the next valid reply.
    #[must_use]
    pub const fn is_lost(&self) -> bool {
        self.lost
    }

    /// True while guarding.
    #[must_use]
    pub const fn is_running(&self) -> bool {
        self.running
    }

    /// The node life time: guard time x life time factor (a factor of 0
    /// counts as 1).
    #[must_use]
    pub fn node_life_time(&self) -> Duration {
        Duration::from_micros(
            self.guard_time_us
                .saturating_mul(u64::from(self.life_time_factor.max(1))),
        )
    }

    /// The state the node should report (`None`: any). A reply with
    /// another state is [`MasterGuardingEvent::StateMismatch`].
    pub fn set_expected_state(&mut self, state: Option<NmtState>) {
        self.expected_state = state;
    }

    /// Starts guarding: the first request now, then one every guard time.
    pub fn start(&mut self, now: Timestamp) {
        self.running = true;
        self.awaiting = false;
        self.misses = 0;
        self.expected_toggle = None;
        self.request(now);
    }

    /// Stops guarding (no more requests; a lost node stays lost).
    pub fn stop(&mut self) {
        self.running = false;
        self.awaiting = false;
        self.timers.clear();
    }

    fn request(&mut self, now: Timestamp) {
        if self.guard_time_us == 0 {
            return;
        }
        self.out.push(guard_request(self.node));
        self.awaiting = true;
        self.timers.set(
            MasterTimer::NextRequest,
            now.deadline_after(self.guard_time_us),
        );
    }

    fn reply(&mut self, reply: Heartbeat) {
        if let Some(expected) = self.expected_toggle {
            if reply.toggle != expected {
                self.expected_toggle = Some(!reply.toggle);
                self.events.push(MasterGuardingEvent::ToggleError {
                    node: self.node,
                    toggle: reply.toggle,
                });
                return;
            }
        }
        self.expected_toggle = Some(!reply.toggle);
        self.awaiting = false;
        self.misses = 0;
        let previous = self.state.replace(reply.state);
        if core::mem::replace(&mut self.lost, false) {
            self.events.push(MasterGuardingEvent::Restored {
                node: self.node,
                state: reply.state,
            });
        }
        match self.expected_state {
            Some(expected) if expected != reply.state && previous != Some(reply.state) => {
                self.events.push(MasterGuardingEvent::StateMismatch {
                    node: self.node,
                    expected,
                    reported: reply.state,
                });
            }
            _ => {}
        }
    }
}

impl Machine for GuardingMaster {
    type Event = MasterGuardingEvent;

    /// Takes the node's boot-up message at any time and its one-byte
    /// replies while a request is outstanding; ignores every other frame.
    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        if frame.is_remote() || frame.id() != error_control_id(self.node) {
            return;
        }
        let Ok(reply) = Heartbeat::parse_frame(frame) else {
            return;
        };
        if reply.is_boot_up() && !reply.toggle {
            // A reply never reports state 0: this is the boot-up message.
            self.expected_toggle = Some(false);
            self.state = None;
            self.events.push(MasterGuardingEvent::BootUp(self.node));
        } else if self.running && self.awaiting {
            self.reply(reply);
        }
    }

    /// Sends the next request; a request still unanswered is a miss, and
    /// `life time factor` misses in a row are [`MasterGuardingEvent::Lost`].
    fn handle_timeout(&mut self, now: Timestamp) {
        let Some(due) = self.timers.get(MasterTimer::NextRequest) else {
            return;
        };
        if !self.timers.expire(MasterTimer::NextRequest, now) {
            return;
        }
        if self.awaiting {
            self.misses = self.misses.saturating_add(1);
            if self.misses >= self.life_time_factor.max(1) && !self.lost {
                self.lost = true;
                self.events.push(MasterGuardingEvent::Lost(self.node));
            }
        }
        // The next request one guard time after the one due (no drift),
        // or one guard time from now when the call is that late.
        match due.deadline_after(self.guard_time_us) {
            Some(next) if !now.has_reached(next) => {
                self.request(due);
            }
            _ => self.request(now),
        }
    }

    // When the next request is due.
    crate::machine::queued_outputs!(timers: timers, frames: out, events: events);
}

#[cfg(test)]
#[path = "guarding_tests.rs"]
mod tests;
