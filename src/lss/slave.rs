//! The LSS slave (CiA 305, "Layer setting services and protocol", sections
//! 3 "LSS modes and states" and 4 "LSS protocol descriptions").
//!
//! A slave is in LSS waiting state or LSS configuration state. It enters
//! configuration state by switch state global, by switch state selective
//! with its own 128-bit LSS address, or at the end of a fastscan that
//! found it. Only in configuration state does it configure its node-ID and
//! bit timing, store its configuration and answer inquiries. A configured
//! node-ID is *pending*: it becomes active at the next NMT reset
//! communication ([`LssSlave::reset_communication`]). A slave whose active
//! node-ID is "not configured" (255) cannot be reset by NMT, so when it is
//! switched back to waiting state with a pending node-ID it asks for a reset
//! communication itself ([`LssSlaveEvent::ResetCommunication`]).

use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::queue::{EventQueue, FrameQueue};

use super::wire::{
    Fastscan, IdentifyPart, LssAddress, LssErrorCode, LssField, LssInquiry, LssMode, LssRequest,
    LssResponse, LssStatus,
};

/// The node-ID byte that means "not configured" (CiA 305 section 3.3).
pub const NODE_ID_UNCONFIGURED: u8 = 0xFF;

/// The LSS state of a slave.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssState {
    /// LSS waiting state (the state after power-on).
    Waiting,
    /// LSS configuration state.
    Configuration,
}

/// What an [`LssSlave`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LssSlaveEvent {
    /// The LSS state changed.
    StateChanged(LssState),
    /// Configure node-ID succeeded: the pending node-ID (`None`: not
    /// configured), active at the next reset communication.
    NodeIdConfigured(Option<NodeId>),
    /// Configure bit timing succeeded (standard table index).
    BitTimingConfigured {
        /// Table selector.
        table: u8,
        /// Table index.
        index: u8,
    },
    /// Activate bit timing: switch to the configured bit timing after
    /// `delay_ms`, then stay silent for another `delay_ms`.
    ActivateBitTiming {
        /// The switch delay in milliseconds.
        delay_ms: u16,
    },
    /// Store configuration was asked for: the application stores the
    /// pending node-ID and bit timing and answers with
    /// [`LssSlave::answer_store`].
    StoreRequested {
        /// The pending node-ID to store (`None`: not configured).
        node_id: Option<NodeId>,
        /// The pending bit timing (table, index), if one was configured.
        bit_timing: Option<(u8, u8)>,
    },
    /// A not-configured slave was given a node-ID and switched to waiting
    /// state: perform an NMT reset communication (which calls
    /// [`LssSlave::reset_communication`]) so it boots under that node-ID.
    ResetCommunication,
}

/// How an [`LssSlave`] starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct LssSlaveConfig {
    /// The slave's LSS address (its 1018h identity).
    pub address: LssAddress,
    /// The node-ID it starts with (`None`: not configured, 255).
    pub node_id: Option<NodeId>,
    /// Whether store configuration is supported (if not, the slave answers
    /// error 1 itself).
    pub store_supported: bool,
    /// Whether configure bit timing with the standard table (selector 0,
    /// index 0..=8) is accepted (if not, error 1).
    pub bit_timing_supported: bool,
}

impl LssSlaveConfig {
    /// A slave with `address` and `node_id` that supports store
    /// configuration but not bit timing changes.
    #[must_use]
    pub const fn new(address: LssAddress, node_id: Option<NodeId>) -> Self {
        Self {
            address,
            node_id,
            store_supported: true,
            bit_timing_supported: false,
        }
    }
}

/// An LSS slave. Implements [`Machine`]: feed every frame, then drain
/// `poll_transmit` (answers on 7E4h) and `poll_event`. It has no timers.
///
/// ```
/// use canopen_codec::lss::{LssAddress, LssSlave, LssSlaveConfig, LssSlaveEvent, LssState};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// let address = LssAddress { vendor: 0x29A, product: 1, revision: 2, serial: 3 };
/// let mut slave = LssSlave::new(LssSlaveConfig::new(address, None));
/// let t = Timestamp::ZERO;
/// let f = |d: &[u8]| CanFrame::standard(0x7E5, d).unwrap();
/// slave.handle_frame(t, &f(&[0x04, 1, 0, 0, 0, 0, 0, 0])); // switch state global: configuration
/// slave.handle_frame(t, &f(&[0x11, 5, 0, 0, 0, 0, 0, 0])); // configure node-ID 5
/// assert_eq!(slave.poll_transmit().unwrap().to_string(), "7E4#1100000000000000");
/// slave.handle_frame(t, &f(&[0x04, 0, 0, 0, 0, 0, 0, 0])); // back to waiting
/// assert_eq!(slave.poll_event(), Some(LssSlaveEvent::StateChanged(LssState::Configuration)));
/// assert_eq!(slave.poll_event(), Some(LssSlaveEvent::NodeIdConfigured(NodeId::new(5))));
/// assert_eq!(slave.poll_event(), Some(LssSlaveEvent::StateChanged(LssState::Waiting)));
/// assert_eq!(slave.poll_event(), Some(LssSlaveEvent::ResetCommunication));
/// assert_eq!(slave.reset_communication(), NodeId::new(5));
/// ```
#[derive(Debug, Clone)]
pub struct LssSlave {
    config: LssSlaveConfig,
    state: LssState,
    active: Option<NodeId>,
    pending: Option<NodeId>,
    bit_timing: Option<(u8, u8)>,
    /// Switch state selective: how many address parts matched in order.
    selective: u8,
    /// Identify remote slave: how many range parts matched in order.
    identify: u8,
    /// Fastscan: the address part compared next (`None` before a reset).
    scan_pos: Option<u8>,
    store_outstanding: bool,
    tx: FrameQueue<4>,
    events: EventQueue<LssSlaveEvent, 8>,
}

impl LssSlave {
    /// A slave in waiting state.
    #[must_use]
    pub fn new(config: LssSlaveConfig) -> Self {
        Self {
            config,
            state: LssState::Waiting,
            active: config.node_id,
            pending: config.node_id,
            bit_timing: None,
            selective: 0,
            identify: 0,
            scan_pos: None,
            store_outstanding: false,
            tx: FrameQueue::empty(),
            events: EventQueue::new(LssSlaveEvent::ResetCommunication),
        }
    }

    /// The LSS state.
    #[must_use]
    pub const fn state(&self) -> LssState {
        self.state
    }

    /// The active node-ID (`None`: not configured).
    #[must_use]
    pub const fn node_id(&self) -> Option<NodeId> {
        self.active
    }

    /// The pending node-ID, active after the next reset communication.
    #[must_use]
    pub const fn pending_node_id(&self) -> Option<NodeId> {
        self.pending
    }

    /// The LSS address.
    #[must_use]
    pub const fn address(&self) -> LssAddress {
        self.config.address
    }

    /// NMT reset communication: the pending node-ID becomes active. Returns
    /// the active node-ID.
    pub fn reset_communication(&mut self) -> Option<NodeId> {
        self.active = self.pending;
        self.active
    }

    /// At power-on, the configuration an earlier store configuration
    /// saved (CiA 305): `node_id` becomes the active and pending node-ID,
    /// `bit_timing` the pending bit timing.
    pub fn load_stored(&mut self, node_id: Option<NodeId>, bit_timing: Option<(u8, u8)>) {
        self.active = node_id;
        self.pending = node_id;
        self.bit_timing = bit_timing;
    }

    /// Answers an outstanding [`LssSlaveEvent::StoreRequested`]; returns
    /// false (and sends nothing) when no store is outstanding.
    pub fn answer_store(&mut self, status: LssStatus) -> bool {
        if !core::mem::take(&mut self.store_outstanding) {
            return false;
        }
        self.send(LssResponse::StoreConfiguration(status));
        true
    }

    fn send(&mut self, response: LssResponse) {
        self.tx.push(response.to_frame());
    }

    fn enter(&mut self, state: LssState) {
        self.selective = 0;
        self.scan_pos = None;
        if self.state != state {
            self.state = state;
            self.events.push(LssSlaveEvent::StateChanged(state));
        }
    }

    /// Neither an active nor a pending node-ID: the slave takes part in
    /// fastscan and answers identify non-configured remote slave.
    fn unconfigured(&self) -> bool {
        self.active.is_none() && self.pending.is_none()
    }

    fn request(&mut self, request: LssRequest) {
        let configuring = self.state == LssState::Configuration;
        match request {
            LssRequest::SwitchStateGlobal(LssMode::Configuration) => {
                self.enter(LssState::Configuration);
            }
            LssRequest::SwitchStateGlobal(LssMode::Waiting) => {
                let was = self.state;
                self.enter(LssState::Waiting);
                if was == LssState::Configuration && self.active.is_none() && self.pending.is_some()
                {
                    self.events.push(LssSlaveEvent::ResetCommunication);
                }
            }
            LssRequest::SwitchStateSelective(field, value) if !configuring => {
                self.selective(field, value);
            }
            LssRequest::ConfigureNodeId(raw) if configuring => {
                let status = match (raw, NodeId::new(raw)) {
                    (_, Some(id)) => Some(Some(id)),
                    (NODE_ID_UNCONFIGURED, None) => Some(None),
                    _ => None,
                };
                if let Some(node) = status {
                    self.pending = node;
                    self.events.push(LssSlaveEvent::NodeIdConfigured(node));
                    self.send(LssResponse::ConfigureNodeId(LssStatus::OK));
                } else {
                    let refused = LssStatus::new(LssErrorCode::Refused);
                    self.send(LssResponse::ConfigureNodeId(refused));
                }
            }
            LssRequest::ConfigureBitTiming { table, index } if configuring => {
                if self.config.bit_timing_supported && table == 0 && index <= 8 {
                    self.bit_timing = Some((table, index));
                    self.events
                        .push(LssSlaveEvent::BitTimingConfigured { table, index });
                    self.send(LssResponse::ConfigureBitTiming(LssStatus::OK));
                } else {
                    let refused = LssStatus::new(LssErrorCode::Refused);
                    self.send(LssResponse::ConfigureBitTiming(refused));
                }
            }
            LssRequest::ActivateBitTiming { delay_ms } if configuring => {
                self.events
                    .push(LssSlaveEvent::ActivateBitTiming { delay_ms });
            }
            LssRequest::StoreConfiguration if configuring => {
                if self.config.store_supported {
                    self.store_outstanding = true;
                    self.events.push(LssSlaveEvent::StoreRequested {
                        node_id: self.pending,
                        bit_timing: self.bit_timing,
                    });
                } else {
                    let refused = LssStatus::new(LssErrorCode::Refused);
                    self.send(LssResponse::StoreConfiguration(refused));
                }
            }
            LssRequest::Inquire(LssInquiry::Address(field)) if configuring => {
                self.send(LssResponse::Address(field, self.config.address.get(field)));
            }
            LssRequest::Inquire(LssInquiry::NodeId) if configuring => {
                let raw = self.active.map_or(NODE_ID_UNCONFIGURED, NodeId::raw);
                self.send(LssResponse::NodeId(raw));
            }
            LssRequest::IdentifyRemoteSlave(part, value) => self.identify(part, value),
            LssRequest::IdentifyNonConfigured if self.unconfigured() => {
                self.send(LssResponse::IdentifyNonConfigured);
            }
            LssRequest::Fastscan(scan) if !configuring && self.unconfigured() => {
                self.fastscan(scan);
            }
            _ => {}
        }
    }

    /// Switch state selective: the four parts in order, each equal.
    fn selective(&mut self, field: LssField, value: u32) {
        let matches = self.config.address.get(field) == value;
        let expected = field.index() == self.selective || field == LssField::Vendor;
        self.selective = if matches && expected {
            field.index() + 1
        } else {
            0
        };
        if self.selective == 4 {
            self.enter(LssState::Configuration);
            self.send(LssResponse::SwitchStateSelective);
        }
    }

    /// Identify remote slave: vendor and product equal, revision and serial
    /// within the ranges, the six parts in order.
    fn identify(&mut self, part: IdentifyPart, value: u32) {
        let a = self.config.address;
        let (position, ok) = match part {
            IdentifyPart::Vendor => (0, a.vendor == value),
            IdentifyPart::Product => (1, a.product == value),
            IdentifyPart::RevisionLow => (2, a.revision >= value),
            IdentifyPart::RevisionHigh => (3, a.revision <= value),
            IdentifyPart::SerialLow => (4, a.serial >= value),
            IdentifyPart::SerialHigh => (5, a.serial <= value),
        };
        let expected = position == self.identify || position == 0;
        self.identify = if ok && expected { position + 1 } else { 0 };
        if self.identify == 6 {
            self.identify = 0;
            self.send(LssResponse::IdentifySlave);
        }
    }

    /// One fastscan step (CiA 305 "LSS fastscan"): BitChecked 80h resets
    /// the search; otherwise the slave answers when the bits `bit_checked..=31`
    /// of its address part `sub` equal those of `id_number`, and moves to
    /// part `next` when all 32 bits were compared. Out-of-range values
    /// (BitChecked 32..=127 or above 80h, LSSSub or LSSNext above 3) are
    /// ignored.
    fn fastscan(&mut self, scan: Fastscan) {
        if scan.bit_checked == Fastscan::RESET {
            self.scan_pos = Some(0);
            self.send(LssResponse::IdentifySlave);
            return;
        }
        let (Some(field), Some(_)) = (
            LssField::from_index(scan.sub),
            LssField::from_index(scan.next),
        ) else {
            return;
        };
        if self.scan_pos != Some(scan.sub) {
            return;
        }
        let Some(mask) = u32::MAX.checked_shl(u32::from(scan.bit_checked)) else {
            return;
        };
        if (self.config.address.get(field) ^ scan.id_number) & mask != 0 {
            return;
        }
        self.send(LssResponse::IdentifySlave);
        if scan.bit_checked == 0 {
            if scan.next < scan.sub {
                self.enter(LssState::Configuration);
            } else {
                self.scan_pos = Some(scan.next);
            }
        }
    }
}

impl Machine for LssSlave {
    type Event = LssSlaveEvent;

    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        if let Some(request) = LssRequest::of_frame(frame) {
            self.request(request);
        }
    }

    fn handle_timeout(&mut self, _now: Timestamp) {}

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    crate::machine::queued_outputs!(frames: tx, events: events);
}
