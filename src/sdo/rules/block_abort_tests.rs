//! Block transfer aborts: CRC mismatch, the crash sequences seen in
//! another Rust stack (each ends in the right abort and no panic), the
//! protocol switch, phase and sequence errors, duplicates and the timer.

use super::tests::*;
use crate::clock::Timestamp;
use crate::machine::{assert_quiet_until, Machine};
use crate::sdo::*;

#[test]
fn crc_mismatch_aborts_05040004() {
    let mut s = server(Od::new(b""));
    serve(&mut s, &["v17 sub-block", "crc mismatch, download end"]);
    assert_eq!((s.od().aborted, s.od().finished), (1, None));
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    drive(&mut c, &["v18 sub-block", "crc mismatch, upload end"]);
}

#[test]
fn crash_block_size_zero_in_initiate_response() {
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    drive(&mut c, &["crash: block size 0 from the server"]);
    assert!(!c.is_busy());
    let mut s = server(Od::new(V18));
    serve(&mut s, &["crash: block size 128 and 0 from the client"]);
    assert!(!s.is_busy());
}

#[test]
fn crash_two_negative_acknowledgements_in_a_row() {
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, V17).unwrap();
    drive(&mut c, &["crash: two negative acknowledgements, download"]);
    let mut s = server(Od::new(V18));
    serve(&mut s, &["crash: two negative acknowledgements, upload"]);
}

#[test]
fn crash_abort_in_the_middle_of_a_sub_block() {
    let mut s = server(Od::new(b""));
    serve(&mut s, &["crash: abort in a sub-block, download"]);
    assert_eq!((s.od().aborted, s.is_busy()), (1, false));
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    drive(&mut c, &["crash: abort in a sub-block, upload"]);
    assert!(!c.is_busy());
}

#[test]
fn crash_end_frame_claiming_more_unused_bytes_than_there_are() {
    for case in [
        "crash: end frame with more unused bytes than there are, download",
        "crash: end frame with more unused bytes than there are, size indicated",
    ] {
        serve(&mut server(Od::new(b"")), &[case]);
    }
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    let upload = "crash: end frame with more unused bytes than there are, upload";
    drive(&mut c, &[upload]);
}

#[test]
fn crash_block_upload_of_an_empty_object() {
    let empty_upload = ["crash: block upload of an empty object"];
    serve(&mut server(Od::new(b"")), &empty_upload);
    let mut c = client();
    c.start_block_upload(T0, 0x2000, 0).unwrap();
    drive(&mut c, &empty_upload);
    let mut c = client();
    c.start_block_download(T0, 0x2000, 0, b"").unwrap();
    drive(&mut c, &["empty block download"]);
    let mut s = server(Od::new(b"x"));
    serve(&mut s, &["empty block download"]);
    assert_eq!((s.od().written(), s.od().finished), (&b""[..], Some(0)));
}

#[test]
fn protocol_switch_threshold() {
    serve(&mut server(Od::new(V18)), &["protocol switch, server"]);
    // The client follows the switch when it offered a threshold, and,
    // leniently, when it did not.
    let mut c = Client::<&[u8]>::new(ClientConfig {
        block_threshold: 4,
        ..ClientConfig::for_server(node())
    });
    c.start_block_upload(T0, 0x1017, 0).unwrap();
    drive(&mut c, &["protocol switch, client with a threshold"]);
    let mut c = client();
    c.start_block_upload(T0, 0x1008, 0).unwrap();
    drive(&mut c, &["protocol switch, client without a threshold"]);
}

#[test]
fn wrong_phase_and_sequence_aborts() {
    let server_cases = [
        "wrong phase, server",
        "v18 sub-block",
        "ack beyond what was sent",
    ];
    serve(&mut server(Od::new(V18)), &server_cases);
    serve(
        &mut server_with(4, Od::new(b"")),
        &["wrong sequence, server"],
    );
    let mut c = client();
    for case in [
        "wrong phase, client: a segmented response to a block download initiate",
        "wrong phase, client: an end acknowledgement while the sub-block is unanswered",
        "wrong object, client",
    ] {
        c.start_block_download(T0, 0x2000, 0, V17).unwrap();
        drive(&mut c, &[case]);
    }
}

#[test]
fn duplicate_of_the_block_closing_segment_is_ignored() {
    let closing = ["duplicate of the block closing segment"];
    serve(&mut server_with(2, Od::new(b"")), &closing);
    let last = ["v17 sub-block", "duplicate of the last segment"];
    serve(&mut server(Od::new(b"")), &last);
}

#[test]
fn timer_restarts_on_every_segment() {
    let mut s = server(Od::new(b""));
    s.handle_frame(T0, &frame(0x602, "C6 00 20 00 1E 00 00 00"));
    let _ = sent(&mut s);
    assert_eq!(s.poll_timeout(), Some(Timestamp::from_millis(2000)));
    s.handle_frame(
        Timestamp::from_millis(1500),
        &frame(0x602, "01 41 20 72 65 61 6C 6C"),
    );
    assert_quiet_until(&mut s, Timestamp::from_millis(3500));
    assert!(s.is_busy());
    s.handle_timeout(Timestamp::from_millis(3500));
    assert_eq!(sent(&mut s), ["80 00 20 00 00 00 04 05"]);
    assert_eq!(s.od().aborted, 1);
}
