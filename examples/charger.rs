//! A virtual Delta-Q style CiA 419 charger on a pipe: candump log lines in on
//! stdin, the frames it sends out on stdout (one candump log line per frame,
//! flushed), its events in words on stderr. It runs one
//! [`Charger`](canopen_codec::deltaq::Charger): heartbeat supervision of the
//! battery module, PDO COB-ID pairing by SDO, TPDOs, EMCYs, and its charge
//! control. Its power stage and the battery on its output are the `sim`
//! models ([`PowerStageModel`], [`Pack`]), stepped every 250 ms, so it
//! charges: in remote mode it delivers the module's 6070h request once the
//! three conditions hold, in local mode it runs its algorithm; 2002h,
//! 2006h, 6001h and 6052h follow. `--speed F` runs the charger's whole
//! clock F times faster than the wall clock (its timers, the charge and its
//! log stamps: run the other end at the same F). `--current A` /
//! `--voltage V` replace the models with a fixed power stage, a bench
//! supply rather than a charger: AC on, the output reads V volts and A
//! amps whatever the set points; the charge control runs on these readings
//! (its alarms included: a voltage below the battery detection is an
//! unplugged battery) and 2002h / 2100h / 2101h report them.
//!
//! ```text
//! cargo run --features sim --example charger -- --node-id 10 --battery-node 1 [--mode local|remote] </dev/null
//! # a whole session: the module's output feeds the charger and back
//! mkfifo /tmp/c2b
//! cargo run -q --features sim --example battery_module -- --simulate --nmt-start </tmp/c2b \
//!   | cargo run -q --features sim --example charger >/tmp/c2b
//! ```
//!
//! Options: `--node-id N` (10), `--battery-node N` (1), `--mode
//! local|remote|local-override|monitoring` (local), `--no-configure` (use the
//! charger's own default COB-IDs, as the real capture does, instead of
//! reading the module's), `--self-start` (enter operational after boot
//! instead of waiting for an NMT start), `--heartbeat-ms` (1000),
//! `--battery-timeout-ms` (the module's heartbeat consumer time, 1016h:
//! E-0-3-2 comes that long after its last heartbeat; 2000, the Delta-Q IC
//! Series CANopen interface's recommended consumer time, section 4.3.1;
//! the real startup capture's charger had about 340 ms, which its replay
//! uses: docs/REPLAY.md), `--tpdo-ms A,B,C,D` (the event timers
//! of TPDO 0..3; 0 sends that TPDO on events only), `--current A` and `--voltage V` (the
//! fixed power stage's readings, above), `--linger-ms` (2000),
//! `--interface NAME` (can0), `--storage FILE` (1010h "save" and 1011h
//! "load" keep the parameters in FILE, loaded again at the next start with
//! the same file: `examples/support/storage.rs`), `--program-store
//! DIR_OR_FILE` (takes CiA 302-3 program downloads into 1F50h sub 1 and
//! writes the image there; feature `program-download`). The battery on the
//! output: `--pack-chemistry lead-acid|li-ion|nicd|nimh` (lead-acid),
//! `--pack-cells N` (24; 13 for li-ion), `--pack-ah N` (100), `--pack-soc P`
//! (50 %), `--unplugged` (no battery on the leads), `--no-ac`; `--algorithm
//! N` the permanent and no-CAN algorithm (1 for lead acid, 11 for lithium
//! ion), `--speed F` (1).
//!
//! Time: see `examples/support/node.rs` (shared with `battery_module`).

/// The pipe bus, the node loop, the program store and the parameter
/// storage the example programs share (examples/support/).
mod support {
    pub mod bus;
    pub mod node;
    #[cfg(feature = "program-download")]
    pub mod program_store;
    pub mod storage;
}
#[cfg(feature = "program-download")]
use support::program_store;
use support::{bus, node, storage};

use std::process::ExitCode;
use std::time::Duration;

use bus::PipeBus;
use canopen_codec::cia418::Chemistry;
use canopen_codec::deltaq::charge::{ChargeEvent, PowerStage};
use canopen_codec::deltaq::{
    charger_eds, Charger, ChargerAppDictionary, ChargerConfig, ChargerEvent,
};
use canopen_codec::deltaq::{OperatingMode, Reaction};
use canopen_codec::device::DeviceEvent;
use canopen_codec::eds;
use canopen_codec::machine::Machine;
use canopen_codec::sim::{Pack, PackSpec, PowerStageModel};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use node::Runner;

const USAGE: &str = "usage: charger [--node-id N] [--battery-node N] [--mode local|remote|local-override|monitoring]
               [--no-configure] [--self-start] [--heartbeat-ms MS] [--battery-timeout-ms MS]
               [--tpdo-ms A,B,C,D] [--current A] [--voltage V] [--linger-ms MS] [--interface NAME]
               [--program-store DIR_OR_FILE] [--print-eds] [--storage FILE]
               [--pack-chemistry lead-acid|li-ion|nicd|nimh] [--pack-cells N] [--pack-ah N]
               [--pack-soc P] [--unplugged] [--no-ac] [--algorithm N] [--speed F]
The power stage and the battery on the output are simulated (a charger that
charges); --current/--voltage give a fixed power stage's readings instead. --speed F runs
the charger's clock (timers, charge, log stamps) F times the wall clock, 0.001 to
1000: run the other end at the same F.
--battery-timeout-ms MS is the heartbeat consumer time of the battery module
(1016h): MS after the module's last heartbeat the charger raises E-0-3-2 (heartbeat
lost); it takes the module as gone (E-0-3-0, back to pre-operational) 2000 ms
after that heartbeat (right after E-0-3-2 when MS is longer). The default, 2000, is the Delta-Q IC Series
CANopen interface's recommended consumer time (section 4.3.1). The replay of the
real ICL1500 startup capture runs 340: that charger sent E-0-3-2 342 ms after the
last battery heartbeat, so it was set to about 340 ms (docs/REPLAY.md).
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
    fixed: bool,
    chemistry: Chemistry,
    cells: Option<u16>,
    capacity_ah: f64,
    soc: f64,
    unplugged: bool,
    no_ac: bool,
    algorithm: Option<u16>,
    speed: f64,
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
        fixed: false,
        chemistry: Chemistry::LeadAcid,
        cells: None,
        capacity_ah: 100.0,
        soc: 50.0,
        unplugged: false,
        no_ac: false,
        algorithm: None,
        speed: 1.0,
    };
    let mut it = args.iter();
    // An option of the models, which --current/--voltage replace.
    let mut model_option: Option<&str> = None;
    while let Some(a) = it.next() {
        if matches!(
            a.as_str(),
            "--pack-chemistry"
                | "--pack-cells"
                | "--pack-ah"
                | "--pack-soc"
                | "--unplugged"
                | "--no-ac"
        ) {
            model_option = Some(a.as_str());
        }
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
            "--node-id" => o.config.node = node(value()?).map_err(|e| format!("{a}: {e}"))?,
            "--battery-node" => {
                o.config.battery = node(value()?).map_err(|e| format!("{a}: {e}"))?;
            }
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
            "--current" => {
                o.current_a = number(value()?)?;
                o.fixed = true;
            }
            "--voltage" => {
                o.voltage_v = number(value()?)?;
                o.fixed = true;
            }
            "--pack-chemistry" => {
                o.chemistry = match value()?.as_str() {
                    "lead-acid" => Chemistry::LeadAcid,
                    "li-ion" => Chemistry::LithiumIon,
                    "nicd" => Chemistry::NickelCadmium,
                    "nimh" => Chemistry::NickelMetalHydride,
                    other => return Err(format!("--pack-chemistry: no model for '{other}'")),
                }
            }
            "--pack-cells" => {
                let v = value()?;
                o.cells = Some(
                    v.parse()
                        .ok()
                        .filter(|n| *n > 0)
                        .ok_or(format!("--pack-cells: '{v}' is not 1..=65535"))?,
                );
            }
            "--pack-ah" => o.capacity_ah = number(value()?)?,
            "--pack-soc" => o.soc = number(value()?)?,
            "--unplugged" => o.unplugged = true,
            "--no-ac" => o.no_ac = true,
            "--algorithm" => {
                let v = value()?;
                o.algorithm = Some(
                    v.parse()
                        .map_err(|_| format!("--algorithm: '{v}' is not 0..=65535"))?,
                );
            }
            "--speed" => {
                let v = value()?;
                o.speed = number(v)?;
                if !(MIN_SPEED..=MAX_SPEED).contains(&o.speed) {
                    return Err(format!("--speed: '{v}' is not {MIN_SPEED} to {MAX_SPEED}"));
                }
            }
            "--linger-ms" => o.linger = Duration::from_millis(u64::from(ms(value()?)?)),
            "--interface" => o.interface = value()?.clone(),
            "--storage" => o.storage = Some(value()?.clone()),
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    if let (true, Some(m)) = (o.fixed, model_option) {
        return Err(format!(
            "{m} is an option of the simulated battery, which --current/--voltage (a fixed power stage) replace"
        ));
    }
    if !(0.0..=255.0).contains(&o.current_a) {
        return Err(format!("--current: {} is not 0 to 255 A", o.current_a));
    }
    if !(0.0..=256.0).contains(&o.voltage_v) {
        return Err(format!("--voltage: {} is not 0 to 256 V", o.voltage_v));
    }
    if !(0.0..=100.0).contains(&o.soc) {
        return Err(format!("--pack-soc: {} is not 0..=100 %", o.soc));
    }
    if !(o.capacity_ah > 0.0 && o.capacity_ah <= 10_000.0) {
        return Err(format!(
            "--pack-ah: {} is not above 0 and at most 10 000 Ah",
            o.capacity_ah
        ));
    }
    let algorithm = o.algorithm.unwrap_or(match o.chemistry {
        Chemistry::LithiumIon => 11,
        _ => 1,
    });
    o.config.charge.permanent_algorithm = Some(algorithm);
    o.config.charge.no_can_algorithm = Some(algorithm);
    Ok(Some(o))
}

/// An event in words for stderr (`None` for the RPDOs, which come every
/// 200 ms).
fn describe(e: &ChargerEvent) -> Option<String> {
    let words = match *e {
        ChargerEvent::Charge(ChargeEvent::Phase { from, to }) => {
            format!("event: charge phase {from} -> {to}")
        }
        ChargerEvent::Charge(ChargeEvent::Alarm { alarm, active }) => {
            let what = if active { "raised" } else { "cleared" };
            format!("event: charge alarm {alarm:?} {what}")
        }
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
        ChargerEvent::BatteryGone => {
            "event: battery module gone (no heartbeat for 2000 ms or more): EMCY E-0-3-0, out of operational"
                .to_string()
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

/// The physics step, in the charger's (real) time.
const TICK: Duration = Duration::from_millis(250);
/// The fastest `--speed`: heartbeat timeouts of a second or two stay tens
/// of wall milliseconds above the scheduler's jitter.
const MAX_SPEED: f64 = 1000.0;
/// The slowest `--speed` (a second of the charger's time is 17 wall
/// minutes): any deadline of its clock, scaled to the wall clock, stays a
/// `Duration`.
const MIN_SPEED: f64 = 0.001;
/// How often (wall time) the charge is reported on stderr while it flows.
const REPORT_EVERY: Duration = Duration::from_secs(10);

/// The power stage and the battery on its leads, stepped every [`TICK`].
struct Physics {
    pack: Pack,
    stage: PowerStageModel,
    next: Timestamp,
    next_report: Timestamp,
    /// [`REPORT_EVERY`] in the charger's time.
    report_every: Duration,
    ah: f64,
}

impl Physics {
    /// One step: the stage follows the charger's set points into the pack
    /// for a [`TICK`], then the charger gets the measurements.
    fn step(&mut self, now: Timestamp, charger: &mut Charger) {
        let dt = TICK.as_secs_f64();
        self.stage.step(dt, charger.set_points(), &self.pack);
        self.pack.step(dt, self.stage.current_a);
        self.ah += self.stage.current_a * dt / 3600.0;
        charger.handle_power_stage(now, self.stage.measure(&self.pack));
        self.next = now.add_duration(TICK);
        if now.has_reached(self.next_report) && self.stage.current_a > 0.0 {
            self.next_report = now.add_duration(self.report_every);
            eprintln!(
                "charge: {}, {:.2} A at {:.2} V, battery {:.1} %, {:.3} Ah returned",
                charger.charge_control().phase(),
                self.stage.current_a,
                self.pack.terminal_voltage(self.stage.current_a),
                self.pack.soc() * 100.0,
                self.ah
            );
        }
    }
}

/// The charger and its models, as one machine for the runner: the physics
/// step is one more timer.
struct ChargerDevice {
    charger: Charger,
    physics: Option<Physics>,
}

impl Machine for ChargerDevice {
    type Event = ChargerEvent;
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        self.charger.handle_frame(now, frame);
    }
    fn handle_timeout(&mut self, now: Timestamp) {
        if let Some(p) = self.physics.as_mut().filter(|p| now.has_reached(p.next)) {
            p.step(now, &mut self.charger);
        }
        self.charger.handle_timeout(now);
    }
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.charger.poll_transmit()
    }
    fn poll_timeout(&self) -> Option<Timestamp> {
        let physics = self.physics.as_ref().map(|p| p.next);
        match (self.charger.poll_timeout(), physics) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
    fn poll_event(&mut self) -> Option<ChargerEvent> {
        self.charger.poll_event()
    }
    fn events_dropped(&self) -> u64 {
        self.charger.events_dropped()
    }
    fn frames_dropped(&self) -> u64 {
        self.charger.frames_dropped()
    }
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
    let physics = if o.fixed {
        None
    } else {
        let cells = o.cells.unwrap_or(match o.chemistry {
            Chemistry::LithiumIon => 13,
            _ => 24,
        });
        let spec = match PackSpec::new(o.chemistry, cells, o.capacity_ah) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("charger: {e}");
                return ExitCode::from(2);
            }
        };
        let mut stage = PowerStageModel::new(f64::from(o.config.charge.max_power_w));
        stage.set_ac(!o.no_ac);
        stage.battery_connected = !o.unplugged;
        Some(Physics {
            pack: Pack::new(spec, o.soc / 100.0),
            stage,
            next: Timestamp::ZERO,
            next_report: Timestamp::ZERO,
            report_every: REPORT_EVERY.mul_f64(o.speed),
            ah: 0.0,
        })
    };
    let device = ChargerDevice { charger, physics };
    let mut bus = PipeBus::stdin(&o.interface);
    bus.set_speed(o.speed);
    let (mut runner, boot) = Runner::new(bus, device, describe);
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
    if let Some(p) = &runner.device.physics {
        let spec = p.pack.spec();
        eprintln!(
            "charger: {} cells of {:?}, {} Ah at {:.0} %{}{}, algorithm {}, clock x{}",
            spec.cells,
            spec.chemistry,
            spec.capacity_ah,
            p.pack.soc() * 100.0,
            if p.stage.battery_connected {
                ""
            } else {
                " (unplugged)"
            },
            if p.stage.ac_present() { "" } else { ", no AC" },
            o.config.charge.permanent_algorithm.unwrap_or(0),
            o.speed
        );
    }
    let d = &mut runner.device;
    d.charger.boot(boot);
    match d.physics.as_mut() {
        Some(p) => {
            p.next_report = boot;
            p.step(boot, &mut d.charger);
        }
        None => {
            d.charger.update(boot, set_objects);
            let fixed = PowerStage {
                ac_mv: PowerStage::AC_NOMINAL_MV,
                voltage_mv: (voltage * 1000.0).round() as i32,
                current_ma: (current * 1000.0).round() as u32,
                ..PowerStage::OFF
            };
            d.charger.handle_power_stage(boot, fixed);
        }
    }
    runner.flush(boot);
    runner.run(o.linger);
    ExitCode::SUCCESS
}
