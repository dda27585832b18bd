//! [`DeviceConfig`]: the power-on values of a device's communication
//! objects and its policies.

use core::time::Duration;

use super::objects::{CommObjects, ErrorFieldFormat, Identity, MAX_CONSUMERS};
use crate::cob_id::NodeId;
use crate::heartbeat::ConsumerEntry;
use crate::pdo::PdoConfig;
use crate::sdo::{ServerConfig, DEFAULT_TIMEOUT};
use crate::time::millis_u16;

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
    /// 1016h entries: the first `consumer_slots` are the sub-indexes.
    pub consumers: [ConsumerEntry; MAX_CONSUMERS],
    /// 1016h sub 0 (0: the device has no 1016h).
    pub consumer_slots: u8,
    /// SDO server timeout.
    pub sdo_timeout: Duration,
    /// The PDO configuration (1400h-1A03h) at power-on.
    pub pdos: PdoConfig,
    /// How an EMCY is recorded in 1003h.
    pub error_field: ErrorFieldFormat,
}

impl DeviceConfig {
    /// Node `node`: device type 0, no name, heartbeat 1000 ms, no consumer
    /// entries, SDO timeout 2000 ms, no PDOs, standard 1003h entries.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        DeviceConfig {
            node,
            device_type: 0,
            device_name: "",
            identity: Identity::ZERO,
            heartbeat: Duration::from_millis(1000),
            heartbeat_on_change: false,
            consumers: [ConsumerEntry {
                node: 0,
                time_ms: 0,
            }; MAX_CONSUMERS],
            consumer_slots: 0,
            sdo_timeout: DEFAULT_TIMEOUT,
            pdos: PdoConfig::new(),
            error_field: ErrorFieldFormat::LittleEndianInfo,
        }
    }

    /// The same with 1016h holding `entries` (at most [`MAX_CONSUMERS`]).
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

    pub(super) fn comm_objects(&self) -> CommObjects {
        let mut comm = CommObjects::new(self.node);
        comm.device_type = self.device_type;
        comm.device_name = self.device_name;
        comm.identity = self.identity;
        comm.heartbeat_ms = millis_u16(self.heartbeat);
        comm.set_consumers(
            self.consumers
                .get(..usize::from(self.consumer_slots))
                .unwrap_or(&[]),
        );
        comm
    }

    pub(super) fn server_config(&self) -> ServerConfig {
        ServerConfig {
            timeout: self.sdo_timeout,
            ..ServerConfig::for_node(self.node)
        }
    }
}
