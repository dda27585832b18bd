//! Client and server on one simulated bus (`common::sdo::SdoPair`): whole
//! transfers, random values, latencies and dropped frames.

use std::time::Duration;

use crate::common;

use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::sdo::ObserverEvent;
use canopen_codec::sdo::{AbortCode, ClientEvent, ServerEvent, TransferEnd};
use canopen_codec::Timestamp;
use common::observe;
use common::sdo::{SdoPair, CLIENT};
use proptest::prelude::*;

fn od_with(index: u16, sub: u8, max: usize) -> MemoryDictionary {
    let mut od = MemoryDictionary::new();
    od.insert_variable(index, sub, Access::ReadWrite, b"", max);
    od
}

/// Writes `value` then reads it back through the pair; returns the pair.
fn write_then_read(index: u16, sub: u8, value: &[u8], latency_us: u64) -> SdoPair {
    let mut p = SdoPair::new(5, od_with(index, sub, 4096));
    p.set_latency(Duration::from_micros(latency_us));
    p.with_client(|c, now| c.start_download(now, index, sub, value.to_vec()))
        .unwrap();
    p.drive_bounded(10_000).unwrap();
    assert_eq!(
        p.client_events(),
        vec![ClientEvent::Ended(TransferEnd::Downloaded {
            index,
            sub,
            len: value.len()
        })]
    );
    assert_eq!(
        p.server_events(),
        vec![ServerEvent::Downloaded {
            index,
            sub,
            len: value.len()
        }]
    );
    assert_eq!(p.od().get(index, sub), Some(value));
    p.clear_events();
    p.with_client(|c, now| c.start_upload(now, index, sub))
        .unwrap();
    p.drive_bounded(10_000).unwrap();
    assert_eq!(p.uploaded(), value);
    assert_eq!(
        p.client_events().last(),
        Some(&ClientEvent::Ended(TransferEnd::Uploaded {
            index,
            sub,
            len: value.len()
        }))
    );
    assert_eq!(
        p.server_events(),
        vec![ServerEvent::Uploaded {
            index,
            sub,
            len: value.len()
        }]
    );
    // The observer, fed the same frames, saw both transfers complete with
    // every byte.
    let seen = observe::replay(&p.sim, latency_us);
    let ends = seen.ends((index, sub));
    assert_eq!(ends.len(), 2, "{ends:?}");
    for end in ends {
        assert!(
            matches!(end, ObserverEvent::Completed { bytes, .. } if bytes == value.len()),
            "{end:?}"
        );
    }
    assert_eq!(seen.value((index, sub)), value);
    p
}

#[test]
fn sizes_around_every_boundary() {
    for len in [0usize, 1, 3, 4, 5, 6, 7, 8, 13, 14, 15, 21, 22, 1000, 2000] {
        let value: Vec<u8> = (0..len).map(|i| (i * 7 + 3) as u8).collect();
        let p = write_then_read(0x2000, 1, &value, 1_000);
        // Frames on the wire: expedited 1..=4 is one exchange each way.
        let frames_per_direction = if (1..=4).contains(&len) {
            1
        } else {
            1 + len.div_ceil(7).max(1)
        };
        let to_server = p.sent_by(CLIENT).count();
        // The download and the upload each take `frames_per_direction` requests.
        assert_eq!(to_server, 2 * frames_per_direction, "len {len}");
    }
}

#[test]
fn drive_bounded_reports_livelock() {
    let mut p = SdoPair::new(5, od_with(0x2000, 0, 4096));
    p.with_client(|c, now| c.start_download(now, 0x2000, 0, vec![0; 2000]))
        .unwrap();
    assert!(p.drive_bounded(10).is_err());
}

/// Frames of an undisturbed transfer of `len` bytes (both directions).
fn frames_of(len: usize) -> usize {
    if (1..=4).contains(&len) {
        2
    } else {
        2 * (1 + len.div_ceil(7).max(1))
    }
}

/// The transfer ended in the SDO timeout (05040000h), whoever aborted.
fn is_timeout_abort(end: &TransferEnd) -> bool {
    matches!(
        end,
        TransferEnd::Aborted {
            code: AbortCode::SdoProtocolTimedOut,
            ..
        }
    )
}

/// With frame number `k` dropped: the client ends in exactly one timeout
/// abort (its own, or the server's abort frame when the server's deadline
/// came first). The server ends in one timeout abort too, except in the two
/// cases SDO cannot avoid: the first request was lost (the server never saw
/// a transfer: no event) or the server's final response was lost (the server
/// had finished: one success event). Nothing else happens.
fn check_drop(len: usize, upload: bool, k: usize, latency_us: u64) {
    let index = 0x2100;
    let n = frames_of(len);
    if k >= n {
        return;
    }
    let value: Vec<u8> = (0..len).map(|i| i as u8 ^ 0x5A).collect();
    let mut od = od_with(index, 0, 4096);
    od.set(index, 0, &value);
    let mut p = SdoPair::new(9, od);
    p.set_latency(Duration::from_micros(latency_us));
    p.drop_nth(k);
    if upload {
        p.with_client(|c, now| c.start_upload(now, index, 0))
            .unwrap();
    } else {
        p.with_client(|c, now| c.start_download(now, index, 0, vec![0xEE; len]))
            .unwrap();
    }
    p.drive_bounded(10_000).unwrap();
    let ctx = format!("len={len} upload={upload} k={k} wire={:?}", p.log());
    let client_events = p.client_events();
    let server_events = p.server_events();
    let terminal: Vec<&ClientEvent> = client_events.iter().filter(|e| e.is_terminal()).collect();
    assert_eq!(terminal.len(), 1, "{ctx}");
    assert!(
        matches!(terminal[0], ClientEvent::Ended(end) if is_timeout_abort(end)),
        "{ctx}"
    );
    if k == 0 {
        assert_eq!(p.server_events(), vec![], "first request lost: {ctx}");
    } else if k == n - 1 {
        assert_eq!(server_events.len(), 1, "{ctx}");
        assert!(
            matches!(
                server_events[0],
                ServerEvent::Uploaded { .. } | ServerEvent::Downloaded { .. }
            ),
            "{ctx}"
        );
    } else {
        assert_eq!(server_events.len(), 1, "{ctx}");
        assert!(is_timeout_abort(&server_events[0]), "{ctx}");
    }
    // A download that did not complete left the old value in place.
    if !upload && !matches!(server_events.first(), Some(ServerEvent::Downloaded { .. })) {
        assert_eq!(p.od().get(index, 0), Some(value.as_slice()), "{ctx}");
    }
    // Nothing is pending afterwards, and it took the timeout to get there.
    assert!(!p.client().is_busy() && !p.server().is_busy());
    assert!(p.now() >= Timestamp::from_millis(2000));
    // The observer, fed the same frames, ends the transfer once: with the
    // timeout abort that was on the bus, or broken off when the dropped
    // frame was what it needed to see.
    let seen = observe::replay(&p.sim, latency_us);
    let aborts = observe::aborts_on_the_bus(&p.sim, CLIENT);
    let object = (index, 0);
    let expected: &[u8] = if upload { &value } else { &[0xEE; 256][..len] };
    observe::check_one_transfer(&seen, object, expected, false, &aborts);
    // Every abort on the wire carries the transfer's index and the timeout code.
    for s in p.log() {
        if s.frame.data().first() == Some(&0x80) {
            assert_eq!(
                s.frame.data(),
                &[0x80, 0x00, 0x21, 0x00, 0x00, 0x00, 0x04, 0x05],
                "{ctx}"
            );
        }
    }
}

#[test]
fn every_dropped_frame_of_small_transfers() {
    for len in [0usize, 3, 4, 5, 20] {
        for upload in [false, true] {
            for k in 0..12 {
                check_drop(len, upload, k, 1_000);
                check_drop(len, upload, k, 0);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: Some(Box::new(proptest::test_runner::FileFailurePersistence::Direct("tests/proptest-regressions/sdo_pair.txt"))),
        ..ProptestConfig::default()
    })]

    #[test]
    fn value_read_back_equals_value_written(
        value in proptest::collection::vec(any::<u8>(), 0..=2000),
        index in 0x1000u16..=0xFFFF,
        sub in any::<u8>(),
        latency_us in 0u64..=500_000,
    ) {
        write_then_read(index, sub, &value, latency_us);
    }

    #[test]
    fn a_dropped_frame_ends_in_one_timeout_abort(
        len in 0usize..=200,
        upload in any::<bool>(),
        k_seed in any::<usize>(),
        latency_us in 0u64..=100_000,
    ) {
        check_drop(len, upload, k_seed % frames_of(len), latency_us);
    }
}
