//! The client without segmented transfer (feature `sdo-client-segmented`
//! off): what it refuses, the abort it sends and the event it reports.

use std::vec::Vec;

use crate::abort::AbortCode;
use crate::machine::Machine;
use crate::sdo::{AbortOrigin, Client, ClientConfig, ClientError, ClientEvent, TransferEnd};
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
        Some(ClientEvent::Ended(TransferEnd::Downloaded {
            index: 0x2000,
            sub: 1,
            len: 4
        }))
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
            Some(ClientEvent::Ended(TransferEnd::Aborted {
                index: 0x1008,
                sub: 0,
                code: AbortCode::InvalidCommandSpecifier,
                origin: AbortOrigin::Local,
            }))
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
        Some(ClientEvent::Ended(TransferEnd::Uploaded {
            index: 0x1000,
            sub: 0,
            len: 4
        }))
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
    assert_eq!(
        c.poll_event(),
        Some(ClientEvent::Ended(TransferEnd::local_abort(
            0x1008,
            0,
            AbortCode::InvalidCommandSpecifier
        )))
    );
}

/// The bound of the event queue: one call leaves at most
/// [`EVENTS_PER_CALL`](crate::sdo::EVENTS_PER_CALL) events (the capacity
/// the charger gives its client). Every response (each byte 0 at every
/// length, for the transfer's object) to an upload and to a download
/// initiate, then the timeout: never more, none dropped by a queue of
/// that capacity, and the expedited upload with data makes exactly that
/// many, so a queue of one fewer drops one.
#[test]
fn one_call_leaves_at_most_events_per_call() {
    use crate::sdo::EVENTS_PER_CALL;
    let config = ClientConfig::for_server(NodeId::new(2).unwrap());
    let mut most = 0;
    for b0 in 0..=u8::MAX {
        for len in 0..=8 {
            for upload in [true, false] {
                let mut c: Client<&'static [u8], EVENTS_PER_CALL> =
                    Client::with_event_capacity(config);
                if upload {
                    c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
                } else {
                    c.start_download(Timestamp::ZERO, 0x1008, 0, &[1, 2])
                        .unwrap();
                }
                while c.poll_transmit().is_some() {}
                let bytes = [b0, 0x08, 0x10, 0x00, 0x11, 0x22, 0x33, 0x44];
                let later = Timestamp::from_millis(1);
                c.handle_frame(later, &response(&bytes[..len]));
                let mut events = 0;
                while c.poll_event().is_some() {
                    events += 1;
                }
                assert!(events <= EVENTS_PER_CALL, "{b0:02X} / {len}: {events}");
                most = most.max(events);
                // The timeout of a transfer the frame left running.
                c.handle_timeout(Timestamp::from_millis(5000));
                assert!(core::iter::from_fn(|| c.poll_event()).count() <= EVENTS_PER_CALL);
                assert_eq!(c.events_dropped(), 0, "{b0:02X} / {len}");
                assert!(!c.is_busy());
            }
        }
    }
    assert_eq!(most, EVENTS_PER_CALL);
    let mut small: Client<&'static [u8], 1> = Client::with_event_capacity(config);
    small.start_upload(Timestamp::ZERO, 0x1000, 0).unwrap();
    small.handle_frame(
        Timestamp::from_millis(1),
        &response(&[0x43, 0x00, 0x10, 0x00, 0xA2, 0x01, 0x00, 0x00]),
    );
    assert_eq!(small.events_dropped(), 1);
}

/// The response path's outcomes for the transfer's object and another
/// one: the initiate response it waits for ends it, the other initiate
/// response (or a segment) is aborted 05040001h, an initiate response for
/// another object 06040043h, and the server's abort ends it with the
/// server's code (0 as 08000000h), nothing sent back.
#[test]
fn responses_against_the_running_transfer() {
    let local = |code| {
        Some(ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1008,
            sub: 0,
            code,
            origin: AbortOrigin::Local,
        }))
    };
    let peer = |code| {
        Some(ClientEvent::Ended(TransferEnd::Aborted {
            index: 0x1008,
            sub: 0,
            code,
            origin: AbortOrigin::Peer,
        }))
    };
    let cases: [(bool, [u8; 8], Option<ClientEvent>); 9] = [
        (
            false,
            [0x60, 0x08, 0x10, 0x00, 0, 0, 0, 0],
            Some(ClientEvent::Ended(TransferEnd::Downloaded {
                index: 0x1008,
                sub: 0,
                len: 2,
            })),
        ),
        (
            false,
            [0x60, 0x08, 0x10, 0x01, 0, 0, 0, 0],
            local(AbortCode::GeneralParameterIncompatibility),
        ),
        (
            false,
            [0x4F, 0x08, 0x10, 0x00, 1, 0, 0, 0],
            local(AbortCode::InvalidCommandSpecifier),
        ),
        (
            true,
            [0x60, 0x08, 0x10, 0x00, 0, 0, 0, 0],
            local(AbortCode::InvalidCommandSpecifier),
        ),
        (
            true,
            [0x4F, 0x09, 0x10, 0x00, 1, 0, 0, 0],
            local(AbortCode::GeneralParameterIncompatibility),
        ),
        // A segmented answer for another object: the object first.
        (
            true,
            [0x41, 0x08, 0x11, 0x00, 20, 0, 0, 0],
            local(AbortCode::GeneralParameterIncompatibility),
        ),
        (
            true,
            [0x20, 0x08, 0x10, 0x00, 0, 0, 0, 0],
            local(AbortCode::InvalidCommandSpecifier),
        ),
        (
            true,
            [0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x06],
            peer(AbortCode::ObjectDoesNotExist),
        ),
        (
            false,
            [0x80, 0x08, 0x10, 0x00, 0, 0, 0, 0],
            peer(AbortCode::GeneralError),
        ),
    ];
    for (upload, answer, event) in cases {
        let mut c = client();
        if upload {
            c.start_upload(Timestamp::ZERO, 0x1008, 0).unwrap();
        } else {
            c.start_download(Timestamp::ZERO, 0x1008, 0, &[1, 2])
                .unwrap();
        }
        let _ = sent(&mut c);
        c.handle_frame(Timestamp::from_millis(1), &response(&answer));
        assert_eq!(c.poll_event(), event, "{answer:02X?}");
        assert_eq!(c.poll_event(), None);
        // The client sends an abort exactly when it aborts itself.
        let aborts = matches!(
            event,
            Some(ClientEvent::Ended(TransferEnd::Aborted {
                origin: AbortOrigin::Local,
                ..
            }))
        );
        let abort = sent(&mut c);
        assert_eq!(abort.is_some(), aborts, "{answer:02X?}");
        if let (Some(frame), Some(ClientEvent::Ended(TransferEnd::Aborted { code, .. }))) =
            (abort, event)
        {
            let mut expected = vec![0x80, 0x08, 0x10, 0x00];
            expected.extend_from_slice(&code.to_u32().to_le_bytes());
            assert_eq!(frame, expected);
        }
        assert!(!c.is_busy());
        assert_eq!(c.poll_timeout(), None);
    }
}

/// Frames while idle are ignored, aborts among them.
#[test]
fn idle_ignores_every_response() {
    let mut c = client();
    for answer in [
        [0x80, 0x08, 0x10, 0x00, 0, 0, 0, 0],
        [0x43, 0x08, 0x10, 0x00, 1, 2, 3, 4],
        [0x60, 0x08, 0x10, 0x00, 0, 0, 0, 0],
    ] {
        c.handle_frame(Timestamp::from_millis(1), &response(&answer));
        assert_eq!(sent(&mut c), None);
        assert_eq!(c.poll_event(), None);
    }
}
