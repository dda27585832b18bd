//! A Delta-Q style CiA 419 charger at node 10 (battery module at node 1) as
//! Cortex-M4 firmware: the crate's `deltaq::Charger` driven by the
//! `machine::Machine` contract loop from the CAN mailbox and the timer of
//! `canopen_codec_firmware`, with its measurements read from sensor
//! registers. Built to prove the footprint (`bash examples/firmware/size.sh`)
//! and run on an emulated Cortex-M4 against python-canopen
//! (`examples/firmware/emulate.py`, which also measures the stack); the
//! charger's state lives in the static `CHARGER_STATE`, whose size the
//! symbol table gives.

#![no_std]
#![no_main]

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use canopen_codec::deltaq::{Charger, ChargerConfig, ChargerEvent};
use canopen_codec::machine::Machine;
use canopen_codec::NodeId;
use canopen_codec_firmware::{read_register, run_once, write_register, Can, Clock};
use cortex_m_rt::entry;

/// Sensor block: output current in 1/256 A.
const SENSOR_CURRENT: usize = 0x4001_2400;
/// Sensor block: battery voltage in 1/256 V.
const SENSOR_VOLTAGE: usize = 0x4001_2404;
/// Sensor block: AC line voltage in 1/256 V.
const SENSOR_AC_VOLTAGE: usize = 0x4001_2408;
/// Sensor block: charger status bits.
const SENSOR_STATUS: usize = 0x4001_240C;
/// Output stage: write 1 to stop charging (the EMCY policy's reaction).
const OUTPUT_STOP: usize = 0x4001_2410;

/// Node 10, the Delta-Q default.
const CHARGER_NODE: NodeId = match NodeId::new(10) {
    Some(node) => node,
    None => NodeId::MIN,
};

/// Events and frames the charger's queues hold: the loop below drains both
/// after every call, so a few are enough (a full queue drops its oldest
/// entry and counts it; the protocol does not depend on it).
const QUEUE_CAPACITY: usize = 4;

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
    let config = ChargerConfig::new(CHARGER_NODE, NodeId::MIN);
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
    loop {
        let now = clock.now();
        charger.update(now, |o| {
            o.charging_current = read_register(SENSOR_CURRENT) as u16;
            o.battery_voltage_q8 = read_register(SENSOR_VOLTAGE) as u16;
            o.ac_voltage = read_register(SENSOR_AC_VOLTAGE) as u16;
            o.charger_status = read_register(SENSOR_STATUS) as u8;
        });
        run_once(charger, &mut can, now);
        while let Some(event) = charger.poll_event() {
            if let ChargerEvent::BatteryEmcy { reaction, .. } = event {
                // The Delta-Q policy's answer to the module's EMCY.
                write_register(OUTPUT_STOP, u32::from(reaction.stops_charging()));
            }
        }
    }
}
