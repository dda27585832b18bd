//! A virtual CiA 418 battery module on a pipe: candump log lines in on
//! stdin, the frames it sends out on stdout (one candump log line per frame,
//! flushed), its events in words on stderr. It runs one
//! [`BatteryModule`] (SDO server, default PDOs, heartbeat, EMCY, NMT slave).
//!
//! ```text
//! cargo run --example battery_module -- --node-id 1 </dev/null
//! printf '000#0101\n' | cargo run --example battery_module -- --node-id 1 --linger-ms 1000
//! ```
//!
//! `--help` lists the options (object values, heartbeat, PDO bits, ...).
//!
//! # Time
//!
//! The module is driven with one clock, in microseconds, whose time base is
//! the one the output lines are stamped in:
//!
//! - At start it is the **system clock** (wall time at start plus the
//!   monotonic clock since), so `</dev/null` or lines without timestamps
//!   give candump lines with ordinary UNIX times.
//! - The **first input line with a timestamp** switches the time base to the
//!   input's: its timestamp is taken as the time of the module's last step
//!   (its boot, or the last timer it ran), so the module's own clock never
//!   jumps, and every later output line is stamped in the input's base.
//!   (So the phase of the heartbeat follows the boot: the first heartbeat
//!   is one period after the first timestamped line when that line came
//!   before the first heartbeat.)
//! - A later timestamp **ahead** of the clock moves it forward: every timer
//!   due on the way (heartbeats, TPDO event timers, SDO timeouts) runs at
//!   its own due time, in order, with output lines stamped with that time,
//!   before the line's frame is handled. A replayed script or log therefore
//!   gives the same output whatever the speed it is piped in.
//! - A timestamp **behind** the clock (a late line) is handled at the
//!   clock's current time: the clock never goes backwards. A line without a
//!   timestamp is handled at the current time.
//! - **Between lines** the clock runs on the monotonic clock from the last
//!   timestamp that moved it, so heartbeats and TPDOs keep coming on time
//!   while the input is quiet.
//! - Timers are run at their due time, not at the moment the process wakes
//!   up, so periods do not drift. A jump of more than [`MAX_STEPS`] timer
//!   runs expires what is left once, at the target time.
//!
//! When stdin closes the module keeps running on the monotonic clock for
//! `--linger-ms` (default 2000 ms, so `</dev/null` shows the boot-up and two
//! heartbeats), then exits with status 0; `--linger-ms 0` exits as soon as
//! the last line has been handled.

#[path = "support/bus.rs"]
mod bus;

use std::process::ExitCode;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use bus::{Input, PipeBus};
use canopen_codec::cia418::{
    BatteryEvent, BatteryModule, BatteryModuleConfig, BatteryParameters, BatteryStatus,
    BatteryType, BatteryVoltage, DeviceType, Identity, PackedStringObject, StateOfCharge,
    Temperature,
};
use canopen_codec::sdo::AbortOrigin;
use canopen_codec::{CanFrame, NodeId, Timestamp};

const USAGE: &str = "usage: battery_module [OPTIONS]
A virtual CiA 418 battery module: candump lines in on stdin, the frames it
sends out on stdout, its events on stderr.

  --node-id N            node id 1..=127 (default 1)
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
  --simulate             voltage and state of charge change slowly (1 s steps)
  --linger-ms N          keep running N ms after stdin closes (default 2000)
  --interface NAME       interface name in the output lines (default can0)
  -h, --help             this text

Time: the system clock until the first input line with a timestamp, then
that line's time base (see the example's documentation).";

/// Timer runs in one catch-up before the rest is expired at once.
pub const MAX_STEPS: u32 = 1_000_000;

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
    linger: Duration,
    interface: String,
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
        linger: Duration::from_millis(2000),
        interface: "can0".to_string(),
    };
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
            "--node-id" => {
                let v = value()?;
                o.config.node = v
                    .parse()
                    .ok()
                    .and_then(NodeId::new)
                    .ok_or_else(|| format!("bad node id '{v}' (1..=127)"))?;
            }
            "--serial" => o.serial = Some(value()?.clone()),
            "--battery-id" => o.battery_id = Some(value()?.clone()),
            "--battery-type" => o.parameters.battery_type = battery_type(value()?)?,
            "--capacity-ah" => o.parameters.ah_capacity = int(value()?)?,
            "--max-current-a" => o.parameters.max_charge_current = int(value()?)?,
            "--cells" => o.parameters.number_of_cells = int(value()?)?,
            "--voltage" => {
                let v = num(value()?)?;
                if !(0.0..=4_194_303.0).contains(&v) {
                    return Err(format!("voltage {v} V out of range"));
                }
                // In range: the cast cannot truncate.
                #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
                let raw = (v * 1024.0).round() as u32;
                o.voltage = BatteryVoltage::from_raw(raw);
            }
            "--temperature" => {
                let v = num(value()?)?;
                if !(-4096.0..=4095.0).contains(&v) {
                    return Err(format!("temperature {v} degC out of range"));
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
                    .ok_or_else(|| format!("bad state of charge '{v}' (0..=100)"))?;
            }
            "--battery-status" => {
                let v = hex_u32(value()?)?;
                let v = u8::try_from(v).map_err(|_| format!("bad battery status {v:X}h"))?;
                o.status = BatteryStatus::from_bits_retain(v);
            }
            "--device-type" => o.config.device_type = device_type(value()?)?,
            "--device-name" => {
                // The module keeps a &'static str; one leak per run.
                o.config.device_name = Box::leak(value()?.clone().into_boxed_str());
            }
            "--identity" => {
                let v = value()?;
                let parts = v.split(',').map(hex_u32).collect::<Result<Vec<_>, _>>()?;
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
            "--heartbeat-ms" => o.config.heartbeat_ms = int(value()?)?,
            "--no-enable-tpdos" => o.config.enable_tpdos = false,
            "--simulate" => o.simulate = true,
            "--linger-ms" => {
                let v = value()?;
                let ms = v
                    .parse::<u64>()
                    .map_err(|_| format!("bad number '{v}' for --linger-ms"))?;
                o.linger = Duration::from_millis(ms);
            }
            "--interface" => o.interface = value()?.clone(),
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    Ok(Some(o))
}

/// The clock described in the module docs. All values are microseconds;
/// "external" is the base of the output lines, "internal" the module's.
struct Clock {
    /// external (live) = monotonic + `off`
    off: i128,
    /// internal = external - `shift`
    shift: i128,
    /// Whether a timestamped line has set the time base.
    anchored: bool,
    /// The last external time the module was driven at.
    last: i128,
}

fn micros(t: Timestamp) -> i128 {
    i128::from(t.as_micros())
}

fn stamp(us: i128) -> Timestamp {
    Timestamp::from_micros(u64::try_from(us.max(0)).unwrap_or(u64::MAX))
}

impl Clock {
    fn new(bus: &PipeBus) -> Self {
        let wall = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| i128::try_from(d.as_micros()).unwrap_or(0));
        let off = wall - micros(bus.now());
        Clock {
            off,
            shift: 0,
            anchored: false,
            last: wall,
        }
    }

    /// The current external time (never before the last step).
    fn now(&self, bus: &PipeBus) -> i128 {
        (micros(bus.now()) + self.off).max(self.last)
    }

    /// The external time at which to handle a line stamped `ts`.
    fn on_line(&mut self, bus: &PipeBus, ts: Option<Timestamp>) -> i128 {
        let now = self.now(bus);
        let Some(t) = ts.map(micros) else {
            return now;
        };
        if !self.anchored {
            // `t` is the time of the module's last step: internal time is
            // unchanged, only the external base moves.
            self.anchored = true;
            self.shift += t - self.last;
            self.last = t;
            self.off = t - micros(bus.now());
            return t;
        }
        if t > now {
            self.off = t - micros(bus.now());
            t
        } else {
            now
        }
    }

    fn internal(&self, external: i128) -> Timestamp {
        stamp(external - self.shift)
    }

    fn external(&self, internal: Timestamp) -> i128 {
        micros(internal) + self.shift
    }

    /// A deadline (external) on the bus's monotonic clock.
    fn monotonic(&self, external: i128) -> Timestamp {
        stamp(external - self.off)
    }
}

/// The slowly changing values of `--simulate`: one step a second; the
/// voltage follows a triangle of +-2 % over 60 s starting at the given value, the state of charge rises
/// by 1 % every 5 s up to 100 %.
struct Simulation {
    next: Timestamp,
    step: u64,
    voltage: BatteryVoltage,
}

impl Simulation {
    fn run(&mut self, now: Timestamp, module: &mut BatteryModule) {
        self.step += 1;
        self.next = now.add_millis(1000);
        let phase = i64::try_from(self.step % 60).unwrap_or(0);
        // 0, 1 .. 15, 14 .. -15, -14 .. -1: a triangle starting at 0.
        let tri = match phase {
            0..=15 => phase,
            16..=45 => 30 - phase,
            _ => phase - 60,
        };
        let base = i64::from(self.voltage.raw());
        let raw = base + base * tri * 2 / 1500;
        let voltage = BatteryVoltage::from_raw(u32::try_from(raw.max(0)).unwrap_or(u32::MAX));
        let step = self.step;
        module.update(now, |o| {
            o.battery_voltage = voltage;
            if step % 5 == 0 {
                if let Some(p) = o.battery_state_of_charge.percent() {
                    o.battery_state_of_charge = StateOfCharge::from_raw((p + 1).min(100));
                }
            }
        });
    }
}

struct Node {
    bus: PipeBus,
    clock: Clock,
    module: BatteryModule,
    sim: Option<Simulation>,
}

impl Node {
    /// The earliest internal deadline (module or simulation).
    fn deadline(&self) -> Option<Timestamp> {
        let sim = self.sim.as_ref().map(|s| s.next);
        match (self.module.poll_timeout(), sim) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    fn flush(&mut self, internal: Timestamp) {
        let at = stamp(self.clock.external(internal));
        while let Some(f) = self.module.poll_transmit() {
            self.bus.send_at(&f, at);
        }
        while let Some(e) = self.module.poll_event() {
            eprintln!("{}", describe(&e));
        }
    }

    /// Runs every timer due up to `target` (external) at its due time.
    fn advance(&mut self, target: i128) {
        let end = self.clock.internal(target);
        let mut steps = 0;
        while let Some(due) = self.deadline().filter(|d| *d <= end) {
            let due = if steps >= MAX_STEPS { end } else { due };
            steps += 1;
            let now = due.max(self.clock.internal(self.clock.last));
            if let Some(sim) = self.sim.as_mut().filter(|s| now.has_reached(s.next)) {
                sim.run(now, &mut self.module);
            }
            self.module.handle_timeout(now);
            self.clock.last = self.clock.external(now);
            self.flush(now);
            if steps > MAX_STEPS {
                break;
            }
        }
        self.clock.last = self.clock.last.max(target);
    }

    fn handle_frame(&mut self, frame: &CanFrame, ts: Option<Timestamp>) {
        let t = self.clock.on_line(&self.bus, ts);
        self.advance(t);
        let now = self.clock.internal(t);
        self.module.handle_frame(now, frame);
        self.flush(now);
    }

    /// Sleeps until `external` (or less) on the monotonic clock.
    fn sleep_until(&self, external: i128) {
        let wait = self
            .clock
            .monotonic(external)
            .saturating_micros_since(self.bus.now());
        std::thread::sleep(Duration::from_micros(wait));
    }
}

fn describe(e: &BatteryEvent) -> String {
    match *e {
        BatteryEvent::NmtStateChanged { from, to } => format!("event: NMT {from} -> {to}"),
        BatteryEvent::Reset { node: true } => "event: NMT reset node".to_string(),
        BatteryEvent::Reset { node: false } => "event: NMT reset communication".to_string(),
        BatteryEvent::ObjectWritten { index, sub } => {
            format!("event: SDO download to {index:04X}h sub {sub:02X}h")
        }
        BatteryEvent::RpdoReceived { pdo } => {
            format!("event: RPDO {pdo} written into the objects")
        }
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
            };
            format!("event: SDO transfer of {index:04X}h sub {sub:02X}h aborted {by}: {code}")
        }
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
            eprintln!("battery_module: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let mut module = BatteryModule::new(o.config);
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
    let bus = PipeBus::stdin(&o.interface);
    let clock = Clock::new(&bus);
    let boot = clock.internal(clock.last);
    module.update(boot, |obj| {
        obj.battery_parameters = o.parameters;
        obj.battery_voltage = o.voltage;
        obj.temperature = o.temperature;
        obj.battery_state_of_charge = o.soc;
        obj.battery_status = o.status;
    });
    eprintln!(
        "battery_module: node {}, device type {:08X}h, heartbeat {} ms, TPDOs {}",
        o.config.node,
        o.config.device_type.raw(),
        o.config.heartbeat_ms,
        if o.config.enable_tpdos {
            "enabled"
        } else {
            "not valid until enabled"
        }
    );
    module.boot(boot);
    let sim = o.simulate.then(|| Simulation {
        next: boot.add_millis(1000),
        step: 0,
        voltage: o.voltage,
    });
    let mut node = Node {
        bus,
        clock,
        module,
        sim,
    };
    node.flush(boot);
    loop {
        let wait = node
            .deadline()
            .map(|d| node.clock.monotonic(node.clock.external(d)));
        match node.bus.recv(wait) {
            Input::Frame(f, ts) => node.handle_frame(&f, ts),
            Input::Timeout => {
                let now = node.clock.now(&node.bus);
                node.advance(now);
            }
            Input::Closed => break,
        }
    }
    let linger = i128::try_from(o.linger.as_micros()).unwrap_or(i128::MAX / 4);
    let end = node.clock.now(&node.bus) + linger;
    while linger > 0 && node.clock.now(&node.bus) < end {
        let next = node
            .deadline()
            .map(|d| node.clock.external(d))
            .filter(|d| *d <= end)
            .unwrap_or(end);
        node.sleep_until(next);
        let now = node.clock.now(&node.bus).min(end);
        node.advance(now);
    }
    ExitCode::SUCCESS
}
