//! The names nearly every user of the crate needs, in one import.
//!
//! ```
//! use canopen_codec::prelude::*;
//!
//! let frame = CanFrame::standard(0x705, &[0x7F]).unwrap();
//! let Message::Heartbeat { node, .. } = Message::decode(&frame).unwrap() else {
//!     panic!("not a heartbeat");
//! };
//! assert_eq!(node, NodeId::new(5).unwrap());
//! assert_eq!(Timestamp::from_millis(2).as_micros(), 2000);
//! ```

pub use crate::clock::Timestamp;
pub use crate::cob_id::NodeId;
pub use crate::frame::CanFrame;
pub use crate::machine::Machine;
pub use crate::message::Message;
pub use crate::wire::Codec;
