//! The charger's configuration ([`ChargerConfig`]), the form it is kept
//! in for boot and every reset ([`ChargerPowerOn`], the core's
//! [`PowerOn`]) and the default PDO set a reset writes (charger.rs's part,
//! apart to keep that file short).

use core::time::Duration;

use super::super::charge::ChargeConfig;
use super::super::{timeouts, OperatingMode, CHARGER_DEFAULT_PDOS};
use crate::cia419::CHARGER_DEVICE_TYPE;
use crate::cob_id::{NodeId, PdoNumber};
use crate::device::{CommObjects, DeviceConfig, ErrorFieldFormat, Policies, PowerOn};
use crate::nmt::heartbeat::ConsumerEntry;
use crate::pdo::{PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoSlot};

/// How the charger is set up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargerConfig {
    /// The charger's node id (Delta-Q default 10).
    pub node: NodeId,
    /// The battery module's node id (default 1).
    pub battery: NodeId,
    /// Operating mode (Delta-Q section 3.1): how the charge is controlled
    /// ([`ChargeControl`](crate::deltaq::charge::ChargeControl)) and the
    /// reaction to the module's EMCYs.
    pub mode: OperatingMode,
    /// The charge control's algorithms, limits and timers.
    pub charge: ChargeConfig,
    /// Read the module's PDO COB-IDs and pair the charger's PDOs with them.
    pub configure_cob_ids: bool,
    /// Enter operational after boot without waiting for an NMT start.
    pub self_start: bool,
    /// Heartbeat producer period (1017h).
    pub heartbeat: Duration,
    /// Heartbeat consumer time for the battery module (1016h).
    pub battery_timeout: Duration,
    /// Event timers of TPDO 0..3.
    pub tpdo_periods: [Duration; 4],
    /// SDO timeout of the configuration client and of the server.
    pub sdo_timeout: Duration,
    /// 1008h.
    pub device_name: &'static str,
}

impl ChargerConfig {
    /// Delta-Q defaults for charger `node` and battery module `battery`
    /// (Delta-Q IC Series CANopen interface specification rev 2.0, sections
    /// 4.3.1, 4.5.1, 4.5.2 and 4.6.1: heartbeat 1000 ms, consumer 2000 ms,
    /// SDO 2000 ms, TPDO 0-2 every 200 ms and TPDO 3 every 1000 ms).
    #[must_use]
    pub const fn new(node: NodeId, battery: NodeId) -> Self {
        let fast = Duration::from_millis(timeouts::CHARGER_TPDO_0_2_PERIOD_MS);
        ChargerConfig {
            node,
            battery,
            mode: OperatingMode::Local,
            charge: ChargeConfig::example(),
            configure_cob_ids: true,
            self_start: false,
            heartbeat: Duration::from_millis(timeouts::HEARTBEAT_PRODUCER_MS),
            battery_timeout: Duration::from_millis(timeouts::HEARTBEAT_CONSUMER_MS),
            tpdo_periods: [
                fast,
                fast,
                fast,
                Duration::from_millis(timeouts::CHARGER_TPDO_3_PERIOD_MS),
            ],
            sdo_timeout: Duration::from_millis(timeouts::SDO_MS),
            device_name: "canopen-codec charger",
        }
    }

    /// The device core's configuration for this charger (times in the
    /// whole milliseconds its objects and the core keep, see
    /// [`ChargerPowerOn`]).
    #[must_use]
    pub fn device_config(&self) -> DeviceConfig {
        DeviceConfig {
            device_type: CHARGER_DEVICE_TYPE,
            device_name: self.device_name,
            ..ChargerPowerOn::from(*self).power_on_config()
        }
    }
}

/// A [`ChargerConfig`] as the charger keeps it to rebuild its power-on
/// configuration at boot and at every reset ([`PowerOn`]): the same
/// settings with the times in whole milliseconds, the unit of the objects
/// they become (1017h, 1016h and the TPDO event timers are Unsigned16 of
/// milliseconds, saturating at 65 535 ms; the SDO timeout saturates at
/// `u32::MAX` ms). 1008h, the device name, is not
/// kept here: the charger writes it once into its communication objects
/// when it is made, and every reset keeps it there (a `const` object:
/// nothing on the bus changes it).
///
/// ```
/// use canopen_codec::deltaq::charge::ChargeConfig;
/// use canopen_codec::deltaq::{ChargerConfig, ChargerPowerOn};
/// use canopen_codec::device::CommObjects;
/// use canopen_codec::NodeId;
/// use core::time::Duration;
/// let mut config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
/// config.heartbeat = Duration::from_micros(1_500_700);
/// let kept = ChargerPowerOn::from(config);
/// let mut comm = CommObjects::new(config.node);
/// comm.device_name = "DQ";
/// assert_eq!(kept.config(&comm, ChargeConfig::example()).heartbeat, Duration::from_millis(1500));
/// assert_eq!(kept.config(&comm, ChargeConfig::example()).tpdo_periods, config.tpdo_periods);
/// assert_eq!(kept.config(&comm, ChargeConfig::example()).device_name, "DQ");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChargerPowerOn {
    pub(super) node: NodeId,
    pub(super) battery: NodeId,
    pub(super) mode: OperatingMode,
    pub(super) configure_cob_ids: bool,
    pub(super) self_start: bool,
    pub(super) heartbeat_ms: u16,
    pub(super) battery_timeout_ms: u16,
    pub(super) tpdo_periods_ms: [u16; 4],
    pub(super) sdo_timeout_ms: u32,
}

/// `d` in whole milliseconds, saturating (the arithmetic of the crate's
/// `time::millis_u16`, which the tests compare), inlined: a configuration
/// known when the code is compiled (the firmware's) becomes constants, no
/// conversion code.
#[inline(always)]
fn whole_ms(d: Duration) -> u64 {
    d.as_secs()
        .saturating_mul(1000)
        .saturating_add(u64::from(d.subsec_millis()))
}

impl From<ChargerConfig> for ChargerPowerOn {
    fn from(c: ChargerConfig) -> Self {
        let ms16 = |d: Duration| u16::try_from(whole_ms(d)).unwrap_or(u16::MAX);
        let [p0, p1, p2, p3] = c.tpdo_periods;
        ChargerPowerOn {
            node: c.node,
            battery: c.battery,
            mode: c.mode,
            configure_cob_ids: c.configure_cob_ids,
            self_start: c.self_start,
            heartbeat_ms: ms16(c.heartbeat),
            battery_timeout_ms: ms16(c.battery_timeout),
            tpdo_periods_ms: [ms16(p0), ms16(p1), ms16(p2), ms16(p3)],
            sdo_timeout_ms: u32::try_from(whole_ms(c.sdo_timeout)).unwrap_or(u32::MAX),
        }
    }
}

impl ChargerPowerOn {
    /// The configuration kept, as a [`ChargerConfig`] (times in whole
    /// milliseconds), with the device name (1008h) of the charger's
    /// communication objects `comm` and the charge control's `charge`
    /// (which its [`ChargeControl`](crate::deltaq::charge::ChargeControl)
    /// keeps: resets do not change it).
    #[must_use]
    pub fn config(&self, comm: &CommObjects, charge: ChargeConfig) -> ChargerConfig {
        let ms = |v: u16| Duration::from_millis(u64::from(v));
        ChargerConfig {
            node: self.node,
            battery: self.battery,
            mode: self.mode,
            charge,
            configure_cob_ids: self.configure_cob_ids,
            self_start: self.self_start,
            heartbeat: ms(self.heartbeat_ms),
            battery_timeout: ms(self.battery_timeout_ms),
            tpdo_periods: self.tpdo_periods_ms.map(ms),
            sdo_timeout: Duration::from_millis(u64::from(self.sdo_timeout_ms)),
            device_name: comm.device_name,
        }
    }
}

/// What a reset needs of one published row of [`CHARGER_DEFAULT_PDOS`]
/// (its direction, number, COB-ID base and mapping), 12 bytes instead of
/// the row's 32 on a 32-bit target.
#[derive(Clone, Copy)]
struct DefaultSlot {
    direction: PdoDirection,
    number: PdoNumber,
    cob_id_base: u16,
    entries: &'static [(u16, u8, u8)],
}

/// The rows of [`CHARGER_DEFAULT_PDOS`] that have a mapping (all but RPDO
/// 3), in order, made when the crate compiles; every one maps validly
/// (what `PdoSlot::from_table` needs) and has an 11-bit COB-ID base,
/// checked here too, not at every reset.
const DEFAULT_SLOTS: [DefaultSlot; 7] = {
    let mut slots = [DefaultSlot {
        direction: PdoDirection::Receive,
        number: PdoNumber::P0,
        cob_id_base: 0,
        entries: &[],
    }; 7];
    let (mut i, mut n) = (0, 0);
    while i < CHARGER_DEFAULT_PDOS.len() {
        let d = &CHARGER_DEFAULT_PDOS[i];
        assert!(
            PdoSlot::table_mapping_valid(d.entries),
            "a Delta-Q default PDO maps invalidly"
        );
        assert!(
            d.cob_id_base <= 0x780,
            "a Delta-Q default COB-ID base is not 11-bit"
        );
        if !d.entries.is_empty() {
            slots[n] = DefaultSlot {
                direction: d.direction,
                number: d.number,
                cob_id_base: d.cob_id_base as u16,
                entries: d.entries,
            };
            n += 1;
        }
        i += 1;
    }
    assert!(
        n == slots.len(),
        "the Delta-Q default PDOs are not 7 with a mapping"
    );
    slots
};

/// Writes the charger's default PDO set into `pdos` (every slot), in
/// place: one pass over [`DEFAULT_SLOTS`] (the published rows of
/// [`CHARGER_DEFAULT_PDOS`]; RPDO 3 has no mapping and no slot), each slot
/// written from its row, with COB-IDs not valid until configured (or
/// valid defaults without configuration) and the configured TPDO periods.
pub(super) fn default_pdos<const T: usize, const R: usize>(
    config: &ChargerPowerOn,
    pdos: &mut PdoConfig<T, R>,
) {
    pdos.clear();
    let valid = !config.configure_cob_ids;
    for d in &DEFAULT_SLOTS {
        let cob = PdoCobId::from_u32(u32::from(d.cob_id_base) + u32::from(config.node.raw()))
            .with_valid(valid);
        let period = match d.direction {
            PdoDirection::Transmit => config
                .tpdo_periods_ms
                .get(usize::from(d.number.raw()))
                .copied()
                .unwrap_or(0),
            PdoDirection::Receive => 0,
        };
        let comm = PdoCommParams::event_driven(cob, period);
        pdos.insert(d.direction, d.number, PdoSlot::from_table(comm, d.entries));
    }
}

/// The charger's [`DeviceConfig`] is made from its configuration at boot
/// and at every reset (the core keeps no second copy).
impl PowerOn for ChargerPowerOn {
    fn set_node(&mut self, node: NodeId) {
        self.node = node;
    }

    fn restore<const T: usize, const R: usize>(
        &self,
        comm: &mut CommObjects,
        pdos: &mut PdoConfig<T, R>,
    ) -> Policies {
        default_pdos(self, pdos);
        comm.reset_keeping_constants(self.node);
        comm.heartbeat_ms = self.heartbeat_ms;
        comm.set_consumers(&[ConsumerEntry {
            node: self.battery.raw(),
            time_ms: self.battery_timeout_ms,
        }]);
        Policies::of_profile(self.sdo_timeout_ms, ErrorFieldFormat::SwappedInfo)
    }

    fn node(&self) -> NodeId {
        self.node
    }
}
