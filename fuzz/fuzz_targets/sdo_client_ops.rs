//! The SDO client under an arbitrary sequence of received frames, time steps
//! and commands. Invariants: no panic; at most one transfer in progress
//! (a start while busy is refused); every frame sent is a valid SDO request
//! on the client's request identifier; every started transfer ends in at most
//! one terminal event, and upload pieces arrive in order.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::sdo::{AbortCode, Client, ClientCommand, ClientConfig, ClientError, ClientEvent, SdoRequest};
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// A response frame on the client's response id (or, with `other`, on another id).
    Frame { other: bool, remote: bool, data: [u8; 8], len: u8 },
    /// Time passes (possibly backwards).
    Advance { micros: u32, backwards: bool },
    StartUpload { index: u16, sub: u8 },
    StartDownload { index: u16, sub: u8, len: u16 },
    Abort { code: u32 },
}

const NODE: u8 = 3;

fuzz_target!(|ops: Vec<Op>| {
    let node = NodeId::new(NODE).unwrap();
    let config = ClientConfig::for_server(node);
    let mut client: Client<Vec<u8>> = Client::new(config);
    let mut now = Timestamp::from_millis(10_000);
    let mut started = 0usize;
    let mut terminal = 0usize;
    let mut expected_offset = 0usize;
    for op in ops.into_iter().take(256) {
        let was_busy = client.is_busy();
        match op {
            Op::Frame { other, remote, data, len } => {
                let id = if other { CanId::Standard(0x580 + u16::from(NODE) + 1) } else { config.response_id };
                let len = usize::from(len % 9);
                let frame = if remote {
                    CanFrame::remote(id, len as u8).unwrap()
                } else {
                    CanFrame::new(id, &data[..len]).unwrap()
                };
                client.handle_frame(now, &frame);
            }
            Op::Advance { micros, backwards } => {
                now = if backwards {
                    Timestamp::from_micros(now.as_micros().saturating_sub(u64::from(micros)))
                } else {
                    now.add_micros(u64::from(micros) * 16)
                };
                client.handle_timeout(now);
            }
            Op::StartUpload { index, sub } => match client.start_upload(now, index, sub) {
                Ok(()) => {
                    assert!(!was_busy);
                    started += 1;
                    expected_offset = 0;
                }
                Err(ClientError::Busy) => assert!(was_busy),
                Err(e) => panic!("unexpected {e}"),
            },
            Op::StartDownload { index, sub, len } => {
                let data = vec![0xA5; usize::from(len)];
                match client.start_download(now, index, sub, data) {
                    Ok(()) => {
                        assert!(!was_busy);
                        started += 1;
                    }
                    Err(ClientError::Busy) => assert!(was_busy),
                    Err(e) => panic!("unexpected {e}"),
                }
            }
            Op::Abort { code } => {
                let aborted = client.abort(now, AbortCode::from(code));
                assert_eq!(aborted, was_busy);
            }
        }
        while let Some(f) = client.poll_transmit() {
            assert_eq!(f.id(), config.request_id);
            assert!(!f.is_remote());
            assert_eq!(f.dlc(), 8, "{f}");
            let req = SdoRequest::decode(f.data()).expect("client sends valid SDO frames");
            assert!(!matches!(req.command, ClientCommand::Unknown(_)));
        }
        while let Some(e) = client.poll_event() {
            match e {
                ClientEvent::UploadData { offset, data, .. } => {
                    assert_eq!(offset, expected_offset);
                    assert!(!data.is_empty());
                    expected_offset += data.len();
                }
                ClientEvent::Uploaded { len, .. } => {
                    assert_eq!(len, expected_offset);
                    terminal += 1;
                }
                _ => terminal += 1,
            }
        }
        assert!(terminal <= started, "more terminal events than transfers");
        // A transfer that is no longer running has ended exactly once.
        if !client.is_busy() {
            assert_eq!(terminal, started);
            assert_eq!(client.poll_timeout(), None);
        } else {
            assert_eq!(terminal + 1, started);
            assert!(client.poll_timeout().is_some());
        }
    }
});
