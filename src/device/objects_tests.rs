use super::*;
use std::vec::Vec;

fn comm() -> CommObjects {
    let mut c = CommObjects::new(NodeId::new(5).unwrap());
    c.device_type = 0x0004_01A2;
    c.device_name = "node five";
    c.heartbeat_ms = 1000;
    c.identity = Identity {
        vendor_id: 1,
        product_code: 2,
        revision_number: 3,
        serial_number: 4,
    };
    #[cfg(feature = "heartbeat-consumer")]
    c.set_consumers(&[
        ConsumerEntry {
            node: 1,
            time_ms: 2000,
        },
        ConsumerEntry::default(),
    ]);
    c
}

fn read(od: &mut impl ObjectDictionary, index: u16, sub: u8) -> Result<Vec<u8>, AbortCode> {
    let len = od.info(index, sub)?.len;
    let mut buf = std::vec![0u8; len];
    let n = od.read(index, sub, 0, &mut buf)?;
    assert_eq!(n, len, "{index:04X}h:{sub} read length");
    Ok(buf)
}

/// Writes a 32-bit value (little-endian) to `index`/`sub`.
fn write_u32(
    od: &mut impl ObjectDictionary,
    index: u16,
    sub: u8,
    value: u32,
) -> Result<(), AbortCode> {
    write(od, index, sub, &value.to_le_bytes())
}

fn write(
    od: &mut impl ObjectDictionary,
    index: u16,
    sub: u8,
    data: &[u8],
) -> Result<(), AbortCode> {
    od.write(index, sub, 0, data)?;
    od.finish_write(index, sub, data.len())
}

/// The table of the module docs, row by row: (index, sub, access, value).
#[test]
fn every_row_of_the_table() {
    use Access::{Const, ReadOnly as Ro, ReadWrite as Rw};
    let rows: &[(u16, u8, Access, &[u8])] = &[
        (0x1000, 0, Const, &[0xA2, 0x01, 0x04, 0x00]),
        (0x1001, 0, Ro, &[0]),
        (0x1003, 0, Rw, &[0]),
        (0x1005, 0, Rw, &[0x80, 0, 0, 0]),
        (0x1006, 0, Rw, &[0, 0, 0, 0]),
        (0x1007, 0, Rw, &[0, 0, 0, 0]),
        (0x1008, 0, Const, b"node five"),
        (0x100C, 0, Rw, &[0, 0]),
        (0x100D, 0, Rw, &[0]),
        (0x1012, 0, Rw, &[0x00, 0x01, 0, 0]),
        (0x1016, 0, Const, &[2]),
        (0x1016, 1, Rw, &[0xD0, 0x07, 0x01, 0x00]),
        (0x1016, 2, Rw, &[0, 0, 0, 0]),
        (0x1017, 0, Rw, &[0xE8, 0x03]),
        (0x1018, 0, Ro, &[4]),
        (0x1018, 1, Ro, &[1, 0, 0, 0]),
        (0x1018, 2, Ro, &[2, 0, 0, 0]),
        (0x1018, 3, Ro, &[3, 0, 0, 0]),
        (0x1018, 4, Ro, &[4, 0, 0, 0]),
        (0x1019, 0, Rw, &[0]),
        (0x1200, 0, Ro, &[2]),
        (0x1200, 1, Ro, &[0x05, 0x06, 0, 0]),
        (0x1200, 2, Ro, &[0x85, 0x05, 0, 0]),
    ];
    let mut c = comm();
    for &(index, sub, access, value) in rows {
        // Rows of the services a build can leave out: absent without them.
        // An object of a service left out does not exist.
        let of_sync_time = matches!(index, 0x1006 | 0x1012);
        let of_guarding = matches!(index, 0x100C | 0x100D);
        let of_consumer = index == 0x1016;
        let present = (cfg!(feature = "sync-time") || !of_sync_time)
            && (cfg!(feature = "guarding") || !of_guarding)
            && (cfg!(feature = "heartbeat-consumer") || !of_consumer);
        if !present {
            assert_eq!(
                c.info(index, sub),
                Err(AbortCode::ObjectDoesNotExist),
                "{index:04X}h:{sub}"
            );
            assert_eq!(
                write(&mut c, index, sub, value),
                Err(AbortCode::ObjectDoesNotExist),
                "{index:04X}h:{sub}"
            );
            continue;
        }
        assert_eq!(
            c.info(index, sub).unwrap().access,
            access,
            "{index:04X}h:{sub}"
        );
        assert_eq!(
            read(&mut c, index, sub).unwrap(),
            value,
            "{index:04X}h:{sub}"
        );
        if !access.is_writable() {
            assert_eq!(
                write(&mut c, index, sub, value),
                Err(AbortCode::WriteOfReadOnlyObject),
                "{index:04X}h:{sub}"
            );
        }
    }
    for (index, sub) in [
        (0x1000, 1),
        (0x1016, 3),
        (0x1018, 5),
        (0x1200, 3),
        (0x1008, 1),
        (0x1003, 11),
    ] {
        // Without the heartbeat consumer 1016h is not there at all.
        let want = if index == 0x1016 && !cfg!(feature = "heartbeat-consumer") {
            AbortCode::ObjectDoesNotExist
        } else {
            AbortCode::SubIndexDoesNotExist
        };
        assert_eq!(c.info(index, sub), Err(want), "{index:04X}h:{sub}");
    }
    // 1010h/1011h (feature `store`): sub 0 = 3, subs 1-3; nothing above.
    if cfg!(feature = "store") {
        assert_eq!(c.info(0x1010, 4), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(c.info(0x1011, 4), Err(AbortCode::SubIndexDoesNotExist));
    } else {
        assert_eq!(c.info(0x1010, 0), Err(AbortCode::ObjectDoesNotExist));
    }
    assert_eq!(c.info(0x1013, 0), Err(AbortCode::ObjectDoesNotExist));
    #[cfg(feature = "heartbeat-consumer")]
    {
        c.set_consumers(&[]);
        assert_eq!(c.info(0x1016, 0), Err(AbortCode::ObjectDoesNotExist));
    }
}

#[test]
fn error_history_newest_first_last_ten() {
    let mut c = comm();
    assert_eq!(
        c.read(0x1003, 1, 0, &mut [0; 4]),
        Err(AbortCode::NoDataAvailable)
    );
    assert_eq!(c.info(0x1003, 1).unwrap().len, 4);
    for i in 1..=12u16 {
        c.push_error(ErrorFieldEntry {
            code: crate::emcy::ErrorCode(i),
            info: 0,
        });
    }
    assert_eq!(c.errors(), &[12, 11, 10, 9, 8, 7, 6, 5, 4, 3]);
    assert_eq!(read(&mut c, 0x1003, 0).unwrap(), [10]);
    assert_eq!(read(&mut c, 0x1003, 1).unwrap(), 12u32.to_le_bytes());
    assert_eq!(read(&mut c, 0x1003, 10).unwrap(), 3u32.to_le_bytes());
    assert_eq!(write(&mut c, 0x1003, 0, &[3]), Err(AbortCode::InvalidValue));
    assert_eq!(c.errors().len(), 10);
    assert_eq!(write(&mut c, 0x1003, 0, &[0]), Ok(()));
    assert!(c.errors().is_empty());
    assert_eq!(
        write(&mut c, 0x1003, 1, &[0; 4]),
        Err(AbortCode::WriteOfReadOnlyObject)
    );
}

#[test]
fn writes_and_their_checks() {
    let mut c = comm();
    assert_eq!(write(&mut c, 0x1017, 0, &[0xF4, 0x01]), Ok(()));
    assert_eq!(c.heartbeat_ms, 500);
    assert_eq!(
        write(&mut c, 0x1017, 0, &[1]),
        Err(AbortCode::DataTypeLengthTooLow)
    );
    assert_eq!(
        write(&mut c, 0x1017, 0, &[1, 2, 3]),
        Err(AbortCode::DataTypeLengthTooHigh)
    );
    // 1016h sub 2 watching node 1 as well: refused (CiA 301: one entry per node).
    #[cfg(feature = "heartbeat-consumer")]
    {
        assert_eq!(
            write_u32(&mut c, 0x1016, 2, 0x0001_0064),
            Err(AbortCode::GeneralParameterIncompatibility)
        );
        assert_eq!(write_u32(&mut c, 0x1016, 2, 0x0002_0064), Ok(()));
        assert_eq!(
            c.consumers()[1],
            ConsumerEntry {
                node: 2,
                time_ms: 100
            }
        );
        // A disabled duplicate is fine.
        assert_eq!(write_u32(&mut c, 0x1016, 2, 0x0001_0000), Ok(()));
        assert_eq!(
            write(&mut c, 0x1016, 0, &[2]),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
    }
    crate::od::fixture::assert_aborted_write_changes_nothing(&mut c, 0x1017, 0, 2);
    assert_eq!(c.heartbeat_ms, 500);
}

#[test]
fn error_field_formats() {
    let emcy = Emergency {
        code: crate::emcy::ErrorCode(0x8130),
        register: ErrorRegister::GENERIC,
        manufacturer: [0x20, 0x80, 0, 0, 0],
    };
    assert_eq!(
        ErrorFieldFormat::LittleEndianInfo.entry(&emcy).to_u32(),
        0x8020_8130
    );
    // Delta-Q: E-0-3-2 (8020h) byte-swapped in the high word.
    assert_eq!(
        ErrorFieldFormat::SwappedInfo.entry(&emcy).to_u32(),
        0x2080_8130
    );
}

#[test]
fn layered_dictionary_routes_by_index() {
    #[derive(Clone)]
    struct App(u8);
    impl ObjectDictionary for App {
        fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
            match (index, sub) {
                (0x2000, 0) | (0x1F00, 0) => Ok(ObjectInfo::fixed(Access::ReadWrite, 1)),
                _ => Err(AbortCode::ObjectDoesNotExist),
            }
        }
        fn read(&mut self, _: u16, _: u8, _: usize, buf: &mut [u8]) -> Result<usize, AbortCode> {
            if let Some(b) = buf.first_mut() {
                *b = self.0;
            }
            Ok(1)
        }
        fn write(&mut self, _: u16, _: u8, _: usize, data: &[u8]) -> Result<(), AbortCode> {
            self.0 = data.first().copied().unwrap_or(0);
            Ok(())
        }
    }
    let mut od = DeviceObjects {
        comm: comm(),
        app: App(7),
    };
    assert_eq!(read(&mut od, 0x2000, 0).unwrap(), [7]);
    assert_eq!(
        read(&mut od, 0x1F00, 0).unwrap(),
        [7],
        "other 1xxxh objects are the application's"
    );
    assert_eq!(read(&mut od, 0x1001, 0).unwrap(), [0]);
    assert_eq!(write(&mut od, 0x2000, 0, &[9]), Ok(()));
    assert_eq!(od.app.0, 9);
    assert_eq!(od.info(0x3000, 0), Err(AbortCode::ObjectDoesNotExist));
}

#[test]
fn hostile_reads_and_writes_never_panic() {
    let mut c = comm();
    let mut buf = [0u8; 8];
    for index in [
        0x1000u16, 0x1003, 0x1008, 0x1016, 0x1017, 0x1018, 0x1200, 0xFFFF, 0,
    ] {
        for sub in [0u8, 1, 4, 5, 10, 11, 0xFF] {
            let _ = c.read(index, sub, usize::MAX, &mut buf);
            let _ = c.read(index, sub, 3, &mut []);
            let _ = c.write(index, sub, usize::MAX, &[1, 2, 3]);
            let _ = c.write(index, sub, 0, &[0; 9]);
            let _ = c.finish_write(index, sub, usize::MAX);
        }
    }
}

/// Without the SYNC producer (feature `sync-time`) 1005h's generate bit is
/// refused and 1006h and 1012h are absent; without node guarding (feature
/// `guarding`) 100Ch and 100Dh are.
#[cfg(not(all(feature = "guarding", feature = "sync-time")))]
#[test]
fn objects_of_the_services_left_out() {
    let mut c = comm();
    let generate = write_u32(&mut c, 0x1005, 0, 0x4000_0080);
    let cycle = c.info(0x1006, 0);
    let time = c.info(0x1012, 0);
    if cfg!(feature = "sync-time") {
        assert_eq!(
            (generate, cycle.is_ok(), time.is_ok()),
            (Ok(()), true, true)
        );
    } else {
        assert_eq!(generate, Err(AbortCode::InvalidValue));
        assert!(!c.sync_cob_id.generates());
        assert_eq!(cycle, Err(AbortCode::ObjectDoesNotExist));
        assert_eq!(time, Err(AbortCode::ObjectDoesNotExist));
        // The consumer's objects stay.
        assert_eq!(write_u32(&mut c, 0x1005, 0, 0x81), Ok(()));
        assert_eq!(write_u32(&mut c, 0x1007, 0, 2_000), Ok(()));
        assert_eq!(write(&mut c, 0x1019, 0, &[10]), Ok(()));
    }
    for index in [0x100C, 0x100D] {
        let want = if cfg!(feature = "guarding") {
            Ok(())
        } else {
            Err(AbortCode::ObjectDoesNotExist)
        };
        assert_eq!(c.info(index, 0).map(|_| ()), want, "{index:04X}h");
        assert_eq!(read(&mut c, index, 0).map(|_| ()), want, "{index:04X}h");
    }
}

/// 100Ch, 100Dh, 1005h, 1006h, 1007h, 1012h and 1019h: what may be written.
#[cfg(all(feature = "guarding", feature = "sync-time"))]
#[test]
fn guarding_sync_and_time_objects() {
    let mut c = comm();
    assert_eq!(write(&mut c, 0x100C, 0, &[0xF4, 0x01]), Ok(()));
    assert_eq!(write(&mut c, 0x100D, 0, &[3]), Ok(()));
    assert_eq!((c.guard_time_ms, c.life_time_factor), (500, 3));
    assert_eq!(
        write(&mut c, 0x100D, 0, &[3, 0]),
        Err(AbortCode::DataTypeLengthTooHigh)
    );
    // 1019h: 0 and 2..=240 while 1006h is 0; 1 and 241..=255 reserved.
    for v in 0..=255u8 {
        let want = if v == 0 || (2..=240).contains(&v) {
            Ok(())
        } else {
            Err(AbortCode::InvalidValue)
        };
        assert_eq!(write(&mut c, 0x1019, 0, &[v]), want, "1019h = {v}");
    }
    assert_eq!(write(&mut c, 0x1019, 0, &[10]), Ok(()));
    assert_eq!(write_u32(&mut c, 0x1006, 0, 10_000), Ok(()));
    assert_eq!(
        write(&mut c, 0x1019, 0, &[5]),
        Err(AbortCode::DataCannotBeStoredDeviceState)
    );
    assert_eq!((c.cycle_period_us, c.sync_counter_overflow), (10_000, 10));
    assert_eq!(write_u32(&mut c, 0x1007, 0, 2_000), Ok(()));
    assert_eq!(c.sync_window_us, 2_000);
    // 1005h: the generate bit; the identifier cannot move while generating.
    assert_eq!(write_u32(&mut c, 0x1005, 0, 0x4000_0080), Ok(()));
    assert!(c.sync_cob_id.generates());
    assert_eq!(
        write_u32(&mut c, 0x1005, 0, 0x4000_0081),
        Err(AbortCode::InvalidValue)
    );
    assert_eq!(write_u32(&mut c, 0x1005, 0, 0x0000_0081), Ok(()));
    assert_eq!(write_u32(&mut c, 0x1005, 0, 0x4000_0081), Ok(()));
    assert_eq!(
        write_u32(&mut c, 0x1005, 0, 0x0000_0800),
        Err(AbortCode::InvalidValue)
    );
    // 1012h: consume and produce bits, a valid identifier.
    assert_eq!(write_u32(&mut c, 0x1012, 0, 0xC000_0100), Ok(()));
    assert!(c.time_cob_id.consumes() && c.time_cob_id.produces());
    assert_eq!(
        write_u32(&mut c, 0x1012, 0, 0x0000_1000),
        Err(AbortCode::InvalidValue)
    );
}

/// Without the heartbeat consumer (feature `heartbeat-consumer`) 1016h
/// does not exist: every sub-index is 06020000h to read, to write and to
/// ask about, as for any absent object.
#[cfg(not(feature = "heartbeat-consumer"))]
#[test]
fn no_1016h_without_the_heartbeat_consumer() {
    let mut c = comm();
    assert!(!c.has_object(0x1016));
    for sub in [0u8, 1, 2, 127, 0xFF] {
        assert_eq!(c.info(0x1016, sub), Err(AbortCode::ObjectDoesNotExist));
        assert_eq!(
            read(&mut c, 0x1016, sub),
            Err(AbortCode::ObjectDoesNotExist)
        );
        let entry = 0x0001_07D0u32.to_le_bytes();
        assert_eq!(
            write(&mut c, 0x1016, sub, &entry),
            Err(AbortCode::ObjectDoesNotExist)
        );
    }
    // The producer's 1017h is still there.
    assert_eq!(read(&mut c, 0x1017, 0), Ok(std::vec![0xE8, 0x03]));
}

/// Every entry the device core serves is a row of the communication table
/// (od::comm) with the access it is served with, and a fixed-size one has
/// the row's size; the sub-index 0 of each of its ARRAYs and RECORDs
/// reads the row's power-on value.
#[test]
fn every_served_entry_is_a_row_of_the_communication_table() {
    let mut c = comm();
    c.push_error(ErrorFieldEntry {
        code: crate::emcy::ErrorCode::GENERIC,
        info: 0,
    });
    let mut served = 0;
    for index in 0x1000..=0x1FFFu16 {
        for sub in 0..=u8::MAX {
            let Ok(info) = c.info(index, sub) else {
                continue;
            };
            served += 1;
            let row = comm::find(Address::new(index, sub))
                .unwrap_or_else(|| panic!("{index:04X}h:{sub} has no row"));
            assert_eq!(info.access, row.access, "{index:04X}h:{sub} access");
            if row.size() > 0 {
                assert_eq!(info.len, usize::from(row.size()), "{index:04X}h:{sub} size");
            }
            if sub == 0 && row.compound.is_some() && index != PRE_DEFINED_ERROR_FIELD {
                let want = row.default.to_le_bytes()[..1].to_vec();
                #[cfg(feature = "heartbeat-consumer")]
                let want = if index == CONSUMER_HEARTBEAT_TIME {
                    std::vec![c.consumer_slots]
                } else {
                    want
                };
                assert_eq!(read(&mut c, index, 0).unwrap(), want, "{index:04X}h:0");
            }
        }
    }
    assert!(served >= 20, "only {served} entries served");
}
