//! A virtual CiA 418 battery module on a pipe: candump log lines in on
//! stdin, the frames it sends out on stdout (one candump log line per frame,
//! flushed), its events in words on stderr. It runs one
//! [`BatteryModule`] (SDO server, default PDOs, heartbeat, EMCY, NMT slave).
//!
//! ```text
//! cargo run --features sim --example battery_module -- --node-id 1 </dev/null
//! printf '000#0101\n' | cargo run --features sim --example battery_module -- --node-id 1 --linger-ms 1000
//! ```
//!
//! `--help` lists the options (object values, heartbeat, PDO bits, ...).
//!
//! # Time
//!
//! Input timestamps, when present, set the time base; between lines the
//! monotonic clock runs on (see `examples/support/node.rs` for the exact
//! rules, shared with the `charger` example). When stdin closes the module
//! keeps running for `--linger-ms` (default 2000 ms, so `</dev/null` shows
//! the boot-up and two heartbeats), then exits with status 0.

/// The pipe bus, the node loop and the parameter storage the example
/// programs share (examples/support/).
mod support {
    pub mod bus;
    pub mod node;
    pub mod storage;
}
use support::{bus, node, storage};

use std::collections::VecDeque;
use std::process::ExitCode;
use std::time::Duration;

use bus::PipeBus;
use canopen_codec::cia418::{
    battery_module_eds, BatteryEvent, BatteryModule, BatteryModuleConfig, BatteryObjects,
    BatteryParameters, BatteryStatus, BatteryType, BatteryVoltage, DeviceType, Identity,
    PackedStringObject, StateOfCharge, Temperature,
};
use canopen_codec::eds;
use canopen_codec::lss::{LssAddress, LssSlave, LssSlaveConfig, LssSlaveEvent, LssStatus};
use canopen_codec::machine::Machine;
use canopen_codec::sdo::AbortOrigin;
use canopen_codec::sim::module_link::{self, ReturnedCharge};
use canopen_codec::sim::{BmsPolicy, Pack, PackSpec};
use canopen_codec::{CanFrame, NodeId, Timestamp};
use node::Runner;

const USAGE: &str = "usage: battery_module [OPTIONS]
A virtual CiA 418 battery module: candump lines in on stdin, the frames it
sends out on stdout, its events on stderr.

  --node-id N            node id 1..=127 (default 1); 255 = not configured
                         (with --lss: silent until an LSS master gives it one)
  --lss                  carry an LSS slave (CiA 305) whose LSS address is the
                         --identity; a store configuration request is answered
                         ok (kept in memory only; with --storage, in FILE)
  --storage FILE         keep what 1010h stores (1011h restores the defaults)
                         in FILE, loaded again at the next start
  --serial S             6030h battery serial number (packed string, <= 10 chars)
  --battery-id S         6031h battery ID (packed string, <= 20 chars)
  --battery-type B       6020h sub 1: hex (0x10, 10h) or a name: flooded,
                         flooded-tubular, high-gravity, agm, gel, hybrid,
                         nicd, nimh, li-ion (default flooded = 10h)
  --capacity-ah N        6020h sub 2 (default 400)
  --max-current-a N      6020h sub 3 (default 80)
  --cells N              6020h sub 4 (default 24)
  --voltage V            6060h battery voltage in volts (default 48.0)
  --temperature C        6010h temperature in degC (default 25.0)
  --soc P                6081h battery state of charge in % (default 50)
  --battery-status HEX   6000h (default 01: ready to charge)
  --device-type HEX      1000h: 418 plus optional PDO bits 16-19, or just the
                         bits (40000 = 2nd TPDO); default 000001A2
  --device-name S        1008h (default \"canopen-codec battery_module\")
  --identity V,P,R,S     1018h sub 1-4 in hex (default 0,0,0,0)
  --heartbeat-ms N       1017h after boot and resets (default 1000; 0 = off)
  --no-enable-tpdos      keep CiA 418's default: TPDO COB-IDs not valid
                         (bit 31) until a tool enables them by SDO
  --simulate             a simulated pack behind the module (the chemistry of
                         --battery-type, --cells, --capacity-ah, from --soc at
                         --temperature): it takes the charge the charger reports
                         in 6052h; 6000h, 6010h, 6060h, 6070h, 6081h come from
                         the pack and a CC-then-CV BMS policy asking up to
                         --max-current-a
  --speed F              the module's clock (timers, the pack, log stamps) runs F
                         times the wall clock, 0.001 to 1000 (default 1): run
                         the other end at the same F
  --nmt-start            act as the NMT master after boot: send 000#0100 (start all nodes)
  --linger-ms N          keep running N ms after stdin closes (default 2000)
  --interface NAME       interface name in the output lines (default can0)
  --print-eds            print the module's EDS (CiA 306) as configured by the
                         other options on stdout and exit
  -h, --help             this text

Time: the system clock until the first input line with a timestamp, then
that line's time base (see the example's documentation).";

#[derive(Debug)]
struct Options {
    config: BatteryModuleConfig,
    serial: Option<String>,
    battery_id: Option<String>,
    parameters: BatteryParameters,
    voltage: BatteryVoltage,
    temperature: Temperature,
    soc: StateOfCharge,
    status: BatteryStatus,
    simulate: bool,
    speed: f64,
    nmt_start: bool,
    linger: Duration,
    interface: String,
    print_eds: bool,
    lss: bool,
    unconfigured: bool,
    storage: Option<String>,
}

fn hex_u32(s: &str) -> Result<u32, String> {
    let t = s.trim_start_matches("0x").trim_start_matches("0X");
    let t = t.strip_suffix('h').unwrap_or(t);
    u32::from_str_radix(t, 16).map_err(|_| format!("bad hex number '{s}'"))
}

fn battery_type(s: &str) -> Result<BatteryType, String> {
    let raw = match s.to_ascii_lowercase().as_str() {
        "flooded" | "lead-acid" => 0x10,
        "high-gravity" => 0x12,
        "flooded-tubular" => 0x11,
        "agm" => 0x18,
        "gel" => 0x19,
        "hybrid" => 0x1A,
        "nicd" => 0x20,
        "nimh" => 0x80,
        "li-ion" | "lithium-ion" => 0xA0,
        other => u8::try_from(hex_u32(other)?).map_err(|_| format!("bad battery type '{s}'"))?,
    };
    Ok(BatteryType::from_u8(raw))
}

fn device_type(s: &str) -> Result<DeviceType, String> {
    let raw = hex_u32(s)?;
    let dt = if raw & 0xFFFF == 0 {
        DeviceType::cia418(raw)
    } else {
        DeviceType::from_raw(raw)
    };
    if !dt.is_cia418() || dt.cia418_reserved_bits() != 0 {
        return Err(format!(
            "device type {raw:08X}h is not CiA 418 with PDO bits 16-19"
        ));
    }
    Ok(dt)
}

fn parse_args(args: &[String]) -> Result<Option<Options>, String> {
    let mut config = BatteryModuleConfig::new(NodeId::MIN);
    config.device_name = "canopen-codec battery_module";
    let mut o = Options {
        config,
        serial: None,
        battery_id: None,
        parameters: BatteryParameters {
            battery_type: BatteryType::from_u8(0x10),
            ah_capacity: 400,
            max_charge_current: 80,
            number_of_cells: 24,
        },
        voltage: BatteryVoltage::from_raw(48 * 1024),
        temperature: Temperature::from_raw(25 * 8),
        soc: StateOfCharge::from_raw(50),
        status: BatteryStatus::READY_TO_CHARGE,
        simulate: false,
        speed: 1.0,
        nmt_start: false,
        linger: Duration::from_millis(2000),
        interface: "can0".to_string(),
        print_eds: false,
        lss: false,
        storage: None,
        unconfigured: false,
    };
    let mut device_type_given = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{a} needs a value"));
        let num = |v: &str| -> Result<f64, String> {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("bad number '{v}' for {a}"))
        };
        let int = |v: &str| -> Result<u16, String> {
            v.parse::<u16>()
                .map_err(|_| format!("bad number '{v}' for {a}"))
        };
        match a.as_str() {
            "-h" | "--help" => return Ok(None),
            "--lss" => o.lss = true,
            "--node-id" => {
                let v = value()?;
                o.unconfigured = v == "255";
                if o.unconfigured {
                    continue;
                }
                o.config.node = v.parse().ok().and_then(NodeId::new).ok_or_else(|| {
                    format!("{a}: '{v}' is not a node id 1..=127 (or 255 with --lss)")
                })?;
            }
            "--serial" => o.serial = Some(value()?.clone()),
            "--battery-id" => o.battery_id = Some(value()?.clone()),
            "--battery-type" => {
                o.parameters.battery_type =
                    battery_type(value()?).map_err(|e| format!("{a}: {e}"))?;
            }
            "--capacity-ah" => o.parameters.ah_capacity = int(value()?)?,
            "--max-current-a" => o.parameters.max_charge_current = int(value()?)?,
            "--cells" => o.parameters.number_of_cells = int(value()?)?,
            "--voltage" => {
                let v = num(value()?)?;
                if !(0.0..=4_194_303.0).contains(&v) {
                    return Err(format!("{a}: {v} V is not 0 to 4194303 V"));
                }
                // In range: the cast cannot truncate.
                #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
                let raw = (v * 1024.0).round() as u32;
                o.voltage = BatteryVoltage::from_raw(raw);
            }
            "--temperature" => {
                let v = num(value()?)?;
                if !(-4096.0..=4095.0).contains(&v) {
                    return Err(format!("{a}: {v} degC is not -4096 to 4095 degC"));
                }
                #[allow(clippy::cast_possible_truncation)]
                let raw = (v * 8.0).round() as i16;
                o.temperature = Temperature::from_raw(raw);
            }
            "--soc" => {
                let v = value()?;
                o.soc = v
                    .parse()
                    .ok()
                    .and_then(StateOfCharge::new)
                    .ok_or_else(|| format!("{a}: '{v}' is not a state of charge 0..=100 %"))?;
            }
            "--battery-status" => {
                let v = hex_u32(value()?).map_err(|e| format!("{a}: {e}"))?;
                let v = u8::try_from(v).map_err(|_| format!("{a}: {v:X}h is not one byte"))?;
                o.status = BatteryStatus::from_bits_retain(v);
            }
            "--device-type" => {
                o.config.device_type = device_type(value()?).map_err(|e| format!("{a}: {e}"))?;
                device_type_given = true;
            }
            "--device-name" => {
                // The module keeps a &'static str; one leak per run.
                o.config.device_name = Box::leak(value()?.clone().into_boxed_str());
            }
            "--identity" => {
                let v = value()?;
                let parts = v
                    .split(',')
                    .map(hex_u32)
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(|e| format!("{a}: {e}"))?;
                let [vendor_id, product_code, revision_number, serial_number] = parts[..] else {
                    return Err(format!("--identity wants 4 hex numbers, got '{v}'"));
                };
                o.config.identity = Identity {
                    vendor_id,
                    product_code,
                    revision_number,
                    serial_number,
                };
            }
            "--heartbeat-ms" => {
                o.config.heartbeat = std::time::Duration::from_millis(u64::from(int(value()?)?));
            }
            "--no-enable-tpdos" => o.config.enable_tpdos = false,
            "--simulate" => {
                o.simulate = true;
                if !device_type_given {
                    // Every optional PDO: the charger's 6052h and the
                    // module's 6070h travel in the 2nd and 3rd ones.
                    o.config.device_type = DeviceType::cia418(
                        DeviceType::RPDO_2ND
                            | DeviceType::RPDO_3RD
                            | DeviceType::TPDO_2ND
                            | DeviceType::TPDO_3RD,
                    );
                }
            }
            "--speed" => {
                let v = value()?;
                o.speed = v
                    .parse::<f64>()
                    .ok()
                    .filter(|f| (MIN_SPEED..=MAX_SPEED).contains(f))
                    .ok_or(format!("--speed: '{v}' is not {MIN_SPEED} to {MAX_SPEED}"))?;
            }
            "--nmt-start" => o.nmt_start = true,
            "--print-eds" => o.print_eds = true,
            "--linger-ms" => {
                let v = value()?;
                let ms = v
                    .parse::<u64>()
                    .map_err(|_| format!("bad number '{v}' for --linger-ms"))?;
                o.linger = Duration::from_millis(ms);
            }
            "--interface" => o.interface = value()?.clone(),
            "--storage" => o.storage = Some(value()?.clone()),
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    if o.unconfigured && !o.lss {
        return Err("--node-id 255 (not configured) needs --lss".to_string());
    }
    Ok(Some(o))
}

/// The pack behind the module (`--simulate`): the `sim` models, stepped
/// every [`TICK`]. The charge comes
/// from what the charger reports in 6052h (a CiA 418 module learns nothing
/// else of the charger's output: `sim::module_link`); the module's 6000h,
/// 6010h, 6060h, 6070h and 6081h come from the pack and the BMS policy.
struct Simulation {
    pack: Pack,
    bms: BmsPolicy,
    returned: ReturnedCharge,
    /// Seconds of the module's time so far.
    clock_s: f64,
    next: Timestamp,
    next_report: Timestamp,
    /// Ah into the pack since the last report.
    since_report_ah: f64,
    /// [`REPORT_EVERY`] in the module's time.
    report_every: Duration,
}

/// The physics step, in the module's (real) time.
const TICK: Duration = Duration::from_millis(250);
/// The fastest `--speed`: heartbeat timeouts of a second or two stay tens
/// of wall milliseconds above the scheduler's jitter.
const MAX_SPEED: f64 = 1000.0;
/// The slowest `--speed` (a second of the module's time is 17 wall
/// minutes): any deadline of the node's clock, scaled to the wall clock,
/// stays a `Duration`.
const MIN_SPEED: f64 = 0.001;
/// How often (wall time) the pack is reported on stderr while it charges.
const REPORT_EVERY: Duration = Duration::from_secs(10);

impl Simulation {
    fn run(&mut self, now: Timestamp, module: &mut BatteryModule) {
        let dt = TICK.as_secs_f64();
        self.clock_s += dt;
        self.returned
            .report(self.clock_s, module.ah_returned_during_last_charge());
        let current = self.returned.draw(dt);
        self.pack.step(dt, current);
        self.since_report_ah += current * dt / 3600.0;
        let request = self.bms.request(&self.pack);
        let pack = self.pack;
        module.update(now, |o| module_link::publish(o, &pack, current, request));
        self.next = now.add_duration(TICK);
        if now.has_reached(self.next_report) && self.since_report_ah > 0.0 {
            self.next_report = now.add_duration(self.report_every);
            eprintln!(
                "pack: {:.1} % at {:.2} V, {:.3} Ah in the last {:.0} s, {:.1} degC; asking {:.2} A{}",
                pack.soc() * 100.0,
                pack.rest_voltage(),
                self.since_report_ah,
                self.report_every.as_secs_f64(),
                pack.temperature_c(),
                request.current_a,
                if request.ready { "" } else { " (not ready)" }
            );
            self.since_report_ah = 0.0;
        }
    }
}

/// The module and its optional simulation, as one machine for the runner:
/// the simulation's step is one more timer.
struct BatteryDevice {
    module: BatteryModule,
    sim: Option<Simulation>,
    events: VecDeque<BatteryEvent>,
}

impl BatteryDevice {
    /// Takes the module's events; an LSS store request is answered at once
    /// (the configuration is kept in memory only).
    fn take_events(&mut self) {
        while let Some(e) = self.module.poll_event() {
            if let BatteryEvent::Lss(LssSlaveEvent::StoreRequested { .. }) = e {
                if let Some(lss) = self.module.device_mut().lss_mut() {
                    let _ = lss.answer_store(LssStatus::OK);
                }
            }
            self.events.push_back(e);
        }
    }
}

impl Machine for BatteryDevice {
    type Event = BatteryEvent;
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        self.module.handle_frame(now, frame);
        self.take_events();
    }
    fn handle_timeout(&mut self, now: Timestamp) {
        if let Some(sim) = self.sim.as_mut().filter(|s| now.has_reached(s.next)) {
            sim.run(now, &mut self.module);
        }
        self.module.handle_timeout(now);
    }
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.module.poll_transmit()
    }
    fn poll_timeout(&self) -> Option<Timestamp> {
        let sim = self.sim.as_ref().map(|s| s.next);
        match (self.module.poll_timeout(), sim) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
    fn poll_event(&mut self) -> Option<BatteryEvent> {
        self.take_events();
        self.events.pop_front()
    }
    fn events_dropped(&self) -> u64 {
        self.module.events_dropped()
    }
    fn frames_dropped(&self) -> u64 {
        self.module.frames_dropped()
    }
}

/// An event in words for stderr (every event but the RPDOs).
fn describe(e: &BatteryEvent) -> Option<String> {
    let words = match *e {
        BatteryEvent::NmtStateChanged { from, to } => format!("event: NMT {from} -> {to}"),
        BatteryEvent::Reset { node: true } => "event: NMT reset node".to_string(),
        BatteryEvent::Reset { node: false } => "event: NMT reset communication".to_string(),
        BatteryEvent::ObjectWritten { index, sub } => {
            format!("event: SDO download to {index:04X}h sub {sub:02X}h")
        }
        // The charger's TPDOs come every 200 ms: not printed.
        BatteryEvent::RpdoReceived { .. } => return None,
        BatteryEvent::RpdoRefused { pdo, error } => format!("event: RPDO {pdo} refused: {error}"),
        BatteryEvent::SdoAborted {
            index,
            sub,
            code,
            origin,
        } => {
            let by = match origin {
                AbortOrigin::Local => "by us",
                AbortOrigin::Peer => "by the client",
                AbortOrigin::Superseded => "superseded by a new request",
                _ => "for another reason",
            };
            format!("event: SDO transfer of {index:04X}h sub {sub:02X}h aborted {by}: {code}")
        }
        BatteryEvent::Heartbeat(h) => format!("event: heartbeat supervision: {h:?}"),
        BatteryEvent::Lss(e) => match e {
            LssSlaveEvent::StateChanged(state) => format!("event: LSS {state:?} state"),
            LssSlaveEvent::NodeIdConfigured(Some(n)) => {
                format!("event: LSS node-ID {n} configured (active after reset communication)")
            }
            LssSlaveEvent::NodeIdConfigured(None) => {
                "event: LSS node-ID 255 (not configured) configured".to_string()
            }
            LssSlaveEvent::StoreRequested { node_id, .. } => format!(
                "event: LSS store configuration (node-ID {}): ok",
                node_id.map_or(255, NodeId::raw)
            ),
            LssSlaveEvent::ResetCommunication => {
                "event: LSS reset communication under the new node-ID".to_string()
            }
            other => format!("event: LSS {other:?}"),
        },
        BatteryEvent::LifeGuarding(g) => format!("event: life guarding: {g:?}"),
        BatteryEvent::Sync(s) => format!("event: SYNC: {s:?}"),
        BatteryEvent::Storage(s) => format!("event: storage: {s:?}"),
        BatteryEvent::Time(t) => format!("event: TIME: {t:?}"),
        _ => return None,
    };
    Some(words)
}

/// The object values the options set.
fn set_objects(obj: &mut BatteryObjects, o: &Options) {
    obj.battery_parameters = o.parameters;
    obj.battery_voltage = o.voltage;
    obj.temperature = o.temperature;
    obj.battery_state_of_charge = o.soc;
    obj.battery_status = o.status;
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
            eprintln!("battery_module: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let mut module = if o.lss {
        let i = o.config.identity;
        let address = LssAddress {
            vendor: i.vendor_id,
            product: i.product_code,
            revision: i.revision_number,
            serial: i.serial_number,
        };
        let node = (!o.unconfigured).then_some(o.config.node);
        BatteryModule::with_lss(o.config, LssSlave::new(LssSlaveConfig::new(address, node)))
    } else {
        BatteryModule::new(o.config)
    };
    for (object, text) in [
        (PackedStringObject::BatterySerialNumber, &o.serial),
        (PackedStringObject::BatteryId, &o.battery_id),
    ] {
        if let Some(text) = text {
            if let Err(e) = module.set_text(object, text) {
                eprintln!("battery_module: {:04X}h: {e}", object.index());
                return ExitCode::from(2);
            }
        }
    }
    if let Some(path) = &o.storage {
        match storage::FileStorage::open_for_device(path) {
            Ok(s) => module.device_mut().set_storage(s),
            Err(e) => {
                eprintln!("battery_module: {e}");
                return ExitCode::from(2);
            }
        }
    }
    if o.print_eds {
        module.update(Timestamp::ZERO, |obj| set_objects(obj, &o));
        print!("{}", eds::write(&battery_module_eds(&module)));
        return ExitCode::SUCCESS;
    }
    let mut bus = PipeBus::stdin(&o.interface);
    bus.set_speed(o.speed);
    let (mut runner, boot) = Runner::new(
        bus,
        BatteryDevice {
            module,
            sim: None,
            events: VecDeque::new(),
        },
        describe,
    );
    let module = &mut runner.device.module;
    module.update(boot, |obj| set_objects(obj, &o));
    let node = if o.unconfigured {
        "255 (not configured, waiting for LSS)".to_string()
    } else {
        o.config.node.to_string()
    };
    eprintln!(
        "battery_module: node {}{}, device type {:08X}h, heartbeat {} ms, TPDOs {}",
        node,
        if o.lss { " with LSS" } else { "" },
        o.config.device_type.raw(),
        o.config.heartbeat.as_millis(),
        if o.config.enable_tpdos {
            "enabled"
        } else {
            "not valid until enabled"
        }
    );
    module.boot(boot);
    if o.simulate {
        let p = o.parameters;
        let spec = match PackSpec::new(
            p.battery_type.chemistry(),
            p.number_of_cells,
            f64::from(p.ah_capacity),
        ) {
            Ok(mut spec) => {
                spec.ambient_c = f64::from(o.temperature.raw()) / 8.0;
                spec
            }
            Err(e) => {
                eprintln!("battery_module: --simulate: {e}");
                return ExitCode::from(2);
            }
        };
        let soc = f64::from(o.soc.percent().unwrap_or(50)) / 100.0;
        let pack = Pack::new(spec, soc);
        let bms = BmsPolicy::for_pack(&spec, f64::from(p.max_charge_current));
        eprintln!(
            "battery_module: simulated pack: {} cells of {:?}, {} Ah at {:.0} %, asking up to {} A",
            spec.cells,
            spec.chemistry,
            spec.capacity_ah,
            soc * 100.0,
            p.max_charge_current
        );
        let mut sim = Simulation {
            pack,
            bms,
            // Twice what it asks for at most: a bunched 6052h report (the
            // module's steps stalled and caught up) flows over the next steps.
            returned: ReturnedCharge::with_max_rate(2.0 * f64::from(p.max_charge_current)),
            clock_s: 0.0,
            next: boot,
            next_report: boot,
            since_report_ah: 0.0,
            report_every: REPORT_EVERY.mul_f64(o.speed),
        };
        sim.run(boot, &mut runner.device.module);
        runner.device.sim = Some(sim);
    }
    runner.flush(boot);
    if o.nmt_start {
        // The BMS as NMT master (the real capture's battery controller sends
        // 000#010A): start every node, this one included.
        if let Ok(start) = CanFrame::standard(0x000, &[0x01, 0x00]) {
            runner
                .bus
                .send_at(&start, node::stamp(runner.clock.external(boot)));
            runner.device.module.handle_frame(boot, &start);
            runner.flush(boot);
        }
    }
    runner.run(o.linger);
    ExitCode::SUCCESS
}
