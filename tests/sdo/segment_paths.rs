//! The segment of a running segmented transfer takes a short path through
//! the client's and the server's `handle_frame`; these tests hold it to
//! the rules of the general path: frames that are not a data frame on the
//! machine's identifier, and segments too short for their command, are
//! ignored at every step of an upload and a download (no frame, no event,
//! the transfer goes on), and the value arrives intact.

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::sdo::{
    Client, ClientConfig, ClientEvent, Server, ServerConfig, ServerEvent, TransferEnd,
};
use canopen_codec::{CanFrame, CanId, NodeId, Timestamp};

const VALUE: [u8; 20] = *b"battery module 0418!";

/// Frames on `id` that neither machine may act on while a segmented
/// transfer runs: a remote frame, the same bytes on the 29-bit identifier
/// of the same number, an empty data frame, and segments (ccs/scs 0, 1, 3)
/// shorter than their command needs.
fn noise(id: u16) -> Vec<CanFrame> {
    vec![
        CanFrame::remote(CanId::Standard(id), 8).unwrap(),
        CanFrame::new(CanId::Extended(u32::from(id)), &[0x60, 0, 0, 0, 0, 0, 0, 0]).unwrap(),
        CanFrame::new(CanId::Extended(u32::from(id)), &[0x00, 1, 2, 3, 4, 5, 6, 7]).unwrap(),
        CanFrame::new(CanId::Extended(u32::from(id)), &[0x20, 0, 0, 0, 0, 0, 0, 0]).unwrap(),
        CanFrame::standard(id, &[]).unwrap(),
        // A segment saying 7 data bytes (n = 0) with only 3 present.
        CanFrame::standard(id, &[0x00, 1, 2, 3]).unwrap(),
        CanFrame::standard(id, &[0x10, 1, 2, 3]).unwrap(),
    ]
}

fn pair() -> (Client<Vec<u8>>, Server<MemoryDictionary>) {
    let node = NodeId::new(3).unwrap();
    let mut od = MemoryDictionary::new();
    od.insert_variable(0x2000, 0, Access::ReadWrite, &VALUE, 64);
    (
        Client::new(ClientConfig::for_server(node)),
        Server::new(ServerConfig::for_node(node), od),
    )
}

/// Runs the started transfer, feeding both machines the noise before every
/// real frame; returns the client's and the server's events.
fn run(
    client: &mut Client<Vec<u8>>,
    server: &mut Server<MemoryDictionary>,
) -> (Vec<ClientEvent>, Vec<ServerEvent>) {
    let now = Timestamp::ZERO;
    let (mut ce, mut se) = (Vec::new(), Vec::new());
    let mut frames = 0;
    while let Some(req) = client.poll_transmit() {
        frames += 1;
        assert!(frames < 100, "the transfer does not end");
        for f in noise(0x603) {
            server.handle_frame(now, &f);
            assert_eq!(server.poll_transmit(), None, "server answered {f}");
            assert_eq!(server.poll_event(), None, "server reported on {f}");
        }
        server.handle_frame(now, &req);
        se.extend(std::iter::from_fn(|| server.poll_event()));
        let Some(resp) = server.poll_transmit() else {
            break;
        };
        for f in noise(0x583) {
            client.handle_frame(now, &f);
            assert_eq!(client.poll_transmit(), None, "client answered {f}");
            assert_eq!(client.poll_event(), None, "client reported on {f}");
        }
        client.handle_frame(now, &resp);
        ce.extend(std::iter::from_fn(|| client.poll_event()));
    }
    (ce, se)
}

#[test]
fn upload_segments_ignore_what_the_general_path_ignores() {
    let (mut c, mut s) = pair();
    c.start_upload(Timestamp::ZERO, 0x2000, 0).unwrap();
    let (ce, se) = run(&mut c, &mut s);
    let mut got = Vec::new();
    for e in &ce {
        if let ClientEvent::UploadData { offset, data, .. } = e {
            assert_eq!(*offset, got.len());
            got.extend_from_slice(data.as_slice());
        }
    }
    assert_eq!(got, VALUE);
    assert_eq!(
        ce.last(),
        Some(&ClientEvent::Ended(TransferEnd::Uploaded {
            index: 0x2000,
            sub: 0,
            len: 20
        }))
    );
    assert_eq!(
        se,
        [ServerEvent::Uploaded {
            index: 0x2000,
            sub: 0,
            len: 20
        }]
    );
    assert!(!c.is_busy() && !s.is_busy());
}

#[test]
fn download_segments_ignore_what_the_general_path_ignores() {
    let (mut c, mut s) = pair();
    let value = b"a value of thirty-one bytes, ok".to_vec();
    c.start_download(Timestamp::ZERO, 0x2000, 0, value.clone())
        .unwrap();
    let (ce, se) = run(&mut c, &mut s);
    assert_eq!(
        ce,
        [ClientEvent::Ended(TransferEnd::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 31
        })]
    );
    assert_eq!(
        se,
        [ServerEvent::Downloaded {
            index: 0x2000,
            sub: 0,
            len: 31
        }]
    );
    assert_eq!(s.od().get(0x2000, 0), Some(&value[..]));
}
