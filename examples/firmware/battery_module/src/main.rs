//! A CiA 418 battery module at node 1 as Cortex-M4 firmware: the crate's
//! `cia418::BatteryModule` driven by the `machine::Machine` contract loop
//! from the CAN mailbox and the timer of `canopen_codec_firmware`, with
//! its measurements read from sensor registers. Built to prove the
//! footprint (`bash examples/firmware/size.sh`) and run on an emulated
//! Cortex-M4 against python-canopen (`examples/firmware/emulate.py`, which
//! also measures the stack); the module's state lives in the static
//! `BATTERY_MODULE_STATE`, whose size the symbol table gives.

#![no_std]
#![no_main]

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use canopen_codec::cia418::{
    BatteryModule, BatteryModuleConfig, BatteryStatus, BatteryVoltage, PackedStringObject,
    StateOfCharge, Temperature,
};
use canopen_codec::machine::Machine;
use canopen_codec::NodeId;
use canopen_codec_firmware::{read_register, run_once, Can, Clock};
use cortex_m_rt::entry;

/// Sensor block: battery voltage in 1/1024 V (the 6060h unit).
const SENSOR_VOLTAGE: usize = 0x4001_2400;
/// Sensor block: temperature in 1/8 degC (the 6010h unit), signed.
const SENSOR_TEMPERATURE: usize = 0x4001_2404;
/// Sensor block: state of charge in percent.
const SENSOR_SOC: usize = 0x4001_2408;
/// Sensor block: bit 0 ready to charge; bit 8 temperature sensor fault.
const SENSOR_STATUS: usize = 0x4001_240C;

/// Events and frames the module's queues hold. Two frames are exact, not
/// lossy: the frame queue holds only EMCYs here (the boot-up message,
/// heartbeats, SDO responses and TPDOs have slots of their own; this build
/// has no SYNC or TIME producer), and between two drains (`run_once` below
/// empties `poll_transmit`) one turn of the loop queues at most two:
/// `set_temperature_sensor_fault` one (EMCY 5010h or its reset 0000h, only
/// when the fault changes), `handle_frame` one (EMCY 8210h for an RPDO of
/// the wrong length: a frame matches one RPDO; NMT, SDO and resets queue
/// none), `handle_timeout` none (the crate's test
/// `tests/devices/module_queue_capacity.rs` drives that worst case). Events are
/// informational: a full event queue drops its oldest and counts it (the
/// back-pressure rule).
const QUEUE_CAPACITY: usize = 2;

/// The module's whole state (in .bss; its size is the RAM the node needs).
#[no_mangle]
static mut BATTERY_MODULE_STATE: MaybeUninit<BatteryModule<QUEUE_CAPACITY>> = MaybeUninit::uninit();

/// Builds the module in its static (`BatteryModule::new_in`: the module is
/// written there and its power-on values loaded in place, not built on the
/// stack and copied in). Not inlined: the temporaries of the construction
/// live in this function's stack frame, which is gone when the loop in
/// `main` runs (inlined, they stayed on the stack for good).
#[inline(never)]
fn init() -> &'static mut BatteryModule<QUEUE_CAPACITY> {
    let config = BatteryModuleConfig::new(NodeId::MIN);
    // SAFETY: `init` runs once, from `main`, and is the only code that
    // touches the static; the reference is the only one ever made.
    BatteryModule::new_in(unsafe { &mut *addr_of_mut!(BATTERY_MODULE_STATE) }, config)
}

#[entry]
fn main() -> ! {
    let module = init();
    let mut can = Can;
    let mut clock = Clock::default();
    let _ = module.set_text(PackedStringObject::BatterySerialNumber, "FW-0001");
    module.boot(clock.now());
    loop {
        let now = clock.now();
        let status = read_register(SENSOR_STATUS);
        module.update(now, |o| {
            o.battery_voltage = BatteryVoltage::from_raw(read_register(SENSOR_VOLTAGE));
            o.temperature = Temperature::from_raw(read_register(SENSOR_TEMPERATURE) as i16);
            o.battery_state_of_charge = StateOfCharge::from_raw(read_register(SENSOR_SOC) as u8);
            o.battery_status = BatteryStatus::from_bits_retain(status as u8);
        });
        module.set_temperature_sensor_fault(now, status & (1 << 8) != 0);
        run_once(module, &mut can, now);
        // Events are informational; a real module might log them.
        while module.poll_event().is_some() {}
    }
}
