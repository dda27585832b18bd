//! The server without block transfer (feature `sdo-block` off): the block
//! commands refused as the feature docs say.
use crate::abort::AbortCode;
use crate::device::CommObjects;
use crate::machine::Machine;
use crate::sdo::{AbortOrigin, Server, ServerConfig, ServerEvent};
use crate::{CanFrame, NodeId, Timestamp};

fn server() -> Server<CommObjects> {
    let node = NodeId::new(1).unwrap();
    let mut comm = CommObjects::new(node);
    comm.heartbeat_ms = 1000;
    Server::new(ServerConfig::for_node(node), comm)
}

fn request(server: &mut Server<CommObjects>, data: [u8; 8]) -> Option<CanFrame> {
    let frame = CanFrame::standard(0x601, &data).unwrap();
    server.handle_frame(Timestamp::ZERO, &frame);
    server.poll_transmit()
}

/// Block download and block upload initiates of 1017h are refused with
/// 05040001h for 1017h; the server serves a normal upload after them.
#[test]
fn block_initiates_are_refused_with_05040001() {
    let refused = CanFrame::standard(0x581, &[0x80, 0x17, 0x10, 0, 0x01, 0, 0x04, 0x05]);
    let aborted = ServerEvent::Aborted {
        index: 0x1017,
        sub: 0,
        code: AbortCode::InvalidCommandSpecifier,
        origin: AbortOrigin::Local,
    };
    let mut s = server();
    // Block download initiate (CRC, size 2), block upload initiate (CRC, blksize 127).
    for data in [
        [0xC6, 0x17, 0x10, 0x00, 0x02, 0, 0, 0],
        [0xA4, 0x17, 0x10, 0x00, 0x7F, 0x00, 0, 0],
    ] {
        assert_eq!(request(&mut s, data), refused.ok());
        assert_eq!(s.poll_transmit(), None);
        assert_eq!(s.poll_event(), Some(aborted));
        assert_eq!(s.poll_event(), None);
        assert_eq!(s.poll_timeout(), None, "nothing runs");
    }
    assert_eq!(
        request(&mut s, [0x40, 0x17, 0x10, 0, 0, 0, 0, 0]),
        CanFrame::standard(0x581, &[0x4B, 0x17, 0x10, 0, 0xE8, 0x03, 0, 0]).ok()
    );
}

/// A block command other than an initiate (here a block ack) is an
/// unknown command: 05040001h.
#[test]
fn other_block_commands_are_unknown_commands() {
    let mut s = server();
    let answer = request(&mut s, [0xA2, 0x7F, 0x7F, 0, 0, 0, 0, 0]).unwrap();
    assert_eq!(answer.data(), &[0x80, 0, 0, 0, 0x01, 0, 0x04, 0x05]);
}
