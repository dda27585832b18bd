//! Block transfer aborts: CRC mismatch, the crash sequences seen in
//! another Rust stack (each ends in the right abort and no panic), the
//! protocol switch, phase and sequence errors, duplicates and the timer.

use std::string::String;
use std::vec::Vec;

use super::tests::*;
use crate::clock::Timestamp;
use crate::machine::Machine;
use crate::sdo::*;

#[test]
fn crc_mismatch_aborts_05040004() {
    let mut s = server(Od::new(b""));
    let _ = req(&mut s, "C6 00 20 00 1E 00 00 00");
    for seg in V17_SEGMENTS {
        let _ = req(&mut s, seg);
    }
    assert_eq!(
        req(&mut s, "D5 46 69 00 00 00 00 00"),
        ["80 00 20 00 04 00 04 05"]
    );
    assert_eq!(s.od().aborted, 1);
    assert_eq!(s.od().finished, None);
    assert!(matches!(
        events(&mut s)[..],
        [ServerEvent::Aborted {
            code: AbortCode::CrcError,
            origin: AbortOrigin::Local,
            ..
        }]
    ));

    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    let _ = sent(&mut c);
    let _ = resp(&mut c, "C6 08 10 00 1A 00 00 00");
    for seg in V18_SEGMENTS {
        let _ = resp(&mut c, seg);
    }
    assert_eq!(
        resp(&mut c, "C9 41 E1 00 00 00 00 00"),
        ["80 08 10 00 04 00 04 05"]
    );
    assert!(matches!(
        events(&mut c).last(),
        Some(ClientEvent::Aborted {
            code: AbortCode::CrcError,
            ..
        })
    ));
}

#[test]
fn crash_block_size_zero_in_initiate_response() {
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    let _ = sent(&mut c);
    assert_eq!(
        resp(&mut c, "A4 00 20 00 00 00 00 00"),
        ["80 00 20 00 02 00 04 05"]
    );
    assert!(!c.is_busy());
    // And 128 from a client asking the server for a block upload.
    let mut s = server(Od::new(V18));
    script(
        &mut s,
        req,
        &[
            ("A4 08 10 00 80 00 00 00", &["80 08 10 00 02 00 04 05"]),
            ("A4 08 10 00 00 00 00 00", &["80 08 10 00 02 00 04 05"]),
        ],
    );
    assert!(!s.is_busy());
}

#[test]
fn crash_two_negative_acknowledgements_in_a_row() {
    // The sender resends the whole sub-block each time, then the
    // receiver falls silent: timeout 05040000h.
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    let _ = sent(&mut c);
    let _ = resp(&mut c, "A4 00 20 00 02 00 00 00");
    assert_eq!(resp(&mut c, "A2 00 02 00 00 00 00 00"), &V17_SEGMENTS[..2]);
    assert_eq!(resp(&mut c, "A2 00 02 00 00 00 00 00"), &V17_SEGMENTS[..2]);
    let due = c.poll_timeout().unwrap();
    c.handle_timeout(due);
    assert_eq!(sent(&mut c), ["80 00 20 00 00 00 04 05"]);
    assert!(matches!(
        events(&mut c)[..],
        [ClientEvent::Aborted {
            code: AbortCode::SdoProtocolTimedOut,
            ..
        }]
    ));

    let mut s = server(Od::new(V18));
    let _ = req(&mut s, "A4 08 10 00 02 00 00 00");
    let _ = req(&mut s, "A3 00 00 00 00 00 00 00");
    assert_eq!(req(&mut s, "A2 00 02 00 00 00 00 00"), &V18_SEGMENTS[..2]);
    assert_eq!(req(&mut s, "A2 00 02 00 00 00 00 00"), &V18_SEGMENTS[..2]);
    let due = s.poll_timeout().unwrap();
    s.handle_timeout(due);
    assert_eq!(sent(&mut s), ["80 08 10 00 00 00 04 05"]);
}

#[test]
fn crash_abort_in_the_middle_of_a_sub_block() {
    let mut s = server(Od::new(b""));
    let _ = req(&mut s, "C6 00 20 00 1E 00 00 00");
    let _ = req(&mut s, V17_SEGMENTS[0]);
    assert_eq!(req(&mut s, "80 00 20 00 00 00 04 05"), Vec::<String>::new());
    assert_eq!(
        events(&mut s),
        [ServerEvent::Aborted {
            index: 0x2000,
            sub: 0,
            code: AbortCode::SdoProtocolTimedOut,
            origin: AbortOrigin::Peer
        }]
    );
    assert_eq!((s.od().aborted, s.is_busy()), (1, false));

    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    let _ = sent(&mut c);
    let _ = resp(&mut c, "C6 08 10 00 1A 00 00 00");
    let _ = resp(&mut c, V18_SEGMENTS[0]);
    assert_eq!(
        resp(&mut c, "80 08 10 00 00 00 00 08"),
        Vec::<String>::new()
    );
    assert!(matches!(
        events(&mut c).last(),
        Some(ClientEvent::Aborted {
            code: AbortCode::GeneralError,
            origin: AbortOrigin::Peer,
            ..
        })
    ));
    assert!(!c.is_busy());
}

#[test]
fn crash_end_frame_claiming_more_unused_bytes_than_there_are() {
    // The last segment carried 1 byte (DLC 2); the end frame says 7 - 0 = 7
    // of its bytes are data: 05040001h.
    let mut s = server(Od::new(b""));
    let _ = req(&mut s, "C2 00 20 00 00 00 00 00");
    script(
        &mut s,
        req,
        &[
            ("81 41", &["A2 01 7F 00 00 00 00 00"]),
            ("C1 00 00 00 00 00 00 00", &["80 00 20 00 01 00 04 05"]),
        ],
    );
    // With the size indicated, 7 unused bytes leave too little data.
    let mut s = server(Od::new(b""));
    let _ = req(&mut s, "C6 00 20 00 0A 00 00 00");
    let _ = req(&mut s, "01 41 42 43 44 45 46 47");
    let _ = req(&mut s, "82 48 49 4A 00 00 00 00");
    assert_eq!(
        req(&mut s, "DD 00 00 00 00 00 00 00"),
        ["80 00 20 00 13 00 07 06"]
    );
    // The client receiving an upload: the same short last segment.
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    let _ = sent(&mut c);
    let _ = resp(&mut c, "C4 08 10 00 00 00 00 00");
    script(
        &mut c,
        resp,
        &[
            ("81 41", &["A2 01 7F 00 00 00 00 00"]),
            ("C1 00 00 00 00 00 00 00", &["80 08 10 00 01 00 04 05"]),
        ],
    );
}

#[test]
fn crash_block_upload_of_an_empty_object() {
    let mut s = server(Od::new(b""));
    script(
        &mut s,
        req,
        &[
            ("A4 00 20 00 7F 00 00 00", &["C6 00 20 00 00 00 00 00"]),
            ("A3 00 00 00 00 00 00 00", &["81 00 00 00 00 00 00 00"]),
            ("A2 01 7F 00 00 00 00 00", &["DD 00 00 00 00 00 00 00"]),
            ("A1 00 00 00 00 00 00 00", &[]),
        ],
    );
    assert_eq!(
        events(&mut s),
        [ServerEvent::Uploaded {
            index: 0x2000,
            sub: 0,
            len: 0
        }]
    );
    let mut c = client();
    c.start_block_upload(T0, 0x2000, 0).unwrap();
    let _ = sent(&mut c);
    script(
        &mut c,
        resp,
        &[
            ("C6 00 20 00 00 00 00 00", &["A3 00 00 00 00 00 00 00"]),
            ("81 00 00 00 00 00 00 00", &["A2 01 7F 00 00 00 00 00"]),
            ("DD 00 00 00 00 00 00 00", &["A1 00 00 00 00 00 00 00"]),
        ],
    );
    assert_eq!(
        events(&mut c),
        [ClientEvent::Uploaded {
            index: 0x2000,
            sub: 0,
            len: 0
        }]
    );
    // An empty block download: one empty last segment, 7 unused bytes.
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, b"").unwrap();
    assert_eq!(sent(&mut c), ["C6 00 20 00 00 00 00 00"]);
    script(
        &mut c,
        resp,
        &[
            ("A4 00 20 00 7F 00 00 00", &["81 00 00 00 00 00 00 00"]),
            ("A2 01 7F 00 00 00 00 00", &["DD 00 00 00 00 00 00 00"]),
        ],
    );
}

#[test]
fn protocol_switch_threshold() {
    // 1008h is 26 bytes: at threshold 26 the server answers segmented.
    let mut s = server(Od::new(V18));
    assert_eq!(
        req(&mut s, "A4 08 10 00 7F 1A 00 00"),
        ["41 08 10 00 1A 00 00 00"]
    );
    // Above the threshold: block.
    assert_eq!(
        req(&mut s, "A4 08 10 00 7F 19 00 00"),
        ["C6 08 10 00 1A 00 00 00"]
    );
    // The client follows the switch when it offered a threshold...
    let mut c = Client::<&[u8]>::new(ClientConfig {
        block_threshold: 4,
        ..ClientConfig::for_server(node())
    });
    c.start_block_upload(T0, 0x1017, 0).unwrap();
    assert_eq!(sent(&mut c), ["A4 17 10 00 7F 04 00 00"]);
    assert_eq!(
        resp(&mut c, "4B 17 10 00 E8 03 00 00"),
        Vec::<String>::new()
    );
    assert_eq!(
        events(&mut c).last(),
        Some(&ClientEvent::Uploaded {
            index: 0x1017,
            sub: 0,
            len: 2
        })
    );
    // ...and, leniently, when it did not (python-canopen's server switches
    // every block upload): here to a segmented upload.
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    let _ = sent(&mut c);
    script(
        &mut c,
        resp,
        &[
            ("41 08 10 00 02 00 00 00", &["60 00 00 00 00 00 00 00"]),
            ("0B 4F 4B 00 00 00 00 00", &[]),
        ],
    );
    assert_eq!(
        events(&mut c).last(),
        Some(&ClientEvent::Uploaded {
            index: 0x1008,
            sub: 0,
            len: 2
        })
    );
}

#[test]
fn wrong_phase_and_sequence_aborts() {
    // A start while idle, an ack before the start: 05040001h.
    let mut s = server(Od::new(V18));
    assert_eq!(
        req(&mut s, "A3 00 00 00 00 00 00 00"),
        ["80 00 00 00 01 00 04 05"]
    );
    let _ = req(&mut s, "A4 08 10 00 7F 00 00 00");
    assert_eq!(
        req(&mut s, "A2 04 7F 00 00 00 00 00"),
        ["80 08 10 00 01 00 04 05"]
    );
    // An ack beyond what was sent: 05040003h.
    let _ = req(&mut s, "A4 08 10 00 7F 00 00 00");
    let _ = req(&mut s, "A3 00 00 00 00 00 00 00");
    assert_eq!(
        req(&mut s, "A2 05 7F 00 00 00 00 00"),
        ["80 08 10 00 03 00 04 05"]
    );
    // A sequence number above the block size: 05040003h.
    let mut s = server_with(4, Od::new(b""));
    let _ = req(&mut s, "C6 00 20 00 1E 00 00 00");
    assert_eq!(
        req(&mut s, "05 00 00 00 00 00 00 00"),
        ["80 00 20 00 03 00 04 05"]
    );
    // Sequence number 0 without c: 05040003h.
    let _ = req(&mut s, "C6 00 20 00 1E 00 00 00");
    assert_eq!(
        req(&mut s, "00 00 00 00 00 00 00 00"),
        ["80 00 20 00 03 00 04 05"]
    );
    // The client: a segmented response to a block download initiate.
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    let _ = sent(&mut c);
    assert_eq!(
        resp(&mut c, "60 00 20 00 00 00 00 00"),
        ["80 00 20 00 01 00 04 05"]
    );
    // An end acknowledgement while the sub-block is unanswered.
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    let _ = sent(&mut c);
    let _ = resp(&mut c, "A4 00 20 00 7F 00 00 00");
    assert_eq!(
        resp(&mut c, "A1 00 00 00 00 00 00 00"),
        ["80 00 20 00 01 00 04 05"]
    );
    // A response for another object: 06040043h.
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    let _ = sent(&mut c);
    assert_eq!(
        resp(&mut c, "A4 01 20 00 7F 00 00 00"),
        ["80 00 20 00 43 00 04 06"]
    );
}

#[test]
fn duplicate_of_the_block_closing_segment_is_ignored() {
    let mut s = server_with(2, Od::new(b""));
    let _ = req(&mut s, "C6 00 20 00 1E 00 00 00");
    let _ = req(&mut s, V17_SEGMENTS[0]);
    assert_eq!(req(&mut s, V17_SEGMENTS[1]), ["A2 02 02 00 00 00 00 00"]);
    assert_eq!(req(&mut s, V17_SEGMENTS[1]), Vec::<String>::new());
    // And of the last segment while the end frame is awaited.
    let mut s = server(Od::new(b""));
    let _ = req(&mut s, "C6 00 20 00 1E 00 00 00");
    for seg in V17_SEGMENTS {
        let _ = req(&mut s, seg);
    }
    assert_eq!(req(&mut s, V17_SEGMENTS[4]), Vec::<String>::new());
    assert_eq!(
        req(&mut s, "D5 45 69 00 00 00 00 00"),
        ["A1 00 00 00 00 00 00 00"]
    );
}

#[test]
fn timer_restarts_on_every_segment() {
    let mut s = server(Od::new(b""));
    s.handle_frame(T0, &frame(0x602, "C6 00 20 00 1E 00 00 00"));
    let _ = sent(&mut s);
    assert_eq!(s.poll_timeout(), Some(Timestamp::from_millis(2000)));
    s.handle_frame(Timestamp::from_millis(1500), &frame(0x602, V17_SEGMENTS[0]));
    assert_eq!(s.poll_timeout(), Some(Timestamp::from_millis(3500)));
    s.handle_timeout(Timestamp::from_millis(3499));
    assert!(s.is_busy());
    s.handle_timeout(Timestamp::from_millis(3500));
    assert_eq!(sent(&mut s), ["80 00 20 00 00 00 04 05"]);
    assert_eq!(s.od().aborted, 1);
}
