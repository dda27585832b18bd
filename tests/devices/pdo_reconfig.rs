//! The PDO reconfiguration procedure (CiA 301 PDO mapping; "Delta-Q IC
//! Series CANopen interface specification rev 2.0", section 4.6.2) through
//! the SDO
//! server: every rule, accepted and rejected, with the exact abort code; and
//! whole runs of the client-side procedure against the device side.

use crate::common;

use canopen_codec::cia418::DEFAULT_PDOS;
use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, MemoryDictionary};
use canopen_codec::pdo::{
    MappingEntry, PdoCobId, PdoCommParams, PdoConfig, PdoDictionary, PdoDirection, PdoMapping,
    PdoSlot, Plan, ReconfigEvent, Reconfigurer, TransmissionType,
};
use canopen_codec::sdo::{
    AbortCode, AbortOrigin, ClientConfig, ClientEvent, ServerEvent, TransferEnd,
};
use canopen_codec::{NodeId, PdoNumber, Timestamp};
use common::sdo::{SdoPair, SERVER};

const NODE: u8 = 1;

/// A CiA 418 battery module's application objects (mappable where the
/// profile maps them) under its default PDO set.
fn battery() -> PdoDictionary<MemoryDictionary> {
    let mut od = MemoryDictionary::new();
    for (index, len) in [
        (0x6000u16, 1usize),
        (0x6001, 1),
        (0x6010, 2),
        (0x6052, 2),
        (0x6060, 4),
        (0x6070, 2),
        (0x6080, 1),
        (0x6081, 1),
    ] {
        od.insert(index, 0, Access::ReadWrite, &vec![0; len]);
        od.set_mappable(index, 0, true);
    }
    od.insert_variable(0x1008, 0, Access::Const, b"battery", 32);
    od.insert(0x6020, 1, Access::ReadOnly, &[0x10]);
    let mut config = PdoConfig::new();
    let node = NodeId::new(NODE).unwrap();
    for d in DEFAULT_PDOS {
        let entries: Vec<MappingEntry> = d
            .entries
            .iter()
            .map(|&(i, s, b)| MappingEntry::new(i, s, b))
            .collect();
        let mut comm =
            PdoCommParams::event_driven(PdoCobId::from_u32(d.cob_id(node)), d.event_timer_ms);
        comm.transmission_type = TransmissionType::from_u8(d.transmission_type).unwrap();
        config.insert(
            d.direction,
            d.number,
            PdoSlot::new(comm, &PdoMapping::new(&entries).unwrap()),
        );
    }
    PdoDictionary::new(config, od)
}

fn pair() -> SdoPair<PdoDictionary<MemoryDictionary>> {
    SdoPair::new(NODE, battery())
}

/// Downloads `value` to `index`/`sub`; returns the client's terminal event
/// and checks the server agrees (and, on an abort, the exact abort frame).
fn write(
    p: &mut SdoPair<PdoDictionary<MemoryDictionary>>,
    index: u16,
    sub: u8,
    value: &[u8],
) -> Result<(), AbortCode> {
    p.clear_events();
    let wire_before = p.log().len();
    p.with_client(|c, now| c.start_download(now, index, sub, value.to_vec()))
        .unwrap();
    p.drive_bounded(1_000).unwrap();
    match p.client_events().as_slice() {
        [ClientEvent::Ended(TransferEnd::Downloaded { .. })] => {
            assert_eq!(
                p.server_events(),
                vec![ServerEvent::Downloaded {
                    index,
                    sub,
                    len: value.len()
                }]
            );
            Ok(())
        }
        [ClientEvent::Ended(TransferEnd::Aborted {
            code,
            origin: AbortOrigin::Peer,
            ..
        })] => {
            let [lo, hi] = index.to_le_bytes();
            let mut abort = vec![0x80, lo, hi, sub];
            abort.extend_from_slice(&code.to_u32().to_le_bytes());
            let last = p.log()[wire_before..]
                .iter()
                .rev()
                .find(|s| s.from == SERVER)
                .unwrap();
            assert_eq!(last.frame.data(), abort.as_slice(), "exact abort frame");
            assert_eq!(
                p.server_events(),
                vec![ServerEvent::Aborted {
                    index,
                    sub,
                    code: *code,
                    origin: AbortOrigin::Local
                }]
            );
            Err(*code)
        }
        other => panic!("unexpected events {other:?}"),
    }
}

fn u32le(v: u32) -> [u8; 4] {
    v.to_le_bytes()
}

fn tpdo0(p: &SdoPair<PdoDictionary<MemoryDictionary>>) -> PdoSlot {
    *p.od()
        .config
        .get(PdoDirection::Transmit, PdoNumber::P0)
        .unwrap()
}

/// Puts TPDO 0 (default: not valid) into the valid state with its id.
fn enable_tpdo0(p: &mut SdoPair<PdoDictionary<MemoryDictionary>>) {
    assert_eq!(write(p, 0x1800, 1, &u32le(0x181)), Ok(()));
    assert!(tpdo0(p).is_valid());
}

#[test]
fn mapping_cannot_change_while_the_pdo_is_valid() {
    let mut p = pair();
    enable_tpdo0(&mut p);
    assert_eq!(
        write(&mut p, 0x1A00, 0, &[0]),
        Err(AbortCode::UnsupportedAccess)
    );
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x6081_0008)),
        Err(AbortCode::UnsupportedAccess)
    );
    assert_eq!(tpdo0(&p).count(), 2, "nothing changed");
}

#[test]
fn entries_change_only_while_the_count_is_zero() {
    let mut p = pair();
    // Default TPDO 0 is not valid, count 2.
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x6081_0008)),
        Err(AbortCode::UnsupportedAccess)
    );
    assert_eq!(write(&mut p, 0x1A00, 0, &[0]), Ok(()));
    assert_eq!(write(&mut p, 0x1A00, 1, &u32le(0x6081_0008)), Ok(()));
    assert_eq!(tpdo0(&p).entry(1), Some(MappingEntry::new(0x6081, 0, 8)));
    // Writing 0 to an entry (clearing it) is allowed.
    assert_eq!(write(&mut p, 0x1A00, 3, &u32le(0)), Ok(()));
}

#[test]
fn count_must_go_through_zero() {
    let mut p = pair();
    assert_eq!(
        write(&mut p, 0x1A00, 0, &[1]),
        Err(AbortCode::UnsupportedAccess)
    );
    assert_eq!(write(&mut p, 0x1A00, 0, &[0]), Ok(()));
    assert_eq!(write(&mut p, 0x1A00, 0, &[1]), Ok(()));
    assert_eq!(
        write(&mut p, 0x1A00, 0, &[2]),
        Err(AbortCode::UnsupportedAccess)
    );
    assert_eq!(tpdo0(&p).count(), 1);
}

#[test]
fn count_is_validated_against_the_entries() {
    let mut p = pair();
    assert_eq!(write(&mut p, 0x1A00, 0, &[0]), Ok(()));
    // count > 8
    assert_eq!(
        write(&mut p, 0x1A00, 0, &[9]),
        Err(AbortCode::PdoLengthExceeded)
    );
    // a counted entry is zero (entries 3..8 are uninitialised)
    assert_eq!(write(&mut p, 0x1A00, 0, &[3]), Err(AbortCode::InvalidValue));
    // over 64 bits: 6060h/32 three times
    for sub in 1..=3 {
        assert_eq!(write(&mut p, 0x1A00, sub, &u32le(0x6060_0020)), Ok(()));
    }
    assert_eq!(
        write(&mut p, 0x1A00, 0, &[3]),
        Err(AbortCode::PdoLengthExceeded)
    );
    assert_eq!(write(&mut p, 0x1A00, 0, &[2]), Ok(()));
    assert_eq!(tpdo0(&p).mapping().total_bits(), 64);
}

#[test]
fn entries_are_checked_against_the_dictionary() {
    let mut p = pair();
    assert_eq!(write(&mut p, 0x1A00, 0, &[0]), Ok(()));
    // not mappable
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x1008_0008)),
        Err(AbortCode::ObjectCannotBeMapped)
    );
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x6020_0108)),
        Err(AbortCode::ObjectCannotBeMapped)
    );
    // more bits than the object holds
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x6000_0010)),
        Err(AbortCode::ObjectCannotBeMapped)
    );
    // missing object / sub-index
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x6099_0008)),
        Err(AbortCode::ObjectDoesNotExist)
    );
    assert_eq!(
        write(&mut p, 0x1A00, 1, &u32le(0x6020_0908)),
        Err(AbortCode::SubIndexDoesNotExist)
    );
    // dummy entries of the right width, and the mapping sub-index range
    assert_eq!(write(&mut p, 0x1A00, 1, &u32le(0x0005_0008)), Ok(()));
    assert_eq!(
        write(&mut p, 0x1A00, 2, &u32le(0x0005_0010)),
        Err(AbortCode::ObjectCannotBeMapped)
    );
    assert_eq!(
        write(&mut p, 0x1A00, 9, &u32le(0x6000_0008)),
        Err(AbortCode::SubIndexDoesNotExist)
    );
}

#[test]
fn cob_id_rules() {
    let mut p = pair();
    enable_tpdo0(&mut p);
    // Another identifier while valid: refused.
    assert_eq!(
        write(&mut p, 0x1800, 1, &u32le(0x182)),
        Err(AbortCode::InvalidValue)
    );
    // A refused COB-ID changes nothing.
    assert_eq!(tpdo0(&p).comm.cob_id, PdoCobId::from_u32(0x181));
    // The same identifier, RTR flag changed: allowed.
    assert_eq!(write(&mut p, 0x1800, 1, &u32le(0x4000_0181)), Ok(()));
    // Disable, change, enable.
    assert_eq!(write(&mut p, 0x1800, 1, &u32le(0x8000_0181)), Ok(()));
    assert_eq!(write(&mut p, 0x1800, 1, &u32le(0x8000_0190)), Ok(()));
    assert_eq!(write(&mut p, 0x1800, 1, &u32le(0x0000_0190)), Ok(()));
    assert_eq!(tpdo0(&p).comm.cob_id, PdoCobId::from_u32(0x190));
    // A valid 11-bit COB-ID with bits 28-11 set is not an identifier.
    assert_eq!(
        write(&mut p, 0x1801, 1, &u32le(0x0000_1281)),
        Err(AbortCode::InvalidValue)
    );
    let tpdo1 = p.od().config.get(PdoDirection::Transmit, PdoNumber::P1);
    assert_ne!(tpdo1.unwrap().comm.cob_id.to_u32(), 0x1281);
    // Wrong length.
    assert_eq!(
        write(&mut p, 0x1800, 1, &[0x81, 0x01]),
        Err(AbortCode::DataTypeLengthTooLow)
    );
}

#[test]
fn transmission_type_inhibit_time_and_sub0() {
    let mut p = pair();
    for t in [241u8, 250, 251, 252, 253] {
        assert_eq!(
            write(&mut p, 0x1800, 2, &[t]),
            Err(AbortCode::InvalidValue),
            "type {t}"
        );
    }
    for t in [0u8, 1, 240, 254, 255] {
        assert_eq!(write(&mut p, 0x1800, 2, &[t]), Ok(()), "type {t}");
    }
    // Inhibit time: while not valid accepted, while valid refused.
    assert_eq!(write(&mut p, 0x1800, 3, &[10, 0]), Ok(()));
    enable_tpdo0(&mut p);
    assert_eq!(
        write(&mut p, 0x1800, 3, &[20, 0]),
        Err(AbortCode::InvalidValue)
    );
    assert_eq!(tpdo0(&p).comm.inhibit_time_100us, 10);
    // Event timer: always.
    assert_eq!(write(&mut p, 0x1800, 5, &[0xF4, 0x01]), Ok(()));
    assert_eq!(tpdo0(&p).comm.event_timer_ms, 500);
    // Sub 0 is read-only; there is no sub 6.
    assert_eq!(
        write(&mut p, 0x1800, 0, &[5]),
        Err(AbortCode::WriteOfReadOnlyObject)
    );
    assert_eq!(
        write(&mut p, 0x1800, 6, &[5]),
        Err(AbortCode::SubIndexDoesNotExist)
    );
    // A PDO the module does not have.
    assert_eq!(
        write(&mut p, 0x1803, 1, &u32le(0x8000_0481)),
        Err(AbortCode::ObjectDoesNotExist)
    );
    assert_eq!(
        write(&mut p, 0x1A03, 0, &[0]),
        Err(AbortCode::ObjectDoesNotExist)
    );
}

#[cfg(feature = "sdo-client-segmented")]
#[test]
fn pdo_objects_read_back() {
    let mut p = pair();
    p.with_client(|c, now| c.start_upload(now, 0x1A01, 3))
        .unwrap();
    p.drive_bounded(100).unwrap();
    assert_eq!(p.uploaded(), u32le(0x6060_0020));
    p.clear_events();
    p.with_client(|c, now| c.start_upload(now, 0x1801, 1))
        .unwrap();
    p.drive_bounded(100).unwrap();
    assert_eq!(p.uploaded(), u32le(0x8000_0281));
    // Other objects pass through to the application's dictionary.
    p.clear_events();
    p.with_client(|c, now| c.start_upload(now, 0x1008, 0))
        .unwrap();
    p.drive_bounded(100).unwrap();
    assert_eq!(p.uploaded(), b"battery");
}

/// Runs a reconfiguration plan against the battery module to its end.
fn run_plan(
    od: PdoDictionary<MemoryDictionary>,
    plan: Plan,
) -> (ReconfigEvent, PdoDictionary<MemoryDictionary>, usize) {
    let node = NodeId::new(NODE).unwrap();
    let mut r = Reconfigurer::new(ClientConfig::for_server(node));
    let mut server =
        canopen_codec::sdo::Server::new(canopen_codec::sdo::ServerConfig::for_node(node), od);
    let mut now = Timestamp::ZERO;
    r.start(now, plan).unwrap();
    let mut frames = 0;
    for _ in 0..1000 {
        while let Some(f) = r.poll_transmit() {
            frames += 1;
            now = now.add_millis(1);
            server.handle_frame(now, &f);
            while server.poll_event().is_some() {}
            while let Some(resp) = server.poll_transmit() {
                now = now.add_millis(1);
                r.handle_frame(now, &resp);
            }
        }
        if let Some(e) = r.poll_event() {
            assert!(!r.is_running());
            assert_eq!(r.poll_event(), None, "exactly one outcome");
            return (e, server.into_inner(), frames);
        }
        if let Some(t) = r.poll_timeout() {
            now = now.max(t);
            r.handle_timeout(now);
        }
    }
    panic!("reconfiguration did not end");
}

#[test]
fn whole_procedure_remaps_a_tpdo() {
    let wanted = PdoMapping::new(&[
        MappingEntry::new(0x6010, 0, 16),
        MappingEntry::new(0x6000, 0, 8),
        MappingEntry::new(0x6081, 0, 8),
        MappingEntry::new(0x0005, 0, 8),
        MappingEntry::new(0x6060, 0, 32),
    ])
    .unwrap_err();
    // 72 bits: the plan's count step is refused with 06040042h.
    assert!(matches!(
        wanted,
        canopen_codec::pdo::MappingError::TooManyBits { got: 72 }
    ));
    let wanted = PdoMapping::new(&[
        MappingEntry::new(0x6010, 0, 16),
        MappingEntry::new(0x6000, 0, 8),
        MappingEntry::new(0x6081, 0, 8),
        MappingEntry::new(0x6060, 0, 32),
    ])
    .unwrap();
    let plan = Plan::new(
        PdoDirection::Transmit,
        PdoNumber::P1,
        PdoCobId::standard(0x2A1),
        &wanted,
    );
    assert_eq!(plan.steps().len(), 8);
    let (outcome, od, frames) = run_plan(battery(), plan);
    assert_eq!(outcome, ReconfigEvent::Done);
    assert_eq!(frames, 8, "one expedited download per step");
    let slot = od
        .config
        .get(PdoDirection::Transmit, PdoNumber::P1)
        .unwrap();
    assert_eq!(slot.mapping(), wanted);
    assert_eq!(slot.comm.cob_id, PdoCobId::standard(0x2A1));
    assert!(slot.is_valid());
}

#[test]
fn a_refused_step_is_reported_with_its_code() {
    // 1008h is not mappable: the entry step (index 2) fails, the PDO stays
    // disabled with count 0, and nothing after it is sent.
    let bad = PdoMapping::new(&[
        MappingEntry::new(0x6010, 0, 16),
        MappingEntry::new(0x1008, 0, 8),
    ])
    .unwrap();
    let plan = Plan::new(
        PdoDirection::Transmit,
        PdoNumber::P0,
        PdoCobId::standard(0x181),
        &bad,
    );
    let (outcome, od, frames) = run_plan(battery(), plan);
    let ReconfigEvent::Failed {
        step,
        at,
        code,
        origin,
    } = outcome
    else {
        panic!("{outcome:?}")
    };
    assert_eq!((step, at.index, at.sub), (3, 0x1A00, 2));
    assert_eq!(
        (code, origin),
        (AbortCode::ObjectCannotBeMapped, AbortOrigin::Peer)
    );
    assert_eq!(frames, 4);
    let slot = od
        .config
        .get(PdoDirection::Transmit, PdoNumber::P0)
        .unwrap();
    assert!(!slot.is_valid());
    assert_eq!(slot.count(), 0);
    // A PDO the module does not have fails at the first step.
    let plan = Plan::new(
        PdoDirection::Transmit,
        PdoNumber::P3,
        PdoCobId::standard(0x481),
        &bad,
    );
    let (outcome, _, _) = run_plan(battery(), plan);
    assert!(matches!(
        outcome,
        ReconfigEvent::Failed {
            step: 0,
            code: AbortCode::ObjectDoesNotExist,
            ..
        }
    ));
}

#[test]
fn a_silent_node_times_out_the_procedure() {
    let node = NodeId::new(NODE).unwrap();
    let mut r = Reconfigurer::new(ClientConfig::for_server(node));
    let m = PdoMapping::new(&[MappingEntry::new(0x6000, 0, 8)]).unwrap();
    r.start(
        Timestamp::ZERO,
        Plan::new(
            PdoDirection::Receive,
            PdoNumber::P0,
            PdoCobId::standard(0x201),
            &m,
        ),
    )
    .unwrap();
    assert!(r.poll_transmit().is_some());
    assert!(r
        .start(
            Timestamp::ZERO,
            Plan::new(
                PdoDirection::Receive,
                PdoNumber::P0,
                PdoCobId::standard(0x201),
                &m
            )
        )
        .is_err());
    r.handle_timeout(Timestamp::from_millis(2000));
    assert!(matches!(
        r.poll_event(),
        Some(ReconfigEvent::Failed {
            step: 0,
            code: AbortCode::SdoProtocolTimedOut,
            origin: AbortOrigin::Local,
            ..
        })
    ));
    assert_eq!(r.poll_transmit().map(|f| f.data()[0]), Some(0x80));
}
