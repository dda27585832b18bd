//! The NMT wire layer, CiA 301 section 7.2.8.3 (NMT services and
//! protocols): the one place where the bytes of NMT module-control frames
//! (identifier 000h) and NMT error-control frames (700h + node: heartbeat,
//! boot-up, node-guarding reply; the node-guarding request is a remote
//! frame) are read and written.
//!
//! - [`NmtFrame`] / [`NmtCommand`]: 2 bytes, byte 0 the command specifier,
//!   byte 1 the node addressed (0: all).
//! - [`HeartbeatFrame`] / [`Heartbeat`]: 1 byte, bit 7 the node-guarding
//!   toggle (0 in heartbeats and the boot-up message), bits 6..=0 the NMT
//!   state.
//! - [`guard_request`]: the node-guarding request (CiA 301 section
//!   7.2.8.3.2.1 "Node guarding protocol"), a remote frame with DLC 1.
//!
//! Unknown command and state values decode to `Unknown(raw)`, never an
//! error: every frame of the right length parses and emits back to itself.

use core::fmt;

use crate::cob_id::{NodeId, NMT, NMT_ERROR_CONTROL_BASE};
use crate::error::DecodeError;
use crate::frame::{CanFrame, CanId};
use crate::nmt::NmtState;
use crate::wire::{fixed, fixed_view, parse_through_view, Codec};

/// NMT command specifier (byte 0 of an NMT frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtCommandSpecifier {
    /// 01h: start remote node (enter operational).
    Start,
    /// 02h: stop remote node (enter stopped).
    Stop,
    /// 80h: enter pre-operational.
    EnterPreOperational,
    /// 81h: reset node.
    ResetNode,
    /// 82h: reset communication.
    ResetCommunication,
    /// Any other byte, kept.
    Unknown(u8),
}

impl From<u8> for NmtCommandSpecifier {
    fn from(raw: u8) -> Self {
        match raw {
            0x01 => Self::Start,
            0x02 => Self::Stop,
            0x80 => Self::EnterPreOperational,
            0x81 => Self::ResetNode,
            0x82 => Self::ResetCommunication,
            other => Self::Unknown(other),
        }
    }
}

impl From<NmtCommandSpecifier> for u8 {
    fn from(cs: NmtCommandSpecifier) -> u8 {
        match cs {
            NmtCommandSpecifier::Start => 0x01,
            NmtCommandSpecifier::Stop => 0x02,
            NmtCommandSpecifier::EnterPreOperational => 0x80,
            NmtCommandSpecifier::ResetNode => 0x81,
            NmtCommandSpecifier::ResetCommunication => 0x82,
            NmtCommandSpecifier::Unknown(raw) => raw,
        }
    }
}

impl fmt::Display for NmtCommandSpecifier {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Start => f.write_str("start"),
            Self::Stop => f.write_str("stop"),
            Self::EnterPreOperational => f.write_str("enter pre-operational"),
            Self::ResetNode => f.write_str("reset node"),
            Self::ResetCommunication => f.write_str("reset communication"),
            Self::Unknown(raw) => write!(f, "unknown command {raw:02X}h"),
        }
    }
}

/// The node(s) an NMT command addresses (byte 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NmtTarget {
    /// 0: every node.
    All,
    /// 1..=127: one node.
    Node(NodeId),
    /// 128..=255: not a node id; kept so the frame round-trips.
    Invalid(u8),
}

impl From<u8> for NmtTarget {
    fn from(raw: u8) -> Self {
        match (raw, NodeId::new(raw)) {
            (0, _) => NmtTarget::All,
            (_, Some(n)) => NmtTarget::Node(n),
            (other, None) => NmtTarget::Invalid(other),
        }
    }
}

impl From<NmtTarget> for u8 {
    fn from(t: NmtTarget) -> u8 {
        match t {
            NmtTarget::All => 0,
            NmtTarget::Node(n) => n.raw(),
            NmtTarget::Invalid(raw) => raw,
        }
    }
}

impl NmtTarget {
    /// True if a node with id `node` must obey a command with this target.
    #[must_use]
    pub fn addresses(self, node: NodeId) -> bool {
        match self {
            NmtTarget::All => true,
            NmtTarget::Node(n) => n == node,
            NmtTarget::Invalid(_) => false,
        }
    }
}

fixed_view! {
    /// The checked view of an NMT module-control frame's data: exactly 2
    /// bytes.
    ///
    /// ```
    /// use canopen_codec::nmt::NmtFrame;
    /// let f = NmtFrame::new_checked(&[0x01, 0x0A]).unwrap();
    /// assert_eq!((f.command(), f.target()), (0x01, 0x0A));
    /// assert!(NmtFrame::new_checked(&[0x01]).is_err());
    /// ```
    NmtFrame, 2
}

impl NmtFrame {
    /// Byte 0: the command specifier.
    #[must_use]
    #[inline]
    pub const fn command(&self) -> u8 {
        let [cs, _] = self.bytes;
        cs
    }

    /// Byte 1: the node-ID addressed (0: all nodes).
    #[must_use]
    #[inline]
    pub const fn target(&self) -> u8 {
        let [_, node] = self.bytes;
        node
    }
}

/// An NMT module-control command (CiA 301 section 7.2.8.3.1 "NMT module
/// control protocols").
///
/// ```
/// use canopen_codec::nmt::{NmtCommand, NmtCommandSpecifier, NmtTarget};
/// use canopen_codec::wire::Codec;
/// use canopen_codec::NodeId;
/// // The real capture's `000#010A`: start node 10.
/// let cmd = NmtCommand::parse(&[0x01, 0x0A]).unwrap();
/// assert_eq!(cmd.command, NmtCommandSpecifier::Start);
/// assert_eq!(cmd.target, NmtTarget::Node(NodeId::new(10).unwrap()));
/// let mut buf = [0; 8];
/// assert_eq!(cmd.emit(&mut buf), 2);
/// assert_eq!(buf[..2], [0x01, 0x0A]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NmtCommand {
    /// What to do.
    pub command: NmtCommandSpecifier,
    /// Who does it.
    pub target: NmtTarget,
}

impl NmtCommand {
    /// The data length of every NMT module-control frame.
    pub const LEN: usize = 2;

    /// The command a checked frame carries.
    #[must_use]
    #[inline]
    pub fn from_view(frame: &NmtFrame) -> Self {
        NmtCommand {
            command: frame.command().into(),
            target: frame.target().into(),
        }
    }

    /// `command` addressed to `target`.
    #[must_use]
    pub const fn new(command: NmtCommandSpecifier, target: NmtTarget) -> Self {
        NmtCommand { command, target }
    }

    /// The frame on 000h (CiA 301 section 7.3.3 "Pre-defined connection
    /// set") that carries this command.
    #[must_use]
    #[inline]
    pub fn to_frame(&self) -> CanFrame {
        self.to_frame_on(CanId::Standard(NMT))
    }
}

impl Codec for NmtCommand {
    parse_through_view!(NmtFrame);

    #[inline]
    fn emit(&self, buf: &mut [u8; 8]) -> usize {
        let [cs, node, ..] = buf;
        *cs = self.command.into();
        *node = self.target.into();
        Self::LEN
    }
}

/// The checked view of an NMT error-control frame's data (heartbeat,
/// boot-up, node-guarding reply): exactly 1 byte.
///
/// ```
/// use canopen_codec::nmt::HeartbeatFrame;
/// let f = HeartbeatFrame::new_checked(&[0x85]).unwrap();
/// assert_eq!((f.state_bits(), f.toggle()), (0x05, true));
/// assert!(HeartbeatFrame::new_checked(&[0x05, 0]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct HeartbeatFrame {
    byte: u8,
}

impl HeartbeatFrame {
    /// The view of `data`: [`DecodeError::Truncated`] when empty,
    /// [`DecodeError::TooLong`] above 1 byte.
    #[inline]
    pub fn new_checked(data: &[u8]) -> Result<Self, DecodeError> {
        let [byte] = *fixed::<1>(data)?;
        Ok(HeartbeatFrame { byte })
    }

    /// The view of a data frame's bytes straight from its padded buffer
    /// (the hot path: no slice), the same checks as
    /// [`new_checked`](Self::new_checked); a remote frame is
    /// [`DecodeError::UnexpectedRemote`].
    #[inline]
    pub fn of_frame(frame: &CanFrame) -> Result<Self, DecodeError> {
        if frame.is_remote() {
            return Err(DecodeError::UnexpectedRemote);
        }
        let [byte, ..] = frame.padded_data();
        match frame.dlc() {
            1 => Ok(HeartbeatFrame { byte }),
            got => Err(Self::length_error(got)),
        }
    }

    /// The error of a frame that is not 1 byte long (out of line: one
    /// compare on the decode path).
    #[cold]
    fn length_error(got: u8) -> DecodeError {
        match got {
            0 => DecodeError::Truncated { need: 1, got: 0 },
            got => DecodeError::TooLong {
                max: 1,
                got: usize::from(got),
            },
        }
    }

    /// The view of the one data byte `byte` (every byte is a valid
    /// error-control frame).
    #[must_use]
    #[inline]
    pub const fn from_byte(byte: u8) -> Self {
        HeartbeatFrame { byte }
    }

    /// The data byte.
    #[must_use]
    #[inline]
    pub const fn byte(&self) -> u8 {
        self.byte
    }

    /// Bits 6..=0: the NMT state.
    #[must_use]
    #[inline]
    pub const fn state_bits(&self) -> u8 {
        self.byte & 0x7F
    }

    /// Bit 7: the node-guarding toggle.
    #[must_use]
    #[inline]
    pub const fn toggle(&self) -> bool {
        self.byte & 0x80 != 0
    }
}

/// A heartbeat, boot-up or node-guarding reply (the 1-byte frame on
/// 0x700 + node; CiA 301 section 7.2.8.3.2 "NMT error control
/// protocols"). The wire cannot tell a heartbeat from a guarding reply
/// except by the toggle bit, which heartbeats keep at 0.
///
/// ```
/// use canopen_codec::nmt::{Heartbeat, NmtState};
/// use canopen_codec::wire::Codec;
/// assert_eq!(Heartbeat::parse(&[0x7F]).unwrap().state, NmtState::PreOperational);
/// let reply = Heartbeat::parse(&[0x85]).unwrap(); // guarding reply, toggle set
/// assert!(reply.toggle);
/// assert_eq!(reply.state, NmtState::Operational);
/// assert_eq!(reply.byte(), 0x85);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Heartbeat {
    /// The producer's NMT state.
    pub state: NmtState,
    /// Bit 7: the node-guarding toggle (always false in heartbeats).
    pub toggle: bool,
}

impl Heartbeat {
    /// A heartbeat (toggle clear) reporting `state`.
    #[must_use]
    pub const fn new(state: NmtState) -> Self {
        Heartbeat {
            state,
            toggle: false,
        }
    }

    /// The boot-up message.
    pub const BOOT_UP: Heartbeat = Heartbeat::new(NmtState::BootUp);

    /// True for the boot-up message (state 0).
    #[must_use]
    pub const fn is_boot_up(&self) -> bool {
        matches!(self.state, NmtState::BootUp)
    }

    /// The heartbeat a checked frame carries.
    #[must_use]
    #[inline]
    pub const fn from_view(frame: &HeartbeatFrame) -> Self {
        Heartbeat {
            state: NmtState::from_bits(frame.state_bits()),
            toggle: frame.toggle(),
        }
    }

    /// The data byte.
    #[must_use]
    #[inline]
    pub const fn byte(&self) -> u8 {
        self.state.bits() | if self.toggle { 0x80 } else { 0 }
    }

    /// The frame on 700h + `node` that carries this heartbeat.
    #[must_use]
    #[inline]
    pub fn to_frame(&self, node: NodeId) -> CanFrame {
        self.to_frame_on(error_control_id(node))
    }
}

impl Codec for Heartbeat {
    parse_through_view!(HeartbeatFrame, of_frame);

    #[inline]
    fn emit(&self, buf: &mut [u8; 8]) -> usize {
        let [b0, ..] = buf;
        *b0 = self.byte();
        1
    }
}

/// The NMT error-control identifier of `node`: 700h + node.
#[must_use]
#[inline]
pub const fn error_control_id(node: NodeId) -> CanId {
    CanId::Standard(NMT_ERROR_CONTROL_BASE + node.raw() as u16)
}

/// The node-guarding request to `node`: a remote frame on 700h + node with
/// DLC 1, the length of the reply it asks for (CiA 301 section 7.2.8.3.2.1
/// "Node guarding protocol").
///
/// ```
/// use canopen_codec::nmt::guard_request;
/// use canopen_codec::NodeId;
/// let f = guard_request(NodeId::new(10).unwrap());
/// assert_eq!(f.to_string(), "70A#R1");
/// ```
#[must_use]
#[inline]
pub fn guard_request(node: NodeId) -> CanFrame {
    let id = error_control_id(node);
    CanFrame::remote(id, 1).unwrap_or(CanFrame::from_parts(id, [0; 8], 0))
}

/// True when `frame` is a node-guarding request to `node`: a remote frame
/// on 700h + node (any DLC: CiA 301 asks for 1, other lengths are kept
/// as received and answered alike).
#[must_use]
#[inline]
pub fn is_guard_request(frame: &CanFrame, node: NodeId) -> bool {
    frame.is_remote() && frame.id() == error_control_id(node)
}

#[cfg(test)]
mod tests;
