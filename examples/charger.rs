//! A virtual Delta-Q style CiA 419 charger on a pipe: candump log lines in on
//! stdin, the frames it sends out on stdout (one candump log line per frame,
//! flushed), its events in words on stderr. It runs one
//! [`Charger`](canopen_codec::deltaq::Charger): heartbeat supervision of the
//! battery module, PDO COB-ID pairing by SDO, TPDOs, EMCYs.
//!
//! ```text
//! cargo run --example charger -- --node-id 10 --battery-node 1 [--mode local|remote] </dev/null
//! # a whole session: the module's output feeds the charger and back
//! mkfifo /tmp/c2b
//! cargo run -q --example battery_module -- --simulate --nmt-start </tmp/c2b \
//!   | cargo run -q --example charger >/tmp/c2b
//! ```
//!
//! Options: `--node-id N` (10), `--battery-node N` (1), `--mode
//! local|remote|local-override|monitoring` (local), `--no-configure` (use the
//! charger's own default COB-IDs, as the real capture does, instead of
//! reading the module's), `--self-start` (enter operational after boot
//! instead of waiting for an NMT start), `--heartbeat-ms` (1000),
//! `--battery-timeout-ms` (2000), `--tpdo-ms A,B,C,D` (the event timers
//! of TPDO 0..3; 0 sends that TPDO on events only), `--current A` and `--voltage V` (the
//! charger's 2002h / 2100h / 2101h measurements), `--linger-ms` (2000),
//! `--interface NAME` (can0), `--storage FILE` (1010h "save" and 1011h
//! "load" keep the parameters in FILE, loaded again at the next start with
//! the same file: `examples/support/storage.rs`), `--program-store
//! DIR_OR_FILE` (takes CiA 302-3 program downloads into 1F50h sub 1 and
//! writes the image there; feature `program-download`).
//!
//! Time: see `examples/support/node.rs` (shared with `battery_module`).

#[path = "support/bus.rs"]
mod bus;
#[path = "support/node.rs"]
mod node;
#[cfg(feature = "program-download")]
#[path = "support/program_store.rs"]
mod program_store;
#[path = "support/storage.rs"]
mod storage;

use std::process::ExitCode;
use std::time::Duration;

use bus::PipeBus;
use canopen_codec::deltaq::{
    charger_eds, Charger, ChargerAppDictionary, ChargerConfig, ChargerEvent,
};
use canopen_codec::deltaq::{OperatingMode, Reaction};
use canopen_codec::device::DeviceEvent;
use canopen_codec::eds;
use canopen_codec::{NodeId, Timestamp};
use node::Runner;

const USAGE: &str = "usage: charger [--node-id N] [--battery-node N] [--mode local|remote|local-override|monitoring]
               [--no-configure] [--self-start] [--heartbeat-ms MS] [--battery-timeout-ms MS]
               [--tpdo-ms A,B,C,D] [--current A] [--voltage V] [--linger-ms MS] [--interface NAME]
               [--program-store DIR_OR_FILE] [--print-eds] [--storage FILE]
--storage FILE keeps what 1010h stores (restored at the next start).
--program-store takes program downloads (CiA 302-3: 1F50h sub 1, 1F51h,
1F56h, 1F57h) into DIR_OR_FILE (a directory gets program-1.bin).
--print-eds prints the charger's EDS (CiA 306) as configured by the other
options on stdout and exits.";

struct Options {
    config: ChargerConfig,
    current_a: f64,
    voltage_v: f64,
    linger: Duration,
    interface: String,
    print_eds: bool,
    storage: Option<String>,
    program_store: Option<std::path::PathBuf>,
}

fn parse_args(args: &[String]) -> Result<Option<Options>, String> {
    let node = |v: &str| {
        v.parse::<u8>()
            .ok()
            .and_then(NodeId::new)
            .ok_or(format!("'{v}' is not a node id 1..=127"))
    };
    let mut config = ChargerConfig::new(node("10")?, node("1")?);
    config.device_name = "canopen-codec charger";
    let mut o = Options {
        config,
        current_a: 0.0,
        voltage_v: 0.0,
        linger: Duration::from_millis(2000),
        interface: "can0".into(),
        print_eds: false,
        storage: None,
        program_store: None,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        let number = |v: &String| {
            v.parse::<f64>()
                .map_err(|_| format!("{a}: '{v}' is not a number"))
        };
        let ms = |v: &String| {
            v.parse::<u16>()
                .map_err(|_| format!("{a}: '{v}' is not 0..=65535 ms"))
        };
        match a.as_str() {
            "-h" | "--help" => return Ok(None),
            "--node-id" => o.config.node = node(value()?)?,
            "--battery-node" => o.config.battery = node(value()?)?,
            "--mode" => {
                o.config.mode = match value()?.as_str() {
                    "local" => OperatingMode::Local,
                    "remote" => OperatingMode::Remote,
                    "local-override" => OperatingMode::LocalOverride,
                    "monitoring" => OperatingMode::MonitoringOnly,
                    other => return Err(format!("--mode: unknown mode '{other}'")),
                }
            }
            "--no-configure" => o.config.configure_cob_ids = false,
            "--self-start" => o.config.self_start = true,
            "--print-eds" => o.print_eds = true,
            "--program-store" => o.program_store = Some(value()?.into()),
            "--heartbeat-ms" => {
                o.config.heartbeat = Duration::from_millis(u64::from(ms(value()?)?))
            }
            "--battery-timeout-ms" => {
                o.config.battery_timeout = Duration::from_millis(u64::from(ms(value()?)?));
            }
            "--tpdo-ms" => {
                let list = value()?;
                let periods: Vec<u16> = list
                    .split(',')
                    .map(|v| v.trim().parse::<u16>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| format!("--tpdo-ms: '{list}' is not four 0..=65535 ms values"))?;
                let [a, b, c, d] = periods[..] else {
                    return Err(format!("--tpdo-ms: '{list}' is not four values"));
                };
                o.config.tpdo_periods = [a, b, c, d].map(|ms| Duration::from_millis(u64::from(ms)));
            }
            "--current" => o.current_a = number(value()?)?,
            "--voltage" => o.voltage_v = number(value()?)?,
            "--linger-ms" => o.linger = Duration::from_millis(u64::from(ms(value()?)?)),
            "--interface" => o.interface = value()?.clone(),
            "--storage" => o.storage = Some(value()?.clone()),
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    if !(0.0..=255.0).contains(&o.current_a) || !(0.0..=64.0 * 4.0).contains(&o.voltage_v) {
        return Err("--current must be 0..=255 A and --voltage 0..=256 V".into());
    }
    Ok(Some(o))
}

/// An event in words for stderr (`None` for the RPDOs, which come every
/// 200 ms).
fn describe(e: &ChargerEvent) -> Option<String> {
    let words = match *e {
        ChargerEvent::Device(DeviceEvent::NmtStateChanged { from, to }) => {
            format!("event: NMT {from} -> {to}")
        }
        ChargerEvent::Device(DeviceEvent::Reset { node }) => {
            let what = if node { "node" } else { "communication" };
            format!("event: NMT reset {what}")
        }
        ChargerEvent::BatteryFound { state } => {
            format!("event: battery module found ({state})")
        }
        ChargerEvent::BatteryLost => {
            "event: battery module heartbeat lost: EMCY E-0-3-2, TPDOs stopped".to_string()
        }
        ChargerEvent::Configured { tpdos, rpdos } => format!(
            "event: PDO COB-IDs configured: TPDOs {tpdos:04b}, RPDOs {rpdos:04b} (bit n = PDO n)"
        ),
        ChargerEvent::ConfigurationFailed { index, sub, code } => format!(
            "event: reading the module's {index:04X}h sub {sub} failed: {code}; EMCY E-0-3-0"
        ),
        ChargerEvent::NotABatteryModule { device_type } => {
            format!("event: device type {device_type:08X}h is not a CiA 418 battery module")
        }
        ChargerEvent::BatteryEmcy { emcy, reaction } => {
            let what = match reaction {
                Reaction::Continue => "continue",
                Reaction::TerminateCharging => "terminate charging",
                Reaction::ShutDown => "shut down",
                Reaction::TemperatureSensorFault => "temperature-sensor-fault handling",
            };
            format!(
                "event: battery EMCY {} (reg {:02X}h): {what}",
                emcy.code,
                emcy.register.bits()
            )
        }
        ChargerEvent::Device(DeviceEvent::RpdoRefused { pdo, error }) => {
            format!("event: RPDO {pdo} refused: {error}")
        }
        ChargerEvent::Device(DeviceEvent::ObjectWritten { index, sub }) => {
            format!("event: SDO download to {index:04X}h sub {sub:02X}h")
        }
        ChargerEvent::Device(DeviceEvent::Storage(s)) => format!("event: storage: {s:?}"),
        ChargerEvent::Device(DeviceEvent::SdoAborted {
            index, sub, code, ..
        }) => format!("event: SDO transfer of {index:04X}h sub {sub:02X}h aborted: {code}"),
        // RPDOs come every 200 ms; heartbeats are reported as battery found/lost.
        _ => return None,
    };
    Some(words)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let o = match parse_args(&args) {
        Ok(Some(o)) => o,
        Ok(None) => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("charger: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let (current, voltage) = (o.current_a, o.voltage_v);
    let set_objects = |obj: &mut ChargerAppDictionary| {
        obj.charging_current = (current * 256.0).round() as u16;
        obj.battery_voltage_q8 = (voltage * 256.0).round() as u16;
        obj.battery_voltage_q10 = (voltage * 1024.0).round().min(65535.0) as u16;
        obj.charger_status = 0x01;
    };
    if o.print_eds {
        let mut charger = Charger::new(o.config);
        charger.update(Timestamp::ZERO, set_objects);
        print!("{}", eds::write(&charger_eds(&charger)));
        return ExitCode::SUCCESS;
    }
    #[allow(unused_mut)]
    let mut charger = Charger::new(o.config);
    if let Some(path) = &o.storage {
        match storage::FileStorage::open_for_device(path) {
            Ok(s) => charger.device_mut().set_storage(s),
            Err(e) => {
                eprintln!("charger: {e}");
                return ExitCode::from(2);
            }
        }
    }
    if let Some(path) = &o.program_store {
        #[cfg(feature = "program-download")]
        {
            let store = program_store::FileProgramStore::new(path);
            eprintln!("charger: program download into {}", store.path().display());
            charger.set_program_store(Box::leak(Box::new(store)));
        }
        #[cfg(not(feature = "program-download"))]
        {
            eprintln!(
                "charger: --program-store {} needs feature program-download",
                path.display()
            );
            return ExitCode::from(2);
        }
    }
    let (mut runner, boot) = Runner::new(PipeBus::stdin(&o.interface), charger, describe);
    eprintln!(
        "charger: node {}, battery node {}, mode {}, COB-ID configuration {}",
        o.config.node,
        o.config.battery,
        o.config.mode,
        if o.config.configure_cob_ids {
            "on"
        } else {
            "off (default COB-IDs)"
        }
    );
    runner.device.boot(boot);
    runner.device.update(boot, set_objects);
    runner.flush(boot);
    runner.run(o.linger);
    ExitCode::SUCCESS
}
