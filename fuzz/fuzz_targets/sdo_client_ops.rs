//! The SDO client under an arbitrary sequence of received frames, time steps
//! and commands, run on two copies side by side: one whose events are read
//! after every call, one whose events are read only when the input says so.
//! Invariants: no panic; at most one transfer in progress (a start while
//! busy is refused, and only then); every frame sent is on the client's
//! request identifier with DLC 8, and each drain of the transmit queue is at
//! most one valid SDO request followed by at most one block download
//! sub-block (segments numbered 1, 2, .. up to 127, only the last may carry
//! the last flag); both copies
//! send exactly the same frames and keep the same timers (an undrained event
//! queue never changes protocol behaviour); the undrained copy's events are
//! the drained copy's with exactly `events_dropped` of them left out; every
//! started transfer ends in exactly one terminal event, and upload pieces
//! arrive in order.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::machine::Machine;
use canopen_codec::sdo::{AbortCode, Client, ClientCommand, ClientConfig, ClientError, ClientEvent, TransferEnd, SdoRequest};
use canopen_codec::{CanFrame, CanId, Codec, NodeId, Timestamp};
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    /// A response frame on the client's response id (or, with `other`, on another id).
    Frame { other: bool, remote: bool, data: [u8; 8], len: u8 },
    /// Time passes (possibly backwards).
    Advance { micros: u32, backwards: bool },
    StartUpload { index: u16, sub: u8 },
    StartDownload { index: u16, sub: u8, len: u16 },
    StartBlockUpload { index: u16, sub: u8 },
    StartBlockDownload { index: u16, sub: u8, len: u16 },
    /// A well-formed block transfer response for the running transfer.
    BlockResponse { kind: u8, a: u8, b: u8, data: [u8; 7] },
    Abort { code: u32 },
    /// Read the second copy's events now.
    ReadUndrained,
    /// Leave this op's frames unsent until after the next op (both copies).
    HoldTransmit,
}

const NODE: u8 = 3;

/// A valid SDO request (not a sub-block segment).
fn is_request(f: &CanFrame) -> bool {
    SdoRequest::parse(f.data()).is_ok_and(|r| !matches!(r.command, ClientCommand::Unknown(_)))
}

/// Segments numbered 1, 2, .. (at most 127), the last flag only on the last.
fn is_sub_block(frames: &[CanFrame]) -> bool {
    frames.len() <= 127
        && frames.iter().enumerate().all(|(i, f)| {
            let b0 = f.data()[0];
            usize::from(b0 & 0x7F) == i + 1 && (b0 & 0x80 == 0 || i + 1 == frames.len())
        })
}

/// `sub` is `full` with some elements left out, in order.
fn is_subsequence<T: PartialEq>(sub: &[T], full: &[T]) -> bool {
    let mut it = full.iter();
    sub.iter().all(|x| it.any(|y| y == x))
}

fuzz_target!(|ops: Vec<Op>| {
    let node = NodeId::new(NODE).unwrap();
    let config = ClientConfig::for_server(node);
    let mut client: Client<Vec<u8>> = Client::new(config);
    let mut undrained: Client<Vec<u8>> = Client::new(config);
    let mut now = Timestamp::from_millis(10_000);
    let mut started = 0usize;
    let mut terminal = 0usize;
    let mut expected_offset = 0usize;
    let mut all_events: Vec<ClientEvent> = Vec::new();
    let mut read_undrained: Vec<ClientEvent> = Vec::new();
    let mut hold = false;
    let mut held = 0u64;
    for op in ops.into_iter().take(256) {
        let was_busy = client.is_busy();
        let hold_now = std::mem::take(&mut hold);
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
                undrained.handle_frame(now, &frame);
            }
            Op::Advance { micros, backwards } => {
                now = if backwards {
                    Timestamp::from_micros(now.as_micros().saturating_sub(u64::from(micros)))
                } else {
                    now.add_micros(u64::from(micros) * 16)
                };
                client.handle_timeout(now);
                undrained.handle_timeout(now);
            }
            Op::StartUpload { index, sub } => {
                let result = client.start_upload(now, index, sub);
                assert_eq!(undrained.start_upload(now, index, sub), result);
                match result {
                    Ok(()) => {
                        assert!(!was_busy);
                        started += 1;
                        expected_offset = 0;
                    }
                    Err(ClientError::Busy) => assert!(was_busy),
                    Err(e) => panic!("unexpected {e}"),
                }
            }
            Op::StartDownload { index, sub, len } => {
                let data = vec![0xA5; usize::from(len)];
                let result = client.start_download(now, index, sub, data.clone());
                assert_eq!(undrained.start_download(now, index, sub, data), result);
                match result {
                    Ok(()) => {
                        assert!(!was_busy);
                        started += 1;
                    }
                    Err(ClientError::Busy) => assert!(was_busy),
                    Err(e) => panic!("unexpected {e}"),
                }
            }
            Op::StartBlockUpload { index, sub } => {
                let result = client.start_block_upload(now, index, sub);
                assert_eq!(undrained.start_block_upload(now, index, sub), result);
                match result {
                    Ok(()) => {
                        assert!(!was_busy);
                        started += 1;
                        expected_offset = 0;
                    }
                    Err(ClientError::Busy) => assert!(was_busy),
                    Err(e) => panic!("unexpected {e}"),
                }
            }
            Op::StartBlockDownload { index, sub, len } => {
                let data: Vec<u8> = (0..usize::from(len) % 2000).map(|i| i as u8).collect();
                let result = client.start_block_download(now, index, sub, data.clone());
                assert_eq!(undrained.start_block_download(now, index, sub, data), result);
                match result {
                    Ok(()) => {
                        assert!(!was_busy);
                        started += 1;
                    }
                    Err(ClientError::Busy) => assert!(was_busy),
                    Err(e) => panic!("unexpected {e}"),
                }
            }
            Op::BlockResponse { kind, a, b, data } => {
                let (index, sub) = client.current().unwrap_or((0x2000, 0));
                let [lo, hi] = index.to_le_bytes();
                let [d0, d1, d2, d3, d4, d5, d6] = data;
                let bytes = match kind % 7 {
                    // Block download initiate response, sc = a bit 0, blksize b.
                    0 => [0xA0 | (a & 1) << 2, lo, hi, sub, b, 0, 0, 0],
                    // Block download sub-block ack.
                    1 => [0xA2, a, b, 0, 0, 0, 0, 0],
                    // Block download end response.
                    2 => [0xA1, 0, 0, 0, 0, 0, 0, 0],
                    // Block upload initiate response with size a + 256 b.
                    3 => [0xC6 | (b & 1) << 2, lo, hi, sub, a, b >> 4, 0, 0],
                    // Sub-block segment: seqno and last flag from a.
                    4 => [a, d0, d1, d2, d3, d4, d5, d6],
                    // Block upload end: unused bytes and CRC.
                    5 => [0xC1 | (a & 7) << 2, b, d0, 0, 0, 0, 0, 0],
                    // Protocol switch: a normal segmented upload response.
                    _ => [0x41, lo, hi, sub, a, 0, 0, 0],
                };
                let frame = CanFrame::new(config.response_id, &bytes).unwrap();
                client.handle_frame(now, &frame);
                undrained.handle_frame(now, &frame);
            }
            Op::Abort { code } => {
                let aborted = client.abort(now, AbortCode::from(code));
                assert_eq!(undrained.abort(now, AbortCode::from(code)), aborted);
                assert_eq!(aborted, was_busy);
            }
            Op::ReadUndrained => read_undrained.extend(std::iter::from_fn(|| undrained.poll_event())),
            Op::HoldTransmit => hold = true,
        }
        // An undrained transmit queue keeps the newest frame and counts the other.
        assert!(client.frames_dropped() <= held);
        assert_eq!(undrained.frames_dropped(), client.frames_dropped());
        if hold_now {
            held += 1;
        } else {
            let mut frames = Vec::new();
            while let Some(f) = client.poll_transmit() {
                assert_eq!(undrained.poll_transmit(), Some(f), "the copies' frames differ");
                assert_eq!(f.id(), config.request_id);
                assert!(!f.is_remote());
                assert_eq!(f.dlc(), 8, "{f}");
                frames.push(f);
                assert!(frames.len() <= 128, "more than a request and a sub-block");
            }
            assert!(
                is_sub_block(&frames) || (is_request(&frames[0]) && is_sub_block(&frames[1..])),
                "not one request and one sub-block: {frames:?}"
            );
            assert_eq!(undrained.poll_transmit(), None, "the copies' frames differ");
        }
        assert_eq!(undrained.poll_timeout(), client.poll_timeout());
        assert_eq!(undrained.is_busy(), client.is_busy());
        assert_eq!(undrained.current(), client.current());
        while let Some(e) = client.poll_event() {
            all_events.push(e);
            match e {
                ClientEvent::UploadData { offset, data, .. } => {
                    assert_eq!(offset, expected_offset);
                    assert!(!data.is_empty());
                    expected_offset += data.len();
                }
                ClientEvent::Ended(TransferEnd::Uploaded { len, .. }) => {
                    assert_eq!(len, expected_offset);
                    terminal += 1;
                }
                _ => terminal += 1,
            }
        }
        assert_eq!(client.events_dropped(), 0, "a drained client drops no events");
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
    // The undrained copy saw the same events, minus exactly the dropped ones
    // (oldest first), and the newest is the newest there is.
    read_undrained.extend(std::iter::from_fn(|| undrained.poll_event()));
    assert!(is_subsequence(&read_undrained, &all_events));
    assert_eq!(read_undrained.len() as u64 + undrained.events_dropped(), all_events.len() as u64);
    assert_eq!(read_undrained.last(), all_events.last());
});
