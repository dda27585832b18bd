//! The charger and a battery module on a [`Sim`] (0.5 ms latency, names
//! [`CHARGER`] and [`BATTERY`]).

use canopen_codec::cia418::BatteryModule;
use canopen_codec::deltaq::Charger;

use super::sim::{bus, Bus, Handle};

pub const CHARGER: &str = "Charger";
pub const BATTERY: &str = "Battery";

/// The charger, then the battery module's place (`None`: nothing plugged in).
pub fn charger_bus(
    charger: Charger,
    battery: Option<BatteryModule>,
) -> (Bus, Handle<Charger>, Handle<BatteryModule>) {
    let mut sim = bus(500);
    let c = sim.add(CHARGER, charger);
    let b = sim.add_unplugged(BATTERY);
    if let Some(battery) = battery {
        assert!(sim.plug(b, battery).is_ok());
    }
    (sim, c, b)
}

/// Boots the plugged ones at the current time, the charger first.
pub fn boot_all(sim: &mut Bus, charger: Handle<Charger>, battery: Handle<BatteryModule>) {
    if sim.is_plugged(charger) {
        sim.with(charger, |m, now| m.boot(now));
    }
    if sim.is_plugged(battery) {
        sim.with(battery, |m, now| m.boot(now));
    }
}
