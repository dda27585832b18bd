//! The charge control's timer slots: the CAN hold-off and the end of the
//! timed phase running, each firing at its time and not before, stopped
//! when what armed it is over, and run by any input that comes after it.

use super::tests::{bms, control, events, pack, s};
use super::*;

/// A BMS present and ready that asks for equalize (4201h bit 0).
fn equalizing_bms() -> BusInputs {
    BusInputs {
        external_override: ExternalOverride::EQUALIZE,
        ..bms(10)
    }
}

#[test]
fn each_timed_phase_ends_at_its_own_deadline_and_not_before() {
    let mut c = control(OperatingMode::LocalOverride);
    c.handle_bus(s(0), equalizing_bms());
    c.handle_power_stage(s(0), pack(50, 10));
    // Bulk has no end of its own.
    assert_eq!((c.phase(), c.poll_timeout()), (ChargePhase::Bulk, None));
    c.handle_power_stage(s(2), pack(59, 10));
    // Absorption: its safety timer, 4 h.
    assert_eq!(c.phase(), ChargePhase::Absorption);
    assert_eq!(c.poll_timeout(), Some(s(2 + 4 * 3600)));
    c.handle_power_stage(s(70), pack(59, 1));
    // Equalize: 2 h.
    assert_eq!(c.phase(), ChargePhase::Equalize);
    let end = s(70 + 2 * 3600);
    assert_eq!(c.poll_timeout(), Some(end));
    c.handle_timeout(Timestamp::from_micros(end.as_micros() - 1));
    assert_eq!(
        (c.phase(), c.poll_timeout()),
        (ChargePhase::Equalize, Some(end))
    );
    c.handle_timeout(end);
    // Rest: a minute, then float; the BMS still asks for equalize, so a
    // new equalize starts at once, with a deadline of its own.
    assert_eq!(c.phase(), ChargePhase::Rest);
    assert_eq!(c.poll_timeout(), Some(s(70 + 2 * 3600 + 60)));
    c.handle_timeout(s(70 + 2 * 3600 + 59));
    assert_eq!(c.phase(), ChargePhase::Rest);
    let rested = 70 + 2 * 3600 + 60;
    c.handle_timeout(s(rested));
    let again = Some(s(rested + 2 * 3600));
    assert_eq!(
        (c.phase(), c.poll_timeout()),
        (ChargePhase::Equalize, again)
    );
}

#[test]
fn a_phase_left_early_leaves_no_deadline_behind() {
    let mut c = control(OperatingMode::Local);
    c.handle_power_stage(s(0), pack(48, 0));
    assert_eq!(c.poll_timeout(), Some(s(10)));
    // A BMS heard during the hold-off stops it.
    c.handle_bus(
        s(5),
        BusInputs {
            battery_present: true,
            battery_status: 0,
            ..BusInputs::none(72_000)
        },
    );
    assert_eq!((c.phase(), c.poll_timeout()), (ChargePhase::Idle, None));
    c.handle_bus(s(6), equalizing_bms());
    c.handle_power_stage(s(7), pack(59, 20));
    assert_eq!(c.phase(), ChargePhase::Absorption);
    assert_eq!(c.poll_timeout(), Some(s(7 + 4 * 3600)));
    // AC lost: the cycle is over, and so is its timer.
    c.handle_power_stage(s(8), PowerStage::OFF);
    assert_eq!((c.phase(), c.poll_timeout()), (ChargePhase::Idle, None));
    c.handle_timeout(s(7 + 4 * 3600));
    assert_eq!(c.phase(), ChargePhase::Idle);
}

#[test]
fn an_input_after_a_deadline_runs_its_timer() {
    // No timeout call at the end of the hold-off: the next measurement
    // finds it over and charges, and no timer is left at or before it.
    let mut c = control(OperatingMode::Local);
    c.handle_power_stage(s(0), pack(48, 0));
    assert_eq!(c.phase(), ChargePhase::HoldOff);
    c.handle_power_stage(s(12), pack(48, 25));
    assert_eq!((c.phase(), c.poll_timeout()), (ChargePhase::Bulk, None));
    // Extra timeout calls change nothing.
    c.handle_timeout(s(12));
    c.handle_timeout(s(13));
    assert_eq!(c.phase(), ChargePhase::Bulk);
}

#[test]
fn it_is_driven_through_the_machine_contract() {
    let mut c = control(OperatingMode::Local);
    c.handle_power_stage(s(0), pack(48, 0));
    // One timer run (the hold-off at 10 s), no frame sent.
    let mut sent = 0;
    let runs = crate::machine::drive_timers(&mut c, s(100), |_, _| sent += 1);
    assert_eq!((runs, sent, c.phase()), (1, 0, ChargePhase::Bulk));
    // A frame changes nothing: the bus inputs come decoded.
    let heartbeat = CanFrame::standard(0x701, &[0x05]).unwrap();
    c.handle_frame(s(101), &heartbeat);
    assert_eq!(
        (c.phase(), c.poll_transmit(), c.frames_dropped()),
        (ChargePhase::Bulk, None, 0)
    );
    let phases = events(&mut c);
    assert_eq!(
        phases,
        [
            ChargeEvent::Phase {
                from: ChargePhase::Idle,
                to: ChargePhase::HoldOff
            },
            ChargeEvent::Phase {
                from: ChargePhase::HoldOff,
                to: ChargePhase::Bulk
            },
        ]
    );
    assert_eq!(c.events_dropped(), 0);
}
