//! The observer beside our own client and server: it reports what
//! they saw, for every transfer type.

use super::*;
use crate::od::{Access, MemoryDictionary};
use crate::sdo::{Client, ClientConfig, ClientEvent, Server, ServerConfig, TransferEnd};
use alloc::vec::Vec;

fn exchange(
    start: impl FnOnce(&mut Client<Vec<u8>>),
    initial: &[u8],
) -> (Vec<u8>, Vec<ObserverEvent>, Vec<ClientEvent>) {
    let mut od = MemoryDictionary::new();
    od.insert_variable(0x2E01, 1, Access::ReadWrite, initial, 4096);
    let mut server = Server::new(ServerConfig::for_node(node()), od);
    let mut client: Client<Vec<u8>> = Client::new(ClientConfig::for_server(node()));
    let mut obs: Observer = Observer::default();
    start(&mut client);
    let mut events = Vec::new();
    let mut client_events = Vec::new();
    let mut value = Vec::new();
    let now = Timestamp::ZERO;
    for _ in 0..10_000 {
        let mut moved = false;
        let mut watch = |obs: &mut Observer, f: &CanFrame| {
            obs.handle_frame(now, f);
            while let Some(e) = obs.poll_event() {
                if let ObserverEvent::Data { offset, data, .. } = e {
                    assert_eq!(offset, value.len());
                    value.extend_from_slice(data.as_slice());
                }
                events.push(e);
            }
        };
        while let Some(f) = client.poll_transmit() {
            moved = true;
            watch(&mut obs, &f);
            server.handle_frame(now, &f);
        }
        while let Some(f) = server.poll_transmit() {
            moved = true;
            watch(&mut obs, &f);
            client.handle_frame(now, &f);
        }
        while let Some(e) = client.poll_event() {
            client_events.push(e);
        }
        if !moved {
            break;
        }
        assert_eq!(obs.events_dropped(), 0);
    }
    (value, events, client_events)
}

#[test]
fn every_transfer_type_of_every_length() {
    for len in [0usize, 1, 4, 5, 7, 8, 13, 14, 15, 100, 889, 890, 1000] {
        let data: Vec<u8> = (0..len).map(|i| (i * 7 + len) as u8).collect();
        let cases: [(&str, bool); 4] = [
            ("upload", true),
            ("download", false),
            ("block upload", true),
            ("block download", false),
        ];
        for (name, upload) in cases {
            let d = data.clone();
            let block = name.starts_with("block");
            if block && !cfg!(feature = "sdo-block") {
                // The client refuses to start one (its own test).
                continue;
            }
            if !block && !matches!(len, 1..=4) && !cfg!(feature = "sdo-client-segmented") {
                // Segmented: the client refuses or aborts (its own tests).
                continue;
            }
            let (value, events, client_events) = exchange(
                |c| {
                    let now = Timestamp::ZERO;
                    match (upload, block) {
                        (true, false) => c.start_upload(now, 0x2E01, 1).unwrap(),
                        (false, false) => c.start_download(now, 0x2E01, 1, d).unwrap(),
                        (true, true) => c.start_block_upload(now, 0x2E01, 1).unwrap(),
                        (false, true) => c.start_block_download(now, 0x2E01, 1, d).unwrap(),
                    }
                },
                if upload { &data } else { b"" },
            );
            assert_eq!(value, data, "{name} of {len} bytes");
            let ends: Vec<_> = events.iter().filter(|e| e.is_terminal()).collect();
            assert_eq!(ends.len(), 1, "{name} of {len}: {events:?}");
            let ObserverEvent::Completed {
                bytes, transfer, ..
            } = ends[0]
            else {
                panic!("{name} of {len}: {ends:?}");
            };
            assert_eq!(*bytes, len);
            assert!(client_events.iter().any(|e| matches!(e, ClientEvent::Ended(TransferEnd::Uploaded { len: l, .. }) | ClientEvent::Ended(TransferEnd::Downloaded { len: l, .. }) if *l == len)));
            if block {
                assert!(matches!(
                    transfer.kind,
                    Some(TransferKind::Block { crc: true })
                ));
            }
        }
    }
}
