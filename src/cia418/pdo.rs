//! The default PDO set of a CiA 418 battery module (CiA 418 sections
//! 6.2.3-6.2.8, DIGEST section 6), as data.
//!
//! All six PDOs are asynchronous (transmission type 255). RPDO COB-IDs
//! default to `0x200/0x300/0x400 + node`; the profile allows bit 30 ("no RTR")
//! to be set as well (`4000 0200h + node`), and this table gives the form
//! without it. TPDO COB-IDs default to "not valid" (bit 31 set): the module's
//! application enables them.

use crate::cob_id::{NodeId, PdoNumber};

use super::{
    DeviceType, AH_RETURNED_DURING_LAST_CHARGE, BATTERY_STATE_OF_CHARGE, BATTERY_STATUS,
    BATTERY_VOLTAGE, CHARGER_STATE_OF_CHARGE, CHARGER_STATUS, CHARGE_CURRENT_REQUESTED,
    TEMPERATURE,
};

pub use crate::pdo::PdoDirection;

/// One default PDO of a CiA 418 battery module.
///
/// ```
/// use canopen_codec::cia418::{DEFAULT_PDOS, DeviceType};
/// use canopen_codec::NodeId;
/// let first_tpdo = &DEFAULT_PDOS[3];
/// assert_eq!(first_tpdo.communication_index, 0x1800);
/// assert_eq!(first_tpdo.cob_id(NodeId::new(1).unwrap()), 0x8000_0181);
/// assert_eq!(first_tpdo.entries, &[(0x6010, 0, 16), (0x6000, 0, 8)]);
/// assert!(first_tpdo.is_present(DeviceType::cia418(0)));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DefaultPdo {
    /// Receive or transmit, seen from the module.
    pub direction: PdoDirection,
    /// PDO number, counted from 0 (CiA 418's "1st" is `P0`).
    pub number: PdoNumber,
    /// Communication parameter index (1400h + n or 1800h + n).
    pub communication_index: u16,
    /// Mapping parameter index (1600h + n or 1A00h + n).
    pub mapping_index: u16,
    /// Default COB-ID without the node id (bit 31 set for the TPDOs: not
    /// valid); see [`DefaultPdo::cob_id`].
    pub cob_id_base: u32,
    /// Transmission type (255: asynchronous, event-driven).
    pub transmission_type: u8,
    /// Default event timer in ms (sub 5): 200 for TPDOs, 0 (off) for RPDOs.
    pub event_timer_ms: u16,
    /// Default mapping entries as (index, sub-index, length in bits).
    pub entries: &'static [(u16, u8, u8)],
    /// The device-type (1000h) bit that says the PDO exists; `None` for the
    /// mandatory 1st RPDO and 1st TPDO.
    pub enabled_by: Option<u32>,
}

impl DefaultPdo {
    /// The default COB-ID (comm. parameter sub 1) for a module with id `node`.
    #[must_use]
    pub const fn cob_id(&self, node: NodeId) -> u32 {
        self.cob_id_base.wrapping_add(node.raw() as u32)
    }

    /// True if a module with device type `device_type` has this PDO.
    #[must_use]
    pub const fn is_present(&self, device_type: DeviceType) -> bool {
        match self.enabled_by {
            None => true,
            Some(bit) => device_type.has(bit),
        }
    }

    /// The mapping entries as CiA 301 Unsigned32 values (index << 16 | sub
    /// << 8 | bits), sub 1 first.
    pub fn mapping_values(&self) -> impl Iterator<Item = u32> + '_ {
        self.entries.iter().map(|&(index, sub, bits)| {
            u32::from(index) << 16 | u32::from(sub) << 8 | u32::from(bits)
        })
    }

    /// Total mapped length in bits.
    #[must_use]
    pub fn total_bits(&self) -> u32 {
        self.entries
            .iter()
            .map(|&(_, _, bits)| u32::from(bits))
            .sum()
    }
}

const TT_ASYNC: u8 = 255;

/// The CiA 418 default PDOs: 1st, 2nd, 3rd RPDO, then 1st, 2nd, 3rd TPDO
/// (DIGEST section 6, "Default PDOs of the battery module").
pub const DEFAULT_PDOS: [DefaultPdo; 6] = [
    DefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P0,
        communication_index: 0x1400,
        mapping_index: 0x1600,
        cob_id_base: 0x200,
        transmission_type: TT_ASYNC,
        event_timer_ms: 0,
        entries: &[(CHARGER_STATUS, 0, 8)],
        enabled_by: None,
    },
    DefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P1,
        communication_index: 0x1401,
        mapping_index: 0x1601,
        cob_id_base: 0x300,
        transmission_type: TT_ASYNC,
        event_timer_ms: 0,
        entries: &[
            (CHARGER_STATUS, 0, 8),
            (AH_RETURNED_DURING_LAST_CHARGE, 0, 16),
        ],
        enabled_by: Some(DeviceType::RPDO_2ND),
    },
    DefaultPdo {
        direction: PdoDirection::Receive,
        number: PdoNumber::P2,
        communication_index: 0x1402,
        mapping_index: 0x1602,
        cob_id_base: 0x400,
        transmission_type: TT_ASYNC,
        event_timer_ms: 0,
        entries: &[
            (CHARGER_STATUS, 0, 8),
            (AH_RETURNED_DURING_LAST_CHARGE, 0, 16),
            (CHARGER_STATE_OF_CHARGE, 0, 8),
        ],
        enabled_by: Some(DeviceType::RPDO_3RD),
    },
    DefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P0,
        communication_index: 0x1800,
        mapping_index: 0x1A00,
        cob_id_base: 0x8000_0180,
        transmission_type: TT_ASYNC,
        event_timer_ms: 200,
        entries: &[(TEMPERATURE, 0, 16), (BATTERY_STATUS, 0, 8)],
        enabled_by: None,
    },
    DefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P1,
        communication_index: 0x1801,
        mapping_index: 0x1A01,
        cob_id_base: 0x8000_0280,
        transmission_type: TT_ASYNC,
        event_timer_ms: 200,
        entries: &[
            (TEMPERATURE, 0, 16),
            (BATTERY_STATUS, 0, 8),
            (BATTERY_VOLTAGE, 0, 32),
        ],
        enabled_by: Some(DeviceType::TPDO_2ND),
    },
    DefaultPdo {
        direction: PdoDirection::Transmit,
        number: PdoNumber::P2,
        communication_index: 0x1802,
        mapping_index: 0x1A02,
        cob_id_base: 0x8000_0380,
        transmission_type: TT_ASYNC,
        event_timer_ms: 200,
        entries: &[
            (CHARGE_CURRENT_REQUESTED, 0, 16),
            (BATTERY_STATE_OF_CHARGE, 0, 8),
        ],
        enabled_by: Some(DeviceType::TPDO_3RD),
    },
];
