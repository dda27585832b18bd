//! The hot entry point: [`Message::decode`] classifies any frame under the
//! CiA 301 predefined connection set and decodes it into a typed message.
//!
//! Decoding copies what it needs out of the frame (at most 8 bytes) and
//! borrows nothing, so a [`Message`] is `Copy` and outlives its frame. It never
//! allocates and never panics. Every message that decodes encodes back to the
//! identical frame ([`Message::encode`]).
//!
//! A [`Message`] is the enum of the protocols' wire representations (the
//! [`Codec`] types of [`crate::wire`]): decoding classifies the identifier
//! and calls that representation's `parse`, encoding calls its `emit`. No
//! byte of a frame is read or written here.

use crate::bytes::Payload;
use crate::cob_id::{
    classify, function_of, CobKind, Function, NodeId, PdoNumber, NMT_ERROR_CONTROL_BASE,
};
use crate::emcy::Emergency;
use crate::error::DecodeError;
use crate::frame::{CanFrame, CanId};
use crate::lss::LssMessage;
use crate::nmt::{Heartbeat, NmtCommand};
use crate::sdo::{SdoFrame, SdoRequest, SdoResponse};
use crate::sync::SyncMessage;
use crate::time::TimeOfDay;
use crate::wire::Codec;

pub mod display;
pub mod lenient;
pub use lenient::Deviation;

/// One decoded CANopen frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Message {
    /// 0x000: NMT module control.
    Nmt(NmtCommand),
    /// 0x080: SYNC.
    Sync(SyncMessage),
    /// 0x080 + node: emergency.
    Emcy {
        /// The producer.
        node: NodeId,
        /// The emergency.
        emcy: Emergency,
    },
    /// 0x100: TIME stamp.
    Time(TimeOfDay),
    /// A transmit PDO of `node` (raw payload; mapping-aware decoding is separate).
    Tpdo {
        /// PDO number (0-based).
        pdo: PdoNumber,
        /// The producer.
        node: NodeId,
        /// 0..=8 payload bytes.
        payload: Payload,
    },
    /// A remote frame on a TPDO identifier: asks `node` to send that TPDO.
    TpdoRequest {
        /// PDO number (0-based).
        pdo: PdoNumber,
        /// The producer asked.
        node: NodeId,
        /// The requested data length.
        dlc: u8,
    },
    /// A receive PDO of `node` (raw payload).
    Rpdo {
        /// PDO number (0-based).
        pdo: PdoNumber,
        /// The consumer.
        node: NodeId,
        /// 0..=8 payload bytes.
        payload: Payload,
    },
    /// 0x600 + node: SDO request to the server `node`.
    SdoRequest {
        /// The server addressed.
        node: NodeId,
        /// The request.
        sdo: SdoRequest,
    },
    /// 0x580 + node: SDO response from the server `node`.
    SdoResponse {
        /// The responding server.
        node: NodeId,
        /// The response.
        sdo: SdoResponse,
    },
    /// 0x700 + node, data: heartbeat, boot-up or node-guarding reply.
    Heartbeat {
        /// The producer.
        node: NodeId,
        /// State and toggle.
        heartbeat: Heartbeat,
    },
    /// 0x700 + node, remote frame: node-guarding request.
    NodeGuardRequest {
        /// The node guarded.
        node: NodeId,
        /// The requested data length (1 by CiA 301; kept as received).
        dlc: u8,
    },
    /// 0x7E4 / 0x7E5: layer setting services (CiA 305), typed; the
    /// direction is the variant of [`LssMessage`].
    Lss(LssMessage),
    /// Outside the predefined connection set (including every 29-bit frame),
    /// or a remote frame on an unassigned identifier: the frame itself.
    Unknown(CanFrame),
}

/// The SDO decoders of one direction, the same for requests and
/// responses: `$frame` reads a frame whose identifier is known to be SDO,
/// a transfer's segments (nearly every SDO frame) built straight into the
/// result and the other commands by `$view` (`from_view`), out of line.
macro_rules! sdo_decoders {
    ($($(#[$doc:meta])* $frame:ident, $view:ident: $sdo:ident;)*) => {$(
        $(#[$doc])*
        #[inline(never)]
        fn $frame(frame: &CanFrame, node: NodeId) -> Result<Message, DecodeError> {
            let sdo = SdoFrame::of_frame(frame)?;
            if $sdo::is_segment(&sdo) {
                return Ok(Message::$sdo {
                    node,
                    sdo: $sdo::segment(sdo),
                });
            }
            Self::$view(node, sdo)
        }

        $(#[$doc])*
        #[inline(never)]
        fn $view(node: NodeId, sdo: SdoFrame) -> Result<Message, DecodeError> {
            Ok(Message::$sdo {
                node,
                sdo: $sdo::from_view(sdo)?,
            })
        }
    )*};
}

impl Message {
    /// Classifies and decodes one frame.
    ///
    /// Fails with a [`DecodeError`] when the identifier names a known object
    /// but the frame does not fit it (wrong length, or a remote frame where
    /// only data frames exist). Use [`classify`] on the frame's id to learn
    /// what it was meant to be.
    ///
    /// ```
    /// use canopen_codec::{CanFrame, Message, NodeId};
    /// use canopen_codec::nmt::NmtState;
    /// let f = CanFrame::standard(0x701, &[0x05]).unwrap();
    /// match Message::decode(&f).unwrap() {
    ///     Message::Heartbeat { node, heartbeat } => {
    ///         assert_eq!(node, NodeId::new(1).unwrap());
    ///         assert_eq!(heartbeat.state, NmtState::Operational);
    ///     }
    ///     other => panic!("{other:?}"),
    /// }
    /// ```
    #[inline(always)]
    pub fn decode(frame: &CanFrame) -> Result<Message, DecodeError> {
        // The objects of a node (heartbeats, PDOs, EMCY, SDO) are nearly
        // all of a bus's traffic: an 11-bit data frame with a node in its
        // identifier decodes straight from the function code. Everything
        // else goes through the full classification; both agree on every
        // frame (the `decode_agrees_with_the_classification` property).
        let Some(raw) = frame.standard_data_id() else {
            return Self::decode_classified(frame);
        };
        let Some(node) = NodeId::new((raw & 0x7F) as u8) else {
            return Self::decode_classified(frame);
        };
        // In the order of a bus's traffic: a mixed stream predicts these
        // tests better than one jump on the function. The heartbeat test
        // is on the identifier's bits, not on the function, so that the
        // compiler keeps it a test of its own (on the function it folds it
        // into the jump on the function that follows).
        if raw & 0x780 == NMT_ERROR_CONTROL_BASE {
            return Ok(Message::Heartbeat {
                node,
                heartbeat: Heartbeat::parse_frame(frame)?,
            });
        }
        let function = function_of(raw);
        if let Function::Tpdo(pdo) = function {
            let payload = Payload::parse_frame(frame)?;
            return Ok(Message::Tpdo { pdo, node, payload });
        }
        if let Function::Rpdo(pdo) = function {
            let payload = Payload::parse_frame(frame)?;
            return Ok(Message::Rpdo { pdo, node, payload });
        }
        match function {
            // Out of line and handed the frame itself (a tail call: this
            // function keeps no stack frame for them).
            Function::SdoTx => Self::decode_sdo_response_frame(frame, node),
            Function::SdoRx => Self::decode_sdo_request_frame(frame, node),
            Function::SyncOrEmcy => Ok(Message::Emcy {
                node,
                emcy: Emergency::parse_frame(frame)?,
            }),
            _ => Self::decode_classified(frame),
        }
    }

    /// [`Message::decode`] by [`classify`] alone: what the identifier
    /// names under the predefined connection set, then that object's
    /// decoder.
    #[inline(never)]
    pub(crate) fn decode_classified(frame: &CanFrame) -> Result<Message, DecodeError> {
        let kind = classify(frame.id());
        if frame.is_remote() {
            return Self::decode_remote(kind, frame);
        }
        let data = frame.data();
        Ok(match kind {
            CobKind::NmtErrorControl(node) => Message::Heartbeat {
                node,
                heartbeat: Heartbeat::parse(data)?,
            },
            CobKind::Tpdo(pdo, node) => Message::Tpdo {
                pdo,
                node,
                payload: Payload::parse(data)?,
            },
            CobKind::Rpdo(pdo, node) => Message::Rpdo {
                pdo,
                node,
                payload: Payload::parse(data)?,
            },
            CobKind::SdoRx(node) => {
                return Self::decode_sdo_request(node, SdoFrame::of_frame(frame)?)
            }
            CobKind::SdoTx(node) => {
                return Self::decode_sdo_response(node, SdoFrame::of_frame(frame)?)
            }
            CobKind::Emcy(node) => Message::Emcy {
                node,
                emcy: Emergency::parse(data)?,
            },
            CobKind::Nmt => Message::Nmt(NmtCommand::parse(data)?),
            CobKind::Sync => Message::Sync(SyncMessage::parse(data)?),
            CobKind::Time => Message::Time(TimeOfDay::parse(data)?),
            CobKind::Lss(direction) => Message::Lss(LssMessage::parse(direction, data)?),
            CobKind::Unknown => Message::Unknown(*frame),
        })
    }

    sdo_decoders! {
        /// 580h + node: an SDO response.
        decode_sdo_response_frame, decode_sdo_response: SdoResponse;
        /// 600h + node: an SDO request.
        decode_sdo_request_frame, decode_sdo_request: SdoRequest;
    }

    /// A remote frame: only a TPDO request and a node-guarding request
    /// exist as remote frames in the predefined connection set (CiA 301
    /// section 7.3.3 "Pre-defined connection set"); on an unassigned
    /// identifier the frame is kept as it came.
    fn decode_remote(kind: CobKind, frame: &CanFrame) -> Result<Message, DecodeError> {
        match kind {
            CobKind::Tpdo(pdo, node) => Ok(Message::TpdoRequest {
                pdo,
                node,
                dlc: frame.dlc(),
            }),
            CobKind::NmtErrorControl(node) => Ok(Message::NodeGuardRequest {
                node,
                dlc: frame.dlc(),
            }),
            CobKind::Unknown => Ok(Message::Unknown(*frame)),
            _ => Err(DecodeError::UnexpectedRemote),
        }
    }

    /// What kind of object this message is.
    #[must_use]
    #[inline]
    pub fn kind(&self) -> CobKind {
        match *self {
            Message::Nmt(_) => CobKind::Nmt,
            Message::Sync(_) => CobKind::Sync,
            Message::Emcy { node, .. } => CobKind::Emcy(node),
            Message::Time(_) => CobKind::Time,
            Message::Tpdo { pdo, node, .. } | Message::TpdoRequest { pdo, node, .. } => {
                CobKind::Tpdo(pdo, node)
            }
            Message::Rpdo { pdo, node, .. } => CobKind::Rpdo(pdo, node),
            Message::SdoRequest { node, .. } => CobKind::SdoRx(node),
            Message::SdoResponse { node, .. } => CobKind::SdoTx(node),
            Message::Heartbeat { node, .. } | Message::NodeGuardRequest { node, .. } => {
                CobKind::NmtErrorControl(node)
            }
            Message::Lss(lss) => CobKind::Lss(lss.direction()),
            Message::Unknown(f) => classify(f.id()),
        }
    }

    /// The node the message belongs to, if any.
    #[must_use]
    pub fn node(&self) -> Option<NodeId> {
        self.kind().node()
    }

    /// Encodes the message as a frame: the identifier of its
    /// [`kind`](Self::kind) and the bytes its representation's
    /// [`Codec::emit`] writes. For a message returned by
    /// [`Message::decode`], this is the identical frame.
    #[must_use]
    #[inline]
    pub fn encode(&self) -> CanFrame {
        let id = CanId::Standard(self.kind().cob_id().unwrap_or(0));
        let mut buf = [0u8; 8];
        let len: usize = match self {
            Message::Unknown(frame) => return *frame,
            Message::TpdoRequest { dlc, .. } | Message::NodeGuardRequest { dlc, .. } => {
                return CanFrame::remote(id, (*dlc).min(8))
                    .unwrap_or(CanFrame::from_parts(id, [0; 8], 0));
            }
            Message::Nmt(cmd) => cmd.emit(&mut buf),
            Message::Sync(sync) => sync.emit(&mut buf),
            Message::Emcy { emcy, .. } => emcy.emit(&mut buf),
            Message::Time(time) => time.emit(&mut buf),
            Message::Tpdo { payload, .. } | Message::Rpdo { payload, .. } => payload.emit(&mut buf),
            Message::Lss(lss) => lss.emit(&mut buf),
            Message::SdoRequest { sdo, .. } => sdo.emit(&mut buf),
            Message::SdoResponse { sdo, .. } => sdo.emit(&mut buf),
            Message::Heartbeat { heartbeat, .. } => heartbeat.emit(&mut buf),
        };
        CanFrame::from_parts(id, buf, len.min(8) as u8)
    }
}

#[cfg(test)]
mod tests;
