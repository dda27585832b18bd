//! The client without segmented transfer (feature `sdo-client-segmented`
//! off): what it refuses, the abort it sends and the event it reports.

use std::vec::Vec;

use crate::machine::Machine;
use crate::sdo::{AbortCode, AbortOrigin, Client, ClientConfig, ClientError, ClientEvent};
use crate::{CanFrame, NodeId, Timestamp};

fn client() -> Client<&'static [u8]> {
    Client::new(ClientConfig::for_server(NodeId::new(2).unwrap()))
}

fn response(data: &[u8]) -> CanFrame {
    CanFrame::standard(0x582, data).unwrap()
}

fn sent(c: &mut Client<&'static [u8]>) -> Option<Vec<u8>> {
    c.poll_transmit().map(|f| f.data().to_vec())
}

/// Empty and longer values refuse to start: nothing sent, no timer, no
/// event, idle; an expedited download runs afterwards.
#[test]
fn downloads_that_need_segments_are_refused() {
    let mut c = client();
    for value in [&[][..], &[1, 2, 3, 4, 5][..], &[0u8; 300][..]] {
        assert_eq!(
            c.start_download(Timestamp::ZERO, 0x2000, 1, value),
            Err(ClientError::SegmentedUnsupported { len: value.len() })
        );
        assert_eq!(sent(&mut c), None);
        assert_eq!(c.poll_timeout(), None);
        assert_eq!(c.poll_event(), None);
        assert!(!c.is_busy());
    }
    c.start_download(Timestamp::ZERO, 0x2000, 1, &[1, 2, 3, 4])
        .unwrap();
    assert_eq!(sent(&mut c), Some(vec![0x23, 0x00, 0x20, 0x01, 1, 2, 3, 4]));
    c.handle_frame(
        Timestamp::from_millis(1),
        &response(&[0x60, 0x00, 0x20, 0x01, 0, 0, 0, 0]),
    );
    assert_eq!(
        c.poll_event(),
        Some(ClientEvent::Downloaded {
            index: 0x2000,
            sub: 1,
            len: 4
        })
    );
}

/// A segmented upload response, with the size (above 4 or not) or
/// without: one abort frame 05040001h for the object, one local `Aborted`
/// event, the client idle and its timer stopped; nothing more follows.
#[test]
fn segmented_upload_responses_are_aborted() {
    for answer in [
        [0x41, 0x08, 0x10, 0x00, 20, 0, 0, 0],
        [0x41, 0x08, 0x10, 0x00, 3, 0, 0, 0],
        [0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0],
    ] {
        let mut c = client();
        c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
        assert_eq!(sent(&mut c), Some(vec![0x40, 0x08, 0x10, 0, 0, 0, 0, 0]));
        c.handle_frame(Timestamp::from_millis(2), &response(&answer));
        assert_eq!(
            sent(&mut c),
            Some(vec![0x80, 0x08, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05]),
            "{answer:02X?}"
        );
        assert_eq!(sent(&mut c), None);
        assert_eq!(
            c.poll_event(),
            Some(ClientEvent::Aborted {
                index: 0x1008,
                sub: 0,
                code: AbortCode::InvalidCommandSpecifier,
                origin: AbortOrigin::Local,
            })
        );
        assert_eq!(c.poll_event(), None);
        assert!(!c.is_busy());
        assert_eq!(c.poll_timeout(), None);
        // A segment the server sends on is not for any transfer now.
        c.handle_frame(
            Timestamp::from_millis(3),
            &response(&[0x00, 1, 2, 3, 4, 5, 6, 7]),
        );
        assert_eq!(sent(&mut c), None);
        assert_eq!(c.poll_event(), None);
    }
}

/// Expedited uploads are untouched: the data, then `Uploaded`.
#[test]
fn expedited_uploads_still_run() {
    let mut c = client();
    c.start_upload(Timestamp::ZERO, 0x1000, 0).unwrap();
    let _ = sent(&mut c);
    c.handle_frame(
        Timestamp::from_millis(1),
        &response(&[0x43, 0x00, 0x10, 0x00, 0xA2, 0x01, 0x00, 0x00]),
    );
    assert!(matches!(
        c.poll_event(),
        Some(ClientEvent::UploadData { index: 0x1000, sub: 0, offset: 0, data }) if data.as_slice() == [0xA2, 0x01, 0, 0]
    ));
    assert_eq!(
        c.poll_event(),
        Some(ClientEvent::Uploaded {
            index: 0x1000,
            sub: 0,
            len: 4
        })
    );
    assert_eq!(sent(&mut c), None);
}

/// A segment of a server that goes on after the initiate was refused, or
/// one too short for its command while the upload initiate is out: the
/// first aborts the transfer as a command that does not fit (05040001h),
/// the second is ignored.
#[test]
fn other_commands_while_initiating() {
    let mut c = client();
    c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
    let _ = sent(&mut c);
    // Upload segment with n = 0 needs 8 bytes: 3 are ignored.
    c.handle_frame(Timestamp::from_millis(1), &response(&[0x00, 1, 2]));
    assert_eq!(sent(&mut c), None);
    assert!(c.is_busy());
    c.handle_frame(
        Timestamp::from_millis(1),
        &response(&[0x00, 1, 2, 3, 4, 5, 6, 7]),
    );
    assert_eq!(
        sent(&mut c),
        Some(vec![0x80, 0x08, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05])
    );
    assert!(matches!(
        c.poll_event(),
        Some(ClientEvent::Aborted {
            code: AbortCode::InvalidCommandSpecifier,
            ..
        })
    ));
}
