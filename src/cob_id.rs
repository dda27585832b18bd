//! Node ids and the CiA 301 predefined connection set.
//!
//! [`classify`] maps any identifier to the communication object it carries
//! under the CiA 301 predefined connection set (NMT 000h, SYNC 080h, EMCY
//! 080h + node, TIME 100h, TPDO 1-4 180h/280h/380h/480h + node, RPDO 1-4
//! 200h/300h/400h/500h + node, SDO 580h/600h + node, heartbeat 700h + node,
//! LSS 7E4h/7E5h); [`CobKind::cob_id`]
//! maps back. 29-bit identifiers are outside the predefined set and classify as
//! [`CobKind::Unknown`].
//!
//! **PDO numbering.** This crate numbers PDOs from 0 ([`PdoNumber`]), as the
//! Delta-Q document does and as the communication parameter indexes do
//! (RPDO n lives at 1400h + n, TPDO n at 1800h + n). CiA 301 and CiA 418 count
//! from 1: CiA 301's "TPDO1" and CiA 418's "1st TPDO" are `PdoNumber` 0 here;
//! [`PdoNumber::cia_number`] gives the 1-based number.

use core::fmt;

use crate::frame::CanId;

/// A CANopen node id, `1..=127`.
///
/// ```
/// use canopen_codec::NodeId;
/// assert_eq!(NodeId::new(10).map(NodeId::raw), Some(10));
/// assert!(NodeId::new(0).is_none());
/// assert!(NodeId::new(128).is_none());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(u8);

impl NodeId {
    /// The smallest node id, 1.
    pub const MIN: NodeId = NodeId(1);
    /// The largest node id, 127.
    pub const MAX: NodeId = NodeId(127);

    /// `Some` for `1..=127`, `None` otherwise.
    #[must_use]
    #[inline]
    pub const fn new(raw: u8) -> Option<Self> {
        if raw >= 1 && raw <= 127 {
            Some(NodeId(raw))
        } else {
            None
        }
    }

    /// The id as a number.
    #[must_use]
    pub const fn raw(self) -> u8 {
        self.0
    }
}

impl fmt::Display for NodeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl From<NodeId> for u8 {
    fn from(n: NodeId) -> u8 {
        n.0
    }
}

/// A PDO number, `0..=3`, counted from 0 (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PdoNumber(u8);

impl PdoNumber {
    /// PDO 0 (CiA 301 "PDO1", CiA 418 "1st").
    pub const P0: PdoNumber = PdoNumber(0);
    /// PDO 1 (CiA 301 "PDO2", CiA 418 "2nd").
    pub const P1: PdoNumber = PdoNumber(1);
    /// PDO 2 (CiA 301 "PDO3", CiA 418 "3rd").
    pub const P2: PdoNumber = PdoNumber(2);
    /// PDO 3 (CiA 301 "PDO4"; Delta-Q's manufacturer TPDO 3 / RPDO 3).
    pub const P3: PdoNumber = PdoNumber(3);

    /// `Some` for `0..=3`.
    #[must_use]
    #[inline]
    pub const fn new(n: u8) -> Option<Self> {
        if n <= 3 {
            Some(PdoNumber(n))
        } else {
            None
        }
    }

    /// The zero-based number (Delta-Q numbering).
    #[must_use]
    pub const fn raw(self) -> u8 {
        self.0
    }

    /// The one-based number CiA 301 uses ("TPDO1" for `P0`).
    #[must_use]
    pub const fn cia_number(self) -> u8 {
        self.0 + 1
    }
}

impl fmt::Display for PdoNumber {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Which LSS direction a frame on 0x7E4/0x7E5 travels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssDirection {
    /// 0x7E5: LSS master to slaves.
    MasterToSlave,
    /// 0x7E4: LSS slave to master.
    SlaveToMaster,
}

/// What an identifier carries under the CiA 301 predefined connection set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CobKind {
    /// 0x000: NMT module control.
    Nmt,
    /// 0x080: SYNC.
    Sync,
    /// 0x080 + node: emergency.
    Emcy(NodeId),
    /// 0x100: TIME stamp.
    Time,
    /// 0x180/0x280/0x380/0x480 + node: transmit PDO of `node`.
    Tpdo(PdoNumber, NodeId),
    /// 0x200/0x300/0x400/0x500 + node: receive PDO of `node`.
    Rpdo(PdoNumber, NodeId),
    /// 0x580 + node: SDO server to client (the server's transmit SDO).
    SdoTx(NodeId),
    /// 0x600 + node: SDO client to server (the server's receive SDO).
    SdoRx(NodeId),
    /// 0x700 + node: NMT error control (heartbeat, boot-up, node guarding).
    NmtErrorControl(NodeId),
    /// 0x7E4 / 0x7E5: layer setting services.
    Lss(LssDirection),
    /// Anything else, including every 29-bit identifier.
    Unknown,
}

/// The type of a COB-ID object's Unsigned32 whose identifier a device
/// produces or consumes on (CiA 301 section 7.5.2: 1005h COB-ID SYNC,
/// 1012h COB-ID TIME): bit 29 the frame format, bits 28-0 the identifier
/// ([`can_id_of_cob_word`]), and the object's own flags in bits 31-30,
/// one row each (the constant, its bit, the getter, the setter, what it
/// says); every bit is kept as written. `DEFAULT` is CiA 301's default
/// value and the [`Default`].
macro_rules! cob_id_word {
    (
        $(#[$meta:meta])*
        $name:ident, $object:literal,
        $(#[$default_meta:meta])*
        DEFAULT = $default:expr,
        flags: [$(($flag:ident, $bit:literal, $get:ident, $set:ident, $what:literal)),* $(,)?] $(,)?
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $name(u32);

        impl $name {
            $(
                #[doc = concat!("Bit ", $bit, ": ", $what, ".")]
                pub const $flag: u32 = 1 << $bit;
            )*
            /// Bit 29: 29-bit identifier.
            pub const EXTENDED: u32 = 0x2000_0000;
            $(#[$default_meta])*
            pub const DEFAULT: $name = $name($default as u32);

            #[doc = concat!("From the Unsigned32 of ", $object, ".")]
            #[must_use]
            pub const fn from_raw(raw: u32) -> Self {
                $name(raw)
            }

            /// The Unsigned32.
            #[must_use]
            pub const fn raw(self) -> u32 {
                self.0
            }

            /// The identifier (`None` when an 11-bit one is above 7FFh).
            #[must_use]
            pub const fn id(self) -> Option<$crate::frame::CanId> {
                $crate::cob_id::can_id_of_cob_word(self.0)
            }

            $(
                #[doc = concat!("True when ", $what, " (bit ", $bit, ").")]
                #[must_use]
                pub const fn $get(self) -> bool {
                    self.0 & Self::$flag != 0
                }

                #[doc = concat!("The same with bit ", $bit, " (", $what, ") set or cleared.")]
                #[must_use]
                pub const fn $set(self, on: bool) -> Self {
                    $name(if on { self.0 | Self::$flag } else { self.0 & !Self::$flag })
                }
            )*
        }

        impl Default for $name {
            fn default() -> Self {
                Self::DEFAULT
            }
        }
    };
}
pub(crate) use cob_id_word;

/// The CAN identifier a COB-ID entry names (CiA 301 section 7.5.2, the
/// COB-ID objects 1005h, 1012h, 14xxh/18xxh ...: bit 29 set, a 29-bit
/// identifier in bits 28-0; clear, an 11-bit one in bits 10-0). `None` for
/// an 11-bit entry with bits 28-11 set (no identifier). Bits 31 and 30 are
/// the object's own flags and are not looked at.
pub(crate) const fn can_id_of_cob_word(word: u32) -> Option<CanId> {
    if word & (1 << 29) != 0 {
        Some(CanId::Extended(word & 0x1FFF_FFFF))
    } else if word & 0x1FFF_F800 != 0 {
        None
    } else {
        Some(CanId::Standard((word & 0x7FF) as u16))
    }
}

/// COB-ID base of NMT.
pub const NMT: u16 = 0x000;
/// COB-ID of SYNC (and base of EMCY).
pub const SYNC: u16 = 0x080;
/// COB-ID base of EMCY (+ node).
pub const EMCY_BASE: u16 = 0x080;
/// COB-ID of TIME.
pub const TIME: u16 = 0x100;
/// COB-ID bases of TPDO 0..3 (+ node).
pub const TPDO_BASE: [u16; 4] = [0x180, 0x280, 0x380, 0x480];
/// COB-ID bases of RPDO 0..3 (+ node).
pub const RPDO_BASE: [u16; 4] = [0x200, 0x300, 0x400, 0x500];
/// COB-ID base of the server-to-client SDO (+ node).
pub const SDO_TX_BASE: u16 = 0x580;
/// COB-ID base of the client-to-server SDO (+ node).
pub const SDO_RX_BASE: u16 = 0x600;
/// COB-ID base of NMT error control (+ node).
pub const NMT_ERROR_CONTROL_BASE: u16 = 0x700;
/// LSS slave-to-master identifier.
pub const LSS_SLAVE_TO_MASTER: u16 = 0x7E4;
/// LSS master-to-slave identifier.
pub const LSS_MASTER_TO_SLAVE: u16 = 0x7E5;

/// Classifies an identifier under the predefined connection set.
///
/// ```
/// use canopen_codec::cob_id::{classify, CobKind};
/// use canopen_codec::{CanId, NodeId, PdoNumber};
/// let n10 = NodeId::new(10).unwrap();
/// assert_eq!(classify(CanId::Standard(0x08A)), CobKind::Emcy(n10));
/// assert_eq!(classify(CanId::Standard(0x18A)), CobKind::Tpdo(PdoNumber::P0, n10));
/// assert_eq!(classify(CanId::Standard(0x080)), CobKind::Sync);
/// assert_eq!(classify(CanId::Extended(0x080)), CobKind::Unknown);
/// ```
#[must_use]
#[inline]
pub fn classify(id: CanId) -> CobKind {
    match id {
        CanId::Standard(raw) => classify_standard(raw),
        CanId::Extended(_) => CobKind::Unknown,
    }
}

/// [`classify`] for an 11-bit identifier given as a number.
#[must_use]
#[inline]
pub fn classify_standard(raw: u16) -> CobKind {
    let node = NodeId::new((raw & 0x7F) as u8);
    match (function_of(raw), node) {
        (Function::Nmt, None) if raw == NMT => CobKind::Nmt,
        (Function::SyncOrEmcy, None) => CobKind::Sync,
        (Function::SyncOrEmcy, Some(n)) => CobKind::Emcy(n),
        (Function::Time, None) => CobKind::Time,
        (Function::Tpdo(p), Some(n)) => CobKind::Tpdo(p, n),
        (Function::Rpdo(p), Some(n)) => CobKind::Rpdo(p, n),
        (Function::SdoTx, Some(n)) => CobKind::SdoTx(n),
        (Function::SdoRx, Some(n)) => CobKind::SdoRx(n),
        (Function::ErrorControl, Some(n)) => CobKind::NmtErrorControl(n),
        (Function::Lss, _) if raw == LSS_SLAVE_TO_MASTER => {
            CobKind::Lss(LssDirection::SlaveToMaster)
        }
        (Function::Lss, _) if raw == LSS_MASTER_TO_SLAVE => {
            CobKind::Lss(LssDirection::MasterToSlave)
        }
        _ => CobKind::Unknown,
    }
}

/// What the function code of an 11-bit identifier (bits 10-7) names in
/// the predefined connection set (CiA 301 section 7.3.3): the one table
/// behind [`classify`] and [`Message::decode`](crate::Message::decode).
/// Which node (bits 6-0) an identifier belongs to, and whether 0 is
/// allowed, is the caller's second step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Function {
    /// 000h: NMT (node bits 0).
    Nmt,
    /// 080h: SYNC (node bits 0) or EMCY (a node).
    SyncOrEmcy,
    /// 100h: TIME (node bits 0).
    Time,
    /// A transmit PDO of a node.
    Tpdo(PdoNumber),
    /// A receive PDO of a node.
    Rpdo(PdoNumber),
    /// 580h: SDO server to client.
    SdoTx,
    /// 600h: SDO client to server.
    SdoRx,
    /// 700h: NMT error control.
    ErrorControl,
    /// 780h: LSS (7E4h, 7E5h).
    Lss,
    /// 680h: not assigned.
    Unassigned,
}

/// [`Function`] of every function code.
const FUNCTIONS: [Function; 16] = [
    Function::Nmt,
    Function::SyncOrEmcy,
    Function::Time,
    Function::Tpdo(PdoNumber::P0),
    Function::Rpdo(PdoNumber::P0),
    Function::Tpdo(PdoNumber::P1),
    Function::Rpdo(PdoNumber::P1),
    Function::Tpdo(PdoNumber::P2),
    Function::Rpdo(PdoNumber::P2),
    Function::Tpdo(PdoNumber::P3),
    Function::Rpdo(PdoNumber::P3),
    Function::SdoTx,
    Function::SdoRx,
    Function::Unassigned,
    Function::ErrorControl,
    Function::Lss,
];

/// The [`Function`] of an 11-bit identifier.
#[inline]
pub(crate) const fn function_of(raw: u16) -> Function {
    FUNCTIONS[((raw >> 7) & 0xF) as usize]
}

impl CobKind {
    /// The 11-bit identifier of this object, or `None` for [`CobKind::Unknown`].
    #[must_use]
    #[inline]
    pub const fn cob_id(self) -> Option<u16> {
        Some(match self {
            CobKind::Nmt => NMT,
            CobKind::Sync => SYNC,
            CobKind::Emcy(n) => EMCY_BASE + n.0 as u16,
            CobKind::Time => TIME,
            CobKind::Tpdo(p, n) => TPDO_BASE[(p.0 & 3) as usize] + n.0 as u16,
            CobKind::Rpdo(p, n) => RPDO_BASE[(p.0 & 3) as usize] + n.0 as u16,
            CobKind::SdoTx(n) => SDO_TX_BASE + n.0 as u16,
            CobKind::SdoRx(n) => SDO_RX_BASE + n.0 as u16,
            CobKind::NmtErrorControl(n) => NMT_ERROR_CONTROL_BASE + n.0 as u16,
            CobKind::Lss(LssDirection::SlaveToMaster) => LSS_SLAVE_TO_MASTER,
            CobKind::Lss(LssDirection::MasterToSlave) => LSS_MASTER_TO_SLAVE,
            CobKind::Unknown => return None,
        })
    }

    /// The node this object belongs to, if it is node-specific.
    #[must_use]
    #[inline]
    pub const fn node(self) -> Option<NodeId> {
        match self {
            CobKind::Emcy(n)
            | CobKind::Tpdo(_, n)
            | CobKind::Rpdo(_, n)
            | CobKind::SdoTx(n)
            | CobKind::SdoRx(n)
            | CobKind::NmtErrorControl(n) => Some(n),
            _ => None,
        }
    }
}

/// The node-ID a test names (it must be one, `1..=127`).
#[cfg(test)]
pub(crate) fn test_node(raw: u8) -> NodeId {
    NodeId::new(raw).expect("a test's node-ID is 1..=127")
}

#[cfg(test)]
mod tests {
    use super::*;
    use test_node as n;

    /// The default COB-ID table of "Delta-Q IC Series CANopen interface
    /// specification rev 2.0", section 4.3.2, row by row, for the charger
    /// (0x0A) and the battery module (0x01).
    #[test]
    fn deltaq_default_cob_id_table() {
        let rows: [(u16, u16, CobKind); 10] = [
            (0x60A, 0x601, CobKind::SdoRx(n(1))),
            (0x58A, 0x581, CobKind::SdoTx(n(1))),
            (0x20A, 0x201, CobKind::Rpdo(PdoNumber::P0, n(1))),
            (0x30A, 0x301, CobKind::Rpdo(PdoNumber::P1, n(1))),
            (0x40A, 0x401, CobKind::Rpdo(PdoNumber::P2, n(1))),
            (0x50A, 0x501, CobKind::Rpdo(PdoNumber::P3, n(1))),
            (0x18A, 0x181, CobKind::Tpdo(PdoNumber::P0, n(1))),
            (0x28A, 0x281, CobKind::Tpdo(PdoNumber::P1, n(1))),
            (0x38A, 0x381, CobKind::Tpdo(PdoNumber::P2, n(1))),
            (0x48A, 0x481, CobKind::Tpdo(PdoNumber::P3, n(1))),
        ];
        for (charger, battery, kind_for_battery) in rows {
            assert_eq!(classify_standard(battery), kind_for_battery, "{battery:#X}");
            assert_eq!(kind_for_battery.cob_id(), Some(battery));
            let charger_kind = classify_standard(charger);
            assert_eq!(charger_kind.node(), Some(n(10)), "{charger:#X}");
            assert_eq!(charger_kind.cob_id(), Some(charger));
        }
    }

    #[test]
    fn function_codes() {
        // (identifier, what the predefined connection set makes of it)
        #[rustfmt::skip]
        let cases = [
            (0x000, CobKind::Nmt),
            (0x080, CobKind::Sync),
            (0x081, CobKind::Emcy(n(1))),
            (0x0FF, CobKind::Emcy(n(127))),
            (0x100, CobKind::Time),
            (0x101, CobKind::Unknown),
            (0x001, CobKind::Unknown),
            (0x180, CobKind::Unknown),
            (0x5FF, CobKind::SdoTx(n(127))),
            (0x67F, CobKind::SdoRx(n(127))),
            (0x680, CobKind::Unknown),
            (0x700, CobKind::Unknown),
            (0x701, CobKind::NmtErrorControl(n(1))),
            (0x77F, CobKind::NmtErrorControl(n(127))),
            (0x7E4, CobKind::Lss(LssDirection::SlaveToMaster)),
            (0x7E5, CobKind::Lss(LssDirection::MasterToSlave)),
            (0x7E6, CobKind::Unknown),
            (0x7FF, CobKind::Unknown),
        ];
        for (id, kind) in cases {
            assert_eq!(classify_standard(id), kind, "{id:03X}h");
        }
        assert_eq!(classify(CanId::Extended(0x181)), CobKind::Unknown);
    }

    #[test]
    fn every_standard_id_round_trips() {
        for raw in 0..=0x7FFu16 {
            let kind = classify_standard(raw);
            match kind.cob_id() {
                Some(id) => assert_eq!(id, raw),
                None => assert_eq!(kind, CobKind::Unknown),
            }
        }
    }

    #[test]
    fn numbering() {
        assert_eq!(PdoNumber::P0.cia_number(), 1);
        assert_eq!(PdoNumber::new(4), None);
        assert_eq!(NodeId::MIN.raw(), 1);
        assert_eq!(NodeId::MAX.raw(), 127);
    }
}
