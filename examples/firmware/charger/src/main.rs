//! A Delta-Q style CiA 419 charger at node 10 (battery module at node 1) as
//! Cortex-M4 firmware: the crate's `deltaq::Charger` driven by the
//! `machine::Machine` contract loop from the CAN mailbox and the timer of
//! `canopen_codec_firmware`, with its power stage's measurements read from
//! sensor registers into its charge control (`deltaq::charge`) and the
//! set points it gives written to the output stage's registers. Built to prove the footprint (`bash examples/firmware/size.sh`)
//! and run on an emulated Cortex-M4 against python-canopen
//! (`examples/firmware/emulate.py`, which also measures the stack); the
//! charger's state lives in the static `CHARGER_STATE`, whose size the
//! symbol table gives.

#![no_std]
#![no_main]

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use canopen_codec::deltaq::charge::{ChargeAlgorithm, PowerStage, StageFaults};
use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::machine::Machine;
use canopen_codec::{NodeId, Timestamp};
use canopen_codec_firmware::{read_register, write_register, Can, Clock};
use cortex_m_rt::entry;

/// Sensor block: output current in 1/256 A.
const SENSOR_CURRENT: usize = 0x4001_2400;
/// Sensor block: battery voltage in 1/256 V.
const SENSOR_VOLTAGE: usize = 0x4001_2404;
/// Sensor block: AC line voltage in 1/256 V.
const SENSOR_AC_VOLTAGE: usize = 0x4001_2408;
/// Sensor block: the stage's hardware fault flags (bit n: F-0-0-(n+1)).
const SENSOR_FAULTS: usize = 0x4001_241C;
/// Output stage: write 1 to stop charging (the EMCY policy's reaction).
const OUTPUT_STOP: usize = 0x4001_2410;
/// Output stage: the current set point, mA (0: output off).
const OUTPUT_CURRENT: usize = 0x4001_2414;
/// Output stage: the voltage set point, mV (0: output off).
const OUTPUT_VOLTAGE: usize = 0x4001_2418;
/// The power stage is measured this often (microseconds).
const MEASURE_US: u64 = 100_000;

/// Node 10, the Delta-Q default.
const CHARGER_NODE: NodeId = match NodeId::new(10) {
    Some(node) => node,
    None => NodeId::MIN,
};

/// The algorithms this charger has (2241h selects them): a 48 V flooded
/// lead-acid cycle and its float algorithm.
static ALGORITHMS: [ChargeAlgorithm; 2] = {
    const CYCLE: ChargeAlgorithm = ChargeAlgorithm::lead_acid(1, "lead acid 48 V", 24, 25_000);
    [CYCLE, ChargeAlgorithm::float_of(3, "float 48 V", &CYCLE)]
};

/// Events and frames the charger's queues hold. Two are exact, not lossy,
/// because the loop below makes one call a turn (`handle_frame` or
/// `handle_timeout`; `update` queues neither) and drains both queues after
/// it:
///
/// - Frames: the queue holds only EMCYs (the boot-up message, heartbeats,
///   SDO server responses, the SDO client's requests and TPDOs have slots of
///   their own; this build has no SYNC, TIME or guarding). A call queues at
///   most two: `handle_frame` one EMCY of the profile (E-0-4-2 for a 1000h
///   that is not 418, E-0-3-0 for an abort, or the error reset when the
///   pairing is done: one SDO answer ends one step) and one of the core
///   (8210h for an RPDO of the wrong length: a frame matches one RPDO), both
///   only for an RPDO the master set to the module's SDO response
///   identifier 581h and a short answer; NMT commands, heartbeats, the
///   module's EMCYs and SDO requests queue none. `handle_timeout` one: the
///   battery module's loss (E-0-3-2, and its SDO transfer ends silently),
///   the module taken as gone (E-0-3-0: never in the call of the loss,
///   at the earliest the next turn) or else the client's timeout (E-0-3-0).
/// - Events: a call reports at most two with the firmware's 1016h (one
///   consumer, the battery module): NMT reset (the reset, then the state
///   change); an RPDO and the heartbeat or SDO answer on the same
///   identifier; a timeout's loss of the module (or the client's timeout)
///   and the SDO server's own timeout; the module gone and the change to
///   pre-operational it makes. Two calls can report three: the module gone
///   in the same call as the SDO server's own timeout (a master's transfer
///   left open 2000 ms before, to the microsecond), and a 1016h a master
///   extends by SDO to four nodes can lose four at once. Events are
///   informational: a full queue drops its oldest and counts it (the
///   back-pressure rule; the frames still go out, as the test shows), and
///   the one event acted on below, the module's EMCY, is the last its call
///   reports, so it is never the one dropped.
///
/// The crate's test `tests/devices/charger_queue_capacity.rs` drives both worst
/// cases and fails with one slot fewer.
const QUEUE_CAPACITY: usize = 2;

/// The charger's whole state (in .bss; its size is the RAM the node needs).
#[no_mangle]
static mut CHARGER_STATE: MaybeUninit<Charger<QUEUE_CAPACITY>> = MaybeUninit::uninit();

/// Builds the charger in its static (`Charger::new_in`: the charger is
/// written there and its power-on values are loaded in place, not built
/// on the stack and moved). Not inlined: the temporaries of the
/// construction live in this function's stack frame, which is gone when
/// the loop in `main` runs (inlined, they stayed on the stack for good).
#[inline(never)]
fn init() -> &'static mut Charger<QUEUE_CAPACITY> {
    let mut config = ChargerConfig::new(CHARGER_NODE, NodeId::MIN);
    config.charge.algorithms = &ALGORITHMS;
    // SAFETY: `init` runs once, from `main`, and is the only code that
    // touches the static; the reference is the only one ever made.
    Charger::new_in(unsafe { &mut *addr_of_mut!(CHARGER_STATE) }, config)
}

#[entry]
fn main() -> ! {
    let charger = init();
    let mut can = Can;
    let mut clock = Clock::default();
    charger.boot(clock.now());
    let mut measure_at = Timestamp::ZERO;
    loop {
        let now = clock.now();
        // The contract loop (`machine::Machine`), one call a turn and the
        // queues drained after it ([`QUEUE_CAPACITY`]): the due timers
        // first (then their deadlines are ahead, so the next turn takes
        // the received frame: neither starves the other); a turn with
        // neither measures the power stage (every `MEASURE_US`), which
        // adds at most one EMCY (a charge alarm) like the others.
        if charger.poll_timeout().is_some_and(|due| due <= now) {
            charger.handle_timeout(now);
        } else if let Some(frame) = can.receive() {
            charger.handle_frame(now, &frame);
        } else if now >= measure_at {
            measure_at = now.add_micros(MEASURE_US);
            // Q8 (1/256) registers to milli-units.
            let milli = |register| read_register(register).saturating_mul(125) / 32;
            let stage = PowerStage {
                ac_mv: milli(SENSOR_AC_VOLTAGE),
                // Two's complement: a reversed battery reads negative.
                voltage_mv: (read_register(SENSOR_VOLTAGE) as i32).saturating_mul(125) / 32,
                current_ma: milli(SENSOR_CURRENT),
                temperature_c: 25,
                faults: StageFaults::from_bits_truncate(read_register(SENSOR_FAULTS) as u8),
            };
            charger.handle_power_stage(now, stage);
            let set = charger.set_points();
            write_register(OUTPUT_CURRENT, set.current_ma);
            write_register(OUTPUT_VOLTAGE, set.voltage_mv);
        }
        while let Some(frame) = charger.poll_transmit() {
            can.transmit(&frame);
        }
        while let Some(event) = charger.poll_event() {
            if let ChargerEvent::BatteryEmcy { reaction, .. } = event {
                // The Delta-Q policy's answer to the module's EMCY.
                write_register(OUTPUT_STOP, u32::from(reaction.stops_charging()));
            }
        }
    }
}
