//! The LSS master (CiA 305, "Layer setting services and protocol", section
//! 4): configures a known slave, inquires its address and node-ID, and
//! finds the 128-bit LSS address of one non-configured slave by fastscan.
//!
//! One confirmed service runs at a time. Each step waits for the answers
//! of the slaves until the caller's clock passes the step's deadline
//! ([`LssMaster::handle_timeout`]): a service whose answer did not come
//! ends with [`LssMasterEvent::NoResponse`]. A fastscan is 133 steps (a
//! reset, 4 × 32 bit steps and 4 confirmations) of one timeout each; every
//! fastscan ends in exactly one [`LssMasterEvent::FastscanFound`] or
//! [`LssMasterEvent::FastscanNotFound`] (or [`LssMaster::cancel`]).

use core::time::Duration;

use crate::clock::{Timers, Timestamp};
use crate::cob_id::NodeId;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::queue::{EventQueue, FrameQueue};

use super::slave::NODE_ID_UNCONFIGURED;
use super::wire::{
    Fastscan, LssAddress, LssField, LssInquiry, LssMode, LssRequest, LssResponse, LssStatus,
};

/// The confirmed LSS services, as named in [`LssMasterEvent::NoResponse`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LssService {
    /// Switch state selective.
    SwitchStateSelective,
    /// Configure node-ID.
    ConfigureNodeId,
    /// Configure bit timing.
    ConfigureBitTiming,
    /// Store configuration.
    StoreConfiguration,
    /// Inquire an address part or the node-ID.
    Inquire(LssInquiry),
    /// Identify non-configured remote slave.
    IdentifyNonConfigured,
}

/// What an [`LssMaster`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LssMasterEvent {
    /// A slave answered switch state selective: it is in configuration state.
    SwitchedSelective,
    /// The answer to configure node-ID.
    NodeIdConfigured(LssStatus),
    /// The answer to configure bit timing.
    BitTimingConfigured(LssStatus),
    /// The answer to store configuration.
    Stored(LssStatus),
    /// The answer to inquire an address part.
    Address(LssField, u32),
    /// The answer to inquire node-ID (`None`: not configured).
    NodeId(Option<NodeId>),
    /// At least one non-configured slave answered identify non-configured
    /// remote slave.
    NonConfiguredPresent,
    /// Fastscan found a slave: it is now in configuration state.
    FastscanFound(LssAddress),
    /// Fastscan found no slave (none answered a step).
    FastscanNotFound,
    /// No answer before the deadline.
    NoResponse(LssService),
}

/// Why a master command was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum LssMasterError {
    /// Another confirmed service or a fastscan is running.
    #[error("an LSS service is already running")]
    Busy,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Reset,
    Bit(u8),
    Confirm,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Scan {
    found: LssAddress,
    sub: LssField,
    phase: Phase,
    answered: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Op {
    Idle,
    Wait(LssService),
    Scan(Scan),
}

/// An LSS master. Implements [`Machine`]; commands are inherent methods
/// taking `now`. After each call drain `poll_transmit`, then `poll_event`,
/// then read `poll_timeout`.
///
/// ```
/// use canopen_codec::lss::{LssAddress, LssMaster, LssMasterEvent, LssSlave, LssSlaveConfig};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::Timestamp;
/// use core::time::Duration;
/// let address = LssAddress { vendor: 0x29A, product: 7, revision: 1, serial: 42 };
/// let mut slave = LssSlave::new(LssSlaveConfig::new(address, None));
/// let mut master = LssMaster::new(Duration::from_millis(10));
/// let mut now = Timestamp::ZERO;
/// master.fastscan(now).unwrap();
/// let result = loop {
///     while let Some(f) = master.poll_transmit() {
///         slave.handle_frame(now, &f);
///     }
///     while let Some(f) = slave.poll_transmit() {
///         master.handle_frame(now, &f);
///     }
///     if let Some(e) = master.poll_event() {
///         break e;
///     }
///     now = master.poll_timeout().unwrap();
///     master.handle_timeout(now);
/// };
/// assert_eq!(result, LssMasterEvent::FastscanFound(address));
/// ```
#[derive(Debug, Clone)]
pub struct LssMaster {
    timeout: Duration,
    op: Op,
    timers: Timers<MasterTimer, 1>,
    tx: FrameQueue<8>,
    events: EventQueue<LssMasterEvent, 8>,
    /// [`LssMaster::fastscan_assign`]: the node-ID for the slave found.
    assign: Option<NodeId>,
    /// Switch to waiting state after the running configure node-ID succeeds.
    release: bool,
}

crate::clock::timer_kind! {
    /// The master's one timer.
    enum MasterTimer {
        /// The end of the wait for an answer (or of a fastscan step).
        Answer,
    }
}

impl LssMaster {
    /// An idle master waiting `timeout` for the answers to each step.
    #[must_use]
    pub fn new(timeout: Duration) -> Self {
        Self {
            timeout,
            op: Op::Idle,
            timers: Timers::new(),
            tx: FrameQueue::empty(),
            events: EventQueue::new(LssMasterEvent::FastscanNotFound),
            assign: None,
            release: false,
        }
    }

    /// True while a confirmed service or a fastscan runs.
    #[must_use]
    pub const fn is_busy(&self) -> bool {
        !matches!(self.op, Op::Idle)
    }

    /// Ends the running service without an event.
    pub fn cancel(&mut self) {
        self.op = Op::Idle;
        self.timers.clear();
        self.assign = None;
        self.release = false;
    }

    fn send(&mut self, request: LssRequest) {
        self.tx.push(request.to_frame());
    }

    fn start(&mut self, now: Timestamp, op: Op) -> Result<(), LssMasterError> {
        if self.is_busy() {
            return Err(LssMasterError::Busy);
        }
        self.op = op;
        self.timers
            .set(MasterTimer::Answer, Some(now.add_duration(self.timeout)));
        Ok(())
    }

    /// Switch state global (unconfirmed): every slave enters `mode`.
    pub fn switch_state_global(&mut self, now: Timestamp, mode: LssMode) {
        let _ = now;
        self.send(LssRequest::SwitchStateGlobal(mode));
    }

    /// Switch state selective: the slave with `address` enters
    /// configuration state and answers.
    pub fn switch_state_selective(
        &mut self,
        now: Timestamp,
        address: LssAddress,
    ) -> Result<(), LssMasterError> {
        self.start(now, Op::Wait(LssService::SwitchStateSelective))?;
        for field in LssField::ALL {
            self.send(LssRequest::SwitchStateSelective(field, address.get(field)));
        }
        Ok(())
    }

    /// Configure node-ID of the slave in configuration state (`None`:
    /// not configured, 255).
    pub fn configure_node_id(
        &mut self,
        now: Timestamp,
        node: Option<NodeId>,
    ) -> Result<(), LssMasterError> {
        self.start(now, Op::Wait(LssService::ConfigureNodeId))?;
        let raw = node.map_or(NODE_ID_UNCONFIGURED, NodeId::raw);
        self.send(LssRequest::ConfigureNodeId(raw));
        Ok(())
    }

    /// Configure bit timing (table selector, table index).
    pub fn configure_bit_timing(
        &mut self,
        now: Timestamp,
        table: u8,
        index: u8,
    ) -> Result<(), LssMasterError> {
        self.start(now, Op::Wait(LssService::ConfigureBitTiming))?;
        self.send(LssRequest::ConfigureBitTiming { table, index });
        Ok(())
    }

    /// Activate bit timing (unconfirmed).
    pub fn activate_bit_timing(&mut self, now: Timestamp, delay_ms: u16) {
        let _ = now;
        self.send(LssRequest::ActivateBitTiming { delay_ms });
    }

    /// Store configuration.
    pub fn store_configuration(&mut self, now: Timestamp) -> Result<(), LssMasterError> {
        self.start(now, Op::Wait(LssService::StoreConfiguration))?;
        self.send(LssRequest::StoreConfiguration);
        Ok(())
    }

    /// Inquire an address part or the node-ID.
    pub fn inquire(&mut self, now: Timestamp, what: LssInquiry) -> Result<(), LssMasterError> {
        self.start(now, Op::Wait(LssService::Inquire(what)))?;
        self.send(LssRequest::Inquire(what));
        Ok(())
    }

    /// Identify non-configured remote slave.
    pub fn identify_non_configured(&mut self, now: Timestamp) -> Result<(), LssMasterError> {
        self.start(now, Op::Wait(LssService::IdentifyNonConfigured))?;
        self.send(LssRequest::IdentifyNonConfigured);
        Ok(())
    }

    /// Starts a fastscan: finds the lowest LSS address among the
    /// non-configured slaves in waiting state, which then enters
    /// configuration state (give it a node-ID with
    /// [`configure_node_id`](Self::configure_node_id)).
    pub fn fastscan(&mut self, now: Timestamp) -> Result<(), LssMasterError> {
        self.start(
            now,
            Op::Scan(Scan {
                found: LssAddress::default(),
                sub: LssField::Vendor,
                phase: Phase::Reset,
                answered: false,
            }),
        )?;
        self.send(LssRequest::Fastscan(Fastscan {
            id_number: 0,
            bit_checked: Fastscan::RESET,
            sub: 0,
            next: 0,
        }));
        Ok(())
    }

    /// A fastscan that, when it finds a slave, gives it `node` and
    /// switches it back to waiting state (where a non-configured slave
    /// resets its communication and boots up as `node`). Events:
    /// [`LssMasterEvent::FastscanFound`] (or `FastscanNotFound`), then
    /// [`LssMasterEvent::NodeIdConfigured`] (or `NoResponse`); the switch
    /// to waiting state is sent only after a successful configure.
    pub fn fastscan_assign(&mut self, now: Timestamp, node: NodeId) -> Result<(), LssMasterError> {
        self.fastscan(now)?;
        self.assign = Some(node);
        Ok(())
    }

    fn finish(&mut self, event: LssMasterEvent) {
        self.op = Op::Idle;
        self.timers.clear();
        self.events.push(event);
        if !matches!(event, LssMasterEvent::FastscanFound(_)) {
            self.assign = None;
        }
    }

    fn response(&mut self, response: LssResponse) {
        let Op::Wait(service) = self.op else {
            if let (Op::Scan(scan), LssResponse::IdentifySlave) = (&mut self.op, response) {
                scan.answered = true;
            }
            return;
        };
        let event = match (service, response) {
            (LssService::SwitchStateSelective, LssResponse::SwitchStateSelective) => {
                LssMasterEvent::SwitchedSelective
            }
            (LssService::ConfigureNodeId, LssResponse::ConfigureNodeId(s)) => {
                if core::mem::take(&mut self.release) && s.is_ok() {
                    self.send(LssRequest::SwitchStateGlobal(LssMode::Waiting));
                }
                LssMasterEvent::NodeIdConfigured(s)
            }
            (LssService::ConfigureBitTiming, LssResponse::ConfigureBitTiming(s)) => {
                LssMasterEvent::BitTimingConfigured(s)
            }
            (LssService::StoreConfiguration, LssResponse::StoreConfiguration(s)) => {
                LssMasterEvent::Stored(s)
            }
            (LssService::Inquire(LssInquiry::Address(f)), LssResponse::Address(g, v)) if f == g => {
                LssMasterEvent::Address(f, v)
            }
            (LssService::Inquire(LssInquiry::NodeId), LssResponse::NodeId(raw)) => {
                LssMasterEvent::NodeId(NodeId::new(raw))
            }
            (LssService::IdentifyNonConfigured, LssResponse::IdentifyNonConfigured) => {
                LssMasterEvent::NonConfiguredPresent
            }
            _ => return,
        };
        self.finish(event);
    }

    /// The fastscan step after `scan`'s deadline, or its end.
    fn step(&mut self, now: Timestamp, mut scan: Scan) {
        let sub = scan.sub;
        let (bit, next) = match scan.phase {
            Phase::Reset if !scan.answered => return self.finish(LssMasterEvent::FastscanNotFound),
            Phase::Reset => (31, sub),
            Phase::Bit(b) => {
                if !scan.answered {
                    let v = scan.found.get(sub) | 1u32.checked_shl(u32::from(b)).unwrap_or(0);
                    scan.found.set(sub, v);
                }
                match b.checked_sub(1) {
                    Some(b) => (b, sub),
                    None => (
                        0,
                        LssField::from_index((sub.index() + 1) & 3).unwrap_or(sub),
                    ),
                }
            }
            Phase::Confirm if !scan.answered => {
                return self.finish(LssMasterEvent::FastscanNotFound)
            }
            Phase::Confirm => match LssField::from_index(sub.index() + 1) {
                None => {
                    self.finish(LssMasterEvent::FastscanFound(scan.found));
                    if let Some(node) = self.assign.take() {
                        self.op = Op::Wait(LssService::ConfigureNodeId);
                        self.timers
                            .set(MasterTimer::Answer, Some(now.add_duration(self.timeout)));
                        self.release = true;
                        self.send(LssRequest::ConfigureNodeId(node.raw()));
                    }
                    return;
                }
                Some(field) => {
                    scan.sub = field;
                    (31, field)
                }
            },
        };
        scan.phase = match scan.phase {
            Phase::Bit(0) => Phase::Confirm,
            _ => Phase::Bit(bit),
        };
        scan.answered = false;
        let sub = scan.sub;
        self.send(LssRequest::Fastscan(Fastscan {
            id_number: scan.found.get(sub),
            bit_checked: bit,
            sub: sub.index(),
            next: next.index(),
        }));
        self.op = Op::Scan(scan);
        self.timers
            .set(MasterTimer::Answer, Some(now.add_duration(self.timeout)));
    }
}

impl Machine for LssMaster {
    type Event = LssMasterEvent;

    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        if let Some(response) = LssResponse::of_frame(frame) {
            self.response(response);
        }
    }

    fn handle_timeout(&mut self, now: Timestamp) {
        if !self.timers.expire(MasterTimer::Answer, now) {
            return;
        }
        match self.op {
            Op::Idle => {}
            Op::Wait(service) => {
                self.release = false;
                self.finish(LssMasterEvent::NoResponse(service));
            }
            Op::Scan(scan) => self.step(now, scan),
        }
    }

    crate::machine::queued_outputs!(timers: timers, frames: tx, events: events);
}
