//! [`DeviceConfig`]: the power-on values of a device's communication
//! objects and its policies.

use core::time::Duration;

#[cfg(feature = "heartbeat-consumer")]
use super::objects::MAX_CONSUMERS;
use super::objects::{CommObjects, ErrorFieldFormat, Identity};
use crate::clock::{micros_u32, millis_u16};
use crate::cob_id::NodeId;
#[cfg(feature = "heartbeat-consumer")]
use crate::nmt::heartbeat::ConsumerEntry;
use crate::pdo::PdoConfig;
#[cfg(feature = "lss")]
use crate::pdo::PdoDirection;
use crate::sdo::{ServerConfig, DEFAULT_TIMEOUT};
use crate::sync::SyncCobId;
use crate::time::TimeCobId;

/// How a [`Device`](super::Device) is set up: the power-on values of its communication
/// objects (restored by the NMT resets) and its policies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeviceConfig {
    /// The node id.
    pub node: NodeId,
    /// 1000h device type.
    pub device_type: u32,
    /// 1008h manufacturer device name.
    pub device_name: &'static str,
    /// 1018h identity.
    pub identity: Identity,
    /// 1017h producer heartbeat time (whole milliseconds; zero: none).
    pub heartbeat: Duration,
    /// Send a heartbeat at once when the NMT state changes (CANopenNode's
    /// behaviour) rather than at the next period (the Delta-Q charger's).
    pub heartbeat_on_change: bool,
    /// 1016h entries: the first `consumer_slots` are the sub-indexes
    /// (feature `heartbeat-consumer`).
    #[cfg(feature = "heartbeat-consumer")]
    pub consumers: [ConsumerEntry; MAX_CONSUMERS],
    /// 1016h sub 0 (0: the device has no 1016h; feature
    /// `heartbeat-consumer`).
    #[cfg(feature = "heartbeat-consumer")]
    pub consumer_slots: u8,
    /// SDO server timeout.
    pub sdo_timeout: Duration,
    /// The PDO configuration (1400h-1A03h) at power-on.
    pub pdos: PdoConfig,
    /// How an EMCY is recorded in 1003h.
    pub error_field: ErrorFieldFormat,
    /// 100Ch guard time (whole milliseconds, saturating at 65535).
    pub guard_time: Duration,
    /// 100Dh life time factor (0: no life guarding).
    pub life_time_factor: u8,
    /// 1005h COB-ID SYNC (the generate bit makes the device the SYNC
    /// producer).
    pub sync_cob_id: SyncCobId,
    /// 1006h communication cycle period (whole µs, saturating at u32::MAX).
    pub cycle_period: Duration,
    /// 1007h synchronous window length (whole µs; zero: no window).
    pub sync_window: Duration,
    /// 1019h synchronous counter overflow value (0 or 2..=240; a reserved
    /// value counts as 0).
    pub sync_counter_overflow: u8,
    /// 1012h COB-ID TIME.
    pub time_cob_id: TimeCobId,
}

impl DeviceConfig {
    /// Node `node`: device type 0, no name, heartbeat 1000 ms, no consumer
    /// entries, SDO timeout 2000 ms, no PDOs, standard 1003h entries, guard
    /// time and life time factor 0, SYNC 080h consumed (no cycle, window or
    /// counter), TIME 100h neither produced nor consumed.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        DeviceConfig {
            node,
            device_type: 0,
            device_name: "",
            identity: Identity::ZERO,
            heartbeat: Duration::from_millis(1000),
            heartbeat_on_change: false,
            #[cfg(feature = "heartbeat-consumer")]
            consumers: [ConsumerEntry::DISABLED; MAX_CONSUMERS],
            #[cfg(feature = "heartbeat-consumer")]
            consumer_slots: 0,
            sdo_timeout: DEFAULT_TIMEOUT,
            pdos: PdoConfig::new(),
            error_field: ErrorFieldFormat::LittleEndianInfo,
            guard_time: Duration::ZERO,
            life_time_factor: 0,
            sync_cob_id: SyncCobId::DEFAULT,
            cycle_period: Duration::ZERO,
            sync_window: Duration::ZERO,
            sync_counter_overflow: 0,
            time_cob_id: TimeCobId::DEFAULT,
        }
    }

    /// The same with 1016h holding `entries` (at most [`MAX_CONSUMERS`];
    /// feature `heartbeat-consumer`).
    #[cfg(feature = "heartbeat-consumer")]
    #[must_use]
    pub fn with_consumers(mut self, entries: &[ConsumerEntry]) -> Self {
        let mut n = 0u8;
        for (slot, e) in self.consumers.iter_mut().zip(entries) {
            *slot = *e;
            n += 1;
        }
        self.consumer_slots = n;
        self
    }

    /// The communication objects and policies of this configuration
    /// (its PDO configuration is [`pdos`](Self::pdos)): what
    /// [`PowerOn::restore`] writes.
    fn restore_into(&self, comm: &mut CommObjects) -> Policies {
        *comm = CommObjects::new(self.node);
        comm.device_type = self.device_type;
        comm.device_name = self.device_name;
        comm.identity = self.identity;
        comm.heartbeat_ms = millis_u16(self.heartbeat);
        comm.guard_time_ms = millis_u16(self.guard_time);
        comm.life_time_factor = self.life_time_factor;
        comm.sync_cob_id = self.sync_cob_id;
        comm.cycle_period_us = micros_u32(self.cycle_period);
        comm.sync_window_us = micros_u32(self.sync_window);
        comm.sync_counter_overflow =
            if crate::sync::valid_counter_overflow(self.sync_counter_overflow) {
                self.sync_counter_overflow
            } else {
                0
            };
        comm.time_cob_id = self.time_cob_id;
        #[cfg(feature = "heartbeat-consumer")]
        comm.set_consumers(
            self.consumers
                .get(..usize::from(self.consumer_slots))
                .unwrap_or(&[]),
        );
        Policies {
            heartbeat_on_change: self.heartbeat_on_change,
            sdo_timeout: self.sdo_timeout,
            error_field: self.error_field,
        }
    }

    /// The configuration whose [`PowerOn::restore`] writes `comm`, `pdos`
    /// and `policies` (times in the units of the objects).
    #[must_use]
    pub fn from_objects(comm: &CommObjects, pdos: &PdoConfig, policies: Policies) -> Self {
        let config = DeviceConfig {
            device_type: comm.device_type,
            device_name: comm.device_name,
            identity: comm.identity,
            heartbeat: Duration::from_millis(u64::from(comm.heartbeat_ms)),
            heartbeat_on_change: policies.heartbeat_on_change,
            sdo_timeout: policies.sdo_timeout,
            pdos: *pdos,
            error_field: policies.error_field,
            guard_time: Duration::from_millis(u64::from(comm.guard_time_ms)),
            life_time_factor: comm.life_time_factor,
            sync_cob_id: comm.sync_cob_id,
            cycle_period: Duration::from_micros(u64::from(comm.cycle_period_us)),
            sync_window: Duration::from_micros(u64::from(comm.sync_window_us)),
            sync_counter_overflow: comm.sync_counter_overflow,
            time_cob_id: comm.time_cob_id,
            ..DeviceConfig::new(comm.node())
        };
        #[cfg(feature = "heartbeat-consumer")]
        let config = config.with_consumers(comm.consumers());
        config
    }
}

/// The settings of a [`Device`](super::Device) that are not objects, as
/// [`PowerOn::restore`] gives them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Policies {
    /// Send a heartbeat at once when the NMT state changes
    /// ([`DeviceConfig::heartbeat_on_change`]).
    pub heartbeat_on_change: bool,
    /// SDO server timeout.
    pub sdo_timeout: Duration,
    /// How an EMCY is recorded in 1003h.
    pub error_field: ErrorFieldFormat,
}

impl Policies {
    /// A profile's policies: the heartbeat at the next period after a
    /// state change, the SDO server timeout in whole milliseconds, 1003h
    /// entries as `error_field` says.
    #[must_use]
    pub const fn of_profile(sdo_timeout_ms: u32, error_field: ErrorFieldFormat) -> Self {
        Policies {
            heartbeat_on_change: false,
            sdo_timeout: Duration::from_millis(sdo_timeout_ms as u64),
            error_field,
        }
    }

    /// The server of `node` with these policies.
    pub(super) fn server_config(&self, node: NodeId) -> ServerConfig {
        ServerConfig {
            timeout: self.sdo_timeout,
            ..ServerConfig::for_node(node)
        }
    }
}

/// Where a [`Device`](super::Device) gets the configuration its NMT resets
/// restore: a stored [`DeviceConfig`] (the default), or a smaller value it
/// is rebuilt from at boot and at every reset (a profile's own
/// configuration: `BatteryModulePowerOn`, `ChargerPowerOn`), so that the
/// device does not keep a second copy of it. The values are written into
/// the device's dictionary in place ([`restore`](Self::restore)): no
/// configuration is built and copied at boot or at a reset.
///
/// ```
/// use canopen_codec::device::{CommObjects, DeviceConfig, PowerOn};
/// use canopen_codec::pdo::PdoConfig;
/// use canopen_codec::NodeId;
/// let config = DeviceConfig { device_type: 0x0001_0191, ..DeviceConfig::new(NodeId::MIN) };
/// let (mut comm, mut pdos) = (CommObjects::new(NodeId::MAX), PdoConfig::new());
/// let policies = config.restore(&mut comm, &mut pdos);
/// assert_eq!((comm.node(), comm.device_type, comm.heartbeat_ms), (NodeId::MIN, 0x0001_0191, 1000));
/// assert_eq!(policies.sdo_timeout, config.sdo_timeout);
/// assert_eq!(config.power_on_config(), config);
/// ```
pub trait PowerOn {
    /// The node-ID.
    fn node(&self) -> NodeId;

    /// Writes the power-on values of the communication objects into `comm`
    /// (all of them: 1001h and 1003h empty, the node-ID
    /// [`node`](Self::node)'s) and the PDO configuration into `pdos`, and
    /// gives the device's other settings.
    fn restore<const T: usize, const R: usize>(
        &self,
        comm: &mut CommObjects,
        pdos: &mut PdoConfig<T, R>,
    ) -> Policies;

    /// The power-on configuration as a [`DeviceConfig`] (made by
    /// [`restore`](Self::restore); times in the units of the objects).
    fn power_on_config(&self) -> DeviceConfig {
        let (mut comm, mut pdos) = (CommObjects::new(self.node()), PdoConfig::new());
        let policies = self.restore(&mut comm, &mut pdos);
        DeviceConfig::from_objects(&comm, &pdos, policies)
    }

    /// The node-ID becomes `node` before the device is built (an LSS slave
    /// that has one, [`Device::with_lss`](super::Device::with_lss)).
    fn set_node(&mut self, node: NodeId);

    /// The node-ID becomes `node` at a reset (CiA 305: the LSS node-ID
    /// configured since takes effect), with the PDO COB-IDs that follow it.
    /// The default is [`set_node`](Self::set_node), right for a
    /// configuration whose PDO COB-IDs are made from its node-ID.
    #[cfg(feature = "lss")]
    fn move_node(&mut self, node: NodeId) {
        self.set_node(node);
    }
}

impl PowerOn for DeviceConfig {
    fn node(&self) -> NodeId {
        self.node
    }

    fn restore<const T: usize, const R: usize>(
        &self,
        comm: &mut CommObjects,
        pdos: &mut PdoConfig<T, R>,
    ) -> Policies {
        pdos.copy_from(&self.pdos);
        self.restore_into(comm)
    }

    fn power_on_config(&self) -> DeviceConfig {
        *self
    }

    fn set_node(&mut self, node: NodeId) {
        self.node = node;
    }

    /// The PDO COB-IDs of the predefined connection set for the old
    /// node-ID move to the new one; COB-IDs set otherwise stay.
    #[cfg(feature = "lss")]
    fn move_node(&mut self, node: NodeId) {
        renumber_pdos(&mut self.pdos, self.node, node);
        self.node = node;
    }
}

/// Moves the PDO COB-IDs that are the predefined connection set's for
/// node `old` (CiA 301 section 7.3.5: 180h/200h + 100h × n + node-ID) to
/// node `new`; COB-IDs set otherwise stay.
#[cfg(feature = "lss")]
fn renumber_pdos(pdos: &mut PdoConfig, old: NodeId, new: NodeId) {
    for dir in [PdoDirection::Receive, PdoDirection::Transmit] {
        let base: u32 = match dir {
            PdoDirection::Receive => 0x200,
            PdoDirection::Transmit => 0x180,
        };
        for n in 0..4u8 {
            let Some(pdo) = crate::cob_id::PdoNumber::new(n) else {
                continue;
            };
            let Some(slot) = pdos.get_mut(dir, pdo) else {
                continue;
            };
            let default = base + 0x100 * u32::from(n);
            let cob = slot.comm.cob_id;
            if !cob.is_extended() && cob.id_bits() == default + u32::from(old.raw()) {
                let flags = cob.to_u32() & !0x1FFF_FFFF;
                slot.comm.cob_id =
                    crate::pdo::PdoCobId::from_u32(flags | (default + u32::from(new.raw())));
            }
        }
    }
}
