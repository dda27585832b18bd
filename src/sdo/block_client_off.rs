//! [`Client`] without block transfer (feature `sdo-block` off): CiA 301
//! section 7.2.4.3 makes block transfer optional. The two commands that
//! start one are still there and refuse with
//! [`ClientError::BlockUnsupported`], sending nothing; no block state can be
//! entered, so every response takes the expedited and segmented paths.

use super::{Client, ClientError};
use crate::clock::Timestamp;
use crate::frame::CanFrame;

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// Would start a block upload of `index`/`sub` (CiA 301 section
    /// 7.2.4.3); built without the feature `sdo-block`, it refuses with
    /// [`ClientError::BlockUnsupported`] and sends nothing (use
    /// [`Client::start_upload`]).
    ///
    /// ```
    /// use canopen_codec::sdo::{Client, ClientConfig, ClientError};
    /// use canopen_codec::{NodeId, Timestamp};
    ///
    /// let mut client: Client = Client::new(ClientConfig::for_server(NodeId::new(2).unwrap()));
    /// let started = client.start_block_upload(Timestamp::ZERO, 0x1008, 0);
    /// assert_eq!(started, Err(ClientError::BlockUnsupported));
    /// ```
    pub fn start_block_upload(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
    ) -> Result<(), ClientError> {
        let _ = (now, index, sub);
        Err(ClientError::BlockUnsupported)
    }

    /// Would start a block download of `data` to `index`/`sub`; built
    /// without the feature `sdo-block`, it refuses with
    /// [`ClientError::BlockUnsupported`], sends nothing and drops `data`
    /// (use [`Client::start_download`]).
    pub fn start_block_download(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        data: D,
    ) -> Result<(), ClientError> {
        let _ = (now, index, sub, data);
        Err(ClientError::BlockUnsupported)
    }

    /// No block upload runs: every frame is a response for the normal path
    /// (the general response path's; the expedited client has its own).
    #[cfg(feature = "sdo-client-segmented")]
    pub(super) fn block_segment(&mut self, _now: Timestamp, _bytes: &[u8]) -> bool {
        false
    }

    /// No block download runs: no segment to make.
    pub(super) fn next_block_segment(&mut self) -> Option<CanFrame> {
        None
    }
}

#[cfg(test)]
mod tests {
    use crate::machine::Machine;
    use crate::sdo::{Client, ClientConfig, ClientError};
    use crate::{NodeId, Timestamp};

    /// Both block commands refuse, send nothing, start no timer and leave
    /// the client idle for a normal transfer.
    #[test]
    fn block_commands_refuse_and_send_nothing() {
        let mut c: Client<[u8; 3]> = Client::new(ClientConfig::for_server(NodeId::new(2).unwrap()));
        assert_eq!(
            c.start_block_upload(Timestamp::ZERO, 0x1008, 0),
            Err(ClientError::BlockUnsupported)
        );
        assert_eq!(
            c.start_block_download(Timestamp::ZERO, 0x2000, 1, [1, 2, 3]),
            Err(ClientError::BlockUnsupported)
        );
        assert_eq!(c.poll_transmit(), None);
        assert_eq!(c.poll_timeout(), None);
        assert_eq!(c.poll_event(), None);
        assert!(!c.is_busy());
        c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
        assert_eq!(
            c.poll_transmit().map(|f| f.data().to_vec()),
            Some(vec![0x40, 0x08, 0x10, 0, 0, 0, 0, 0])
        );
    }
}
