//! The client without block transfer (feature `sdo-block` off): the block
//! commands refused as the feature docs say.
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
