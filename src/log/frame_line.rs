//! What every output form knows about one frame besides its message: the
//! frame's line ([`FrameLine`]) and the notes on it ([`Notes`], with a
//! block transfer's sub-block segment).

use std::prelude::rust_2021::*;

use crate::sdo::{SdoChannel, Side as SdoSide};
use crate::NodeId;

use crate::log::roles::Roles;

/// A block transfer's sub-block segment (CiA 301 SDO block download and
/// upload): byte 0 is a sequence number, not a command specifier.
#[derive(Clone, Copy, Debug)]
pub struct BlockSegment {
    /// The server's node.
    pub node: NodeId,
    /// The sender of the data.
    pub from: SdoSide,
    /// The sequence number (1 to 127).
    pub seqno: u8,
    /// The last segment of the transfer.
    pub last: bool,
    /// The segment's data (7 bytes).
    pub data: crate::sdo::SegmentData,
}

impl std::fmt::Display for BlockSegment {
    /// `SDO block segment seq 3 to node 2: 41 20 72 65 61 6C 6C`
    /// (`seq 5, last`; `from node 2` when the server sends).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SDO block segment seq {}", self.seqno)?;
        if self.last {
            f.write_str(", last")?;
        }
        let to = match self.from {
            SdoSide::Client => "to",
            SdoSide::Server => "from",
        };
        write!(f, " {to} node {}:", self.node)?;
        for b in self.data.as_slice() {
            write!(f, " {b:02X}")?;
        }
        Ok(())
    }
}

/// The default SDO channel of its node (Message::decode names those).
pub fn is_default(channel: SdoChannel) -> bool {
    channel == SdoChannel::default_for(channel.node)
}

/// One frame's line as the output forms see it: the trace line, what it
/// decoded to, the roles, its named PDO fields and the notes on it.
#[derive(Clone, Copy)]
pub struct FrameLine<'a> {
    /// The line as read.
    pub log: &'a crate::trace::candump::LogLine<'a>,
    /// What the frame decoded to.
    pub decoded: &'a Result<crate::Message, crate::DecodeError>,
    /// Which node is which.
    pub roles: &'a Roles,
    /// The PDO's named fields, with where their mapping came from.
    pub fields: Option<&'a (crate::log::mappings::Source, crate::pdo::NamedFields)>,
    /// What the decoder knows besides the message.
    pub notes: &'a Notes,
}

/// What the decoder knows about a line besides its message.
#[derive(Clone, Copy, Default)]
pub struct Notes {
    /// The frame answers a node-guarding request.
    pub guard_reply: bool,
    /// How the frame deviates from CiA 301 (read anyway).
    pub deviation: Option<crate::message::lenient::Deviation>,
    /// The frame is a block transfer's sub-block segment.
    pub block_segment: Option<BlockSegment>,
}
