//! The Delta-Q charge control (`deltaq::charge::ChargeControl`) under an
//! arbitrary sequence of power-stage readings, bus inputs, 2241h requests,
//! module EMCYs and time steps, in every operating mode and with an
//! arbitrary configuration. Invariants: no panic; after every call no
//! timer at or before `now` and the event queue drained without a drop
//! replays the alarms exactly; the set points never exceed the charger's
//! limits and are off without AC; in remote mode they are on only with the
//! module present, ready and asking; 6001h bit 0 and the 2006h flags agree
//! with the set points and the alarms; the charge type and indication are
//! those of the phase.
#![no_main]

use arbitrary::Arbitrary;
use canopen_codec::deltaq::charge::{
    BusInputs, ChargeAlarms, ChargeConfig, ChargeControl, ChargeEvent, ChargePhase, PowerStage,
    StageFaults,
};
use canopen_codec::deltaq::{
    AlgorithmRequest, ChargeStatusFlags, ExternalOverride, OperatingMode,
};
use canopen_codec::emcy::{Emergency, ErrorCode, ErrorRegister};
use canopen_codec::machine::Machine;
use canopen_codec::Timestamp;
use core::time::Duration;
use libfuzzer_sys::fuzz_target;

#[derive(Debug, Arbitrary)]
enum Op {
    Stage { ac_v: u16, volts_mv: i32, amps_ma: u32, temp: i16, faults: u8 },
    Bus {
        present: bool,
        status: u8,
        request: u16,
        volts_mv: u32,
        over: u8,
        target: u16,
        soc: u8,
        error: bool,
        battery_temperature: i16,
    },
    Algorithm(u32),
    Emcy(u16),
    Advance(u32),
    Jump(u64),
}

#[derive(Debug, Arbitrary)]
struct Input {
    mode: u8,
    permanent: Option<u8>,
    no_can: Option<u8>,
    hold_off_ms: u16,
    rest_ms: u16,
    max_current_ma: u32,
    max_voltage_mv: u32,
    max_power_w: u16,
    detect_mv: u16,
    derate: (i8, i8),
    ops: Vec<Op>,
}

fn check(c: &mut ChargeControl, now: Timestamp, alarms: &mut ChargeAlarms) {
    if let Some(t) = c.poll_timeout() {
        assert!(t > now, "timer {t:?} not after {now:?} in {:?}", c.phase());
    }
    let dropped = c.events_dropped();
    while let Some(e) = c.poll_event() {
        if let ChargeEvent::Alarm { alarm, active } = e {
            assert_eq!(alarm.bits().count_ones(), 1);
            if dropped == 0 {
                assert_eq!(alarms.contains(alarm), !active, "{alarm:?} {active}");
            }
            alarms.set(alarm, active);
        }
    }
    if dropped == 0 {
        assert_eq!(*alarms, c.alarms());
    }
    *alarms = c.alarms();
    let set = c.set_points();
    let config = c.config();
    if set.enabled {
        assert!(set.current_ma > 0 && set.current_ma <= config.max_current_ma);
        assert!(set.voltage_mv > 0 && set.voltage_mv <= config.max_voltage_mv);
        assert!(c.ac_present());
        assert!(!c.alarms().intersects(ChargeAlarms::STOPS_OUTPUT));
        assert!(c.phase().delivers());
        if c.mode() == OperatingMode::Remote {
            let bus = c.bus();
            assert!(bus.battery_present && bus.battery_status & 1 == 1);
            assert!(bus.current_request != 0xFFFF && !bus.bus_error);
            assert!(u64::from(set.current_ma) <= u64::from(bus.current_request) * 125 / 2);
        }
    } else {
        assert_eq!((set.current_ma, set.voltage_mv), (0, 0));
    }
    let status = c.status();
    assert_eq!(status.charger_status, u8::from(set.enabled));
    let flags = status.extended.flags;
    assert_eq!(flags.contains(ChargeStatusFlags::CHARGER_ENABLED), set.enabled);
    // 2006h separates the two kinds: an alarm bit for the E- codes, a fault
    // bit for the power stage's F-0-0-x.
    let faults = c.alarms().intersection(ChargeAlarms::FAULTS);
    assert_eq!(flags.contains(ChargeStatusFlags::ALARM_ACTIVE), c.alarms() != faults);
    assert_eq!(flags.contains(ChargeStatusFlags::FAULT_ACTIVE), !faults.is_empty());
    assert_eq!(
        flags.contains(ChargeStatusFlags::HW_SHUTDOWN),
        c.alarms().intersects(ChargeAlarms::STOPS_OUTPUT)
    );
    assert_eq!(flags.contains(ChargeStatusFlags::AC_PRESENT), c.ac_present());
    assert_eq!(flags.contains(ChargeStatusFlags::DERATING), !status.derate.is_empty());
    assert!(status.charger_soc <= 100 || status.charger_soc == 0xFF);
    if matches!(c.phase(), ChargePhase::Idle | ChargePhase::Remote | ChargePhase::Terminated) {
        assert_eq!(status.extended.to_u16() >> 8, 0, "no charge type or indication");
    }
}

fuzz_target!(|input: Input| {
    let mode = OperatingMode::ALL[usize::from(input.mode % 4)];
    let config = ChargeConfig {
        permanent_algorithm: input.permanent.map(u16::from),
        no_can_algorithm: input.no_can.map(u16::from),
        can_hold_off: Duration::from_millis(u64::from(input.hold_off_ms)),
        rest: Duration::from_millis(u64::from(input.rest_ms)),
        max_current_ma: input.max_current_ma,
        max_voltage_mv: input.max_voltage_mv,
        max_power_w: u32::from(input.max_power_w),
        battery_detect_mv: u32::from(input.detect_mv),
        derate_start_c: i16::from(input.derate.0),
        derate_stop_c: i16::from(input.derate.1),
        ..ChargeConfig::example()
    };
    let mut c = ChargeControl::new(mode, config);
    let mut now = Timestamp::ZERO;
    let mut alarms = ChargeAlarms::empty();
    for op in input.ops.into_iter().take(512) {
        match op {
            Op::Stage { ac_v, volts_mv, amps_ma, temp, faults } => {
                let stage = PowerStage {
                    ac_mv: u32::from(ac_v) * 1000,
                    voltage_mv: volts_mv,
                    current_ma: amps_ma,
                    temperature_c: temp,
                    faults: StageFaults::from_bits_truncate(faults),
                };
                c.handle_power_stage(now, stage);
            }
            Op::Bus {
                present,
                status,
                request,
                volts_mv,
                over,
                target,
                soc,
                error,
                battery_temperature,
            } => {
                let bus = BusInputs {
                    battery_present: present,
                    battery_status: status,
                    current_request: request,
                    voltage_request_mv: volts_mv,
                    external_override: ExternalOverride::from_bits_retain(over),
                    ah_target: target,
                    battery_soc: soc,
                    bus_error: error,
                    battery_temperature,
                };
                c.handle_bus(now, bus);
            }
            Op::Algorithm(raw) => c.request_algorithm(now, AlgorithmRequest::from_u32(raw)),
            Op::Emcy(code) => {
                let emcy = Emergency {
                    code: ErrorCode(code),
                    register: ErrorRegister::GENERIC,
                    manufacturer: [0; 5],
                };
                c.handle_battery_emcy(now, &emcy);
            }
            Op::Advance(us) => {
                now = now.add_micros(u64::from(us));
                c.handle_timeout(now);
            }
            Op::Jump(us) => {
                // Up to 12 days a jump; 512 jumps stay far from the end of
                // the clock, where no deadline can lie after `now`.
                now = now.add_micros(us % (1 << 40));
                c.handle_timeout(now);
            }
        }
        check(&mut c, now, &mut alarms);
    }
});
