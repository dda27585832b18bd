//! [`Server`] without block transfer (feature `sdo-block` off): CiA 301
//! section 7.2.4.3 makes block transfer optional, and a server that does not
//! support it answers a block request like any command it does not know,
//! with abort 05040001h ("client/server command specifier not valid or
//! unknown"). A block initiate is a new request: it ends the running
//! transfer (superseded) and is refused for its own object; any other block
//! command aborts the running transfer, as an unknown command does.

use super::{AbortCode, ObjectDictionary, Server};
use crate::clock::Timestamp;
use crate::frame::CanFrame;

impl<D: ObjectDictionary, const EVENTS: usize> Server<D, EVENTS> {
    /// No block download runs: every frame is a command for the normal path.
    pub(super) fn block_segment(&mut self, _now: Timestamp, _bytes: &[u8]) -> bool {
        false
    }

    /// No block upload runs: no segment to make.
    pub(super) fn next_block_segment(&mut self) -> Option<CanFrame> {
        None
    }

    /// A block initiate: superseding and refused for its own object.
    pub(super) fn on_block_initiate(
        &mut self,
        _now: Timestamp,
        _frame: &CanFrame,
        index: u16,
        sub: u8,
    ) {
        self.refuse_block(index, sub);
    }

    /// Any other block command: an unknown command.
    pub(super) fn on_block_command(&mut self, _now: Timestamp, _frame: &CanFrame) {
        self.abort_local(AbortCode::InvalidCommandSpecifier);
    }

    fn refuse_block(&mut self, index: u16, sub: u8) {
        self.supersede();
        self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
    }
}

#[cfg(test)]
mod tests {
    use crate::device::CommObjects;
    use crate::machine::Machine;
    use crate::sdo::{AbortCode, AbortOrigin, Server, ServerConfig, ServerEvent};
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
}
