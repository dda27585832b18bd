//! 6020h battery parameters (record `BatteryPar`, CiA 418 sections 7.2.1 and
//! 7.3.4) and the battery type byte `cccc wxyz` (CiA 418 v1.0.1, 7.3.4 and
//! appendix A): the high nibble `cccc` is the chemistry, the low nibble
//! `wxyz` its variant; unlisted chemistries (0000, 0100, 1111) decode to an
//! unknown variant that keeps the byte.

use core::fmt;

use crate::bytes::InlineData;
use crate::error::DecodeError;

use super::{read_u16, read_u8, BATTERY_PARAMETERS};

/// The chemistry nibble `cccc` of a battery type (bits 7-4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Chemistry {
    /// 0001: lead acid.
    LeadAcid,
    /// 0010: nickel cadmium.
    NickelCadmium,
    /// 0011: nickel zinc.
    NickelZinc,
    /// 0101: nickel iron.
    NickelIron,
    /// 0110: silver oxide.
    SilverOxide,
    /// 0111: nickel hydrogen.
    NickelHydrogen,
    /// 1000: nickel metal hydride.
    NickelMetalHydride,
    /// 1001: zinc / alkaline / manganese dioxide.
    ZincAlkalineManganeseDioxide,
    /// 1010: lithium ion.
    LithiumIon,
    /// 1011: zinc bromine.
    ZincBromine,
    /// 1100: metal air.
    MetalAir,
    /// 1101: lithium / iron sulfide.
    LithiumIronSulfide,
    /// 1110: sodium beta.
    SodiumBeta,
    /// 0000, 0100, 1111: not listed by CiA 418; the nibble is kept.
    Unknown(u8),
}

impl Chemistry {
    /// The chemistry of a nibble (only the low 4 bits of `code` count).
    #[must_use]
    pub const fn from_code(code: u8) -> Self {
        match code & 0x0F {
            0b0001 => Self::LeadAcid,
            0b0010 => Self::NickelCadmium,
            0b0011 => Self::NickelZinc,
            0b0101 => Self::NickelIron,
            0b0110 => Self::SilverOxide,
            0b0111 => Self::NickelHydrogen,
            0b1000 => Self::NickelMetalHydride,
            0b1001 => Self::ZincAlkalineManganeseDioxide,
            0b1010 => Self::LithiumIon,
            0b1011 => Self::ZincBromine,
            0b1100 => Self::MetalAir,
            0b1101 => Self::LithiumIronSulfide,
            0b1110 => Self::SodiumBeta,
            other => Self::Unknown(other),
        }
    }

    /// The 4-bit code (`Unknown` keeps its low nibble).
    #[must_use]
    pub const fn code(self) -> u8 {
        match self {
            Self::LeadAcid => 0b0001,
            Self::NickelCadmium => 0b0010,
            Self::NickelZinc => 0b0011,
            Self::NickelIron => 0b0101,
            Self::SilverOxide => 0b0110,
            Self::NickelHydrogen => 0b0111,
            Self::NickelMetalHydride => 0b1000,
            Self::ZincAlkalineManganeseDioxide => 0b1001,
            Self::LithiumIon => 0b1010,
            Self::ZincBromine => 0b1011,
            Self::MetalAir => 0b1100,
            Self::LithiumIronSulfide => 0b1101,
            Self::SodiumBeta => 0b1110,
            Self::Unknown(raw) => raw & 0x0F,
        }
    }
}

impl fmt::Display for Chemistry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Self::LeadAcid => "lead acid",
            Self::NickelCadmium => "nickel cadmium",
            Self::NickelZinc => "nickel zinc",
            Self::NickelIron => "nickel iron",
            Self::SilverOxide => "silver oxide",
            Self::NickelHydrogen => "nickel hydrogen",
            Self::NickelMetalHydride => "nickel metal hydride",
            Self::ZincAlkalineManganeseDioxide => "zinc / alkaline / manganese dioxide",
            Self::LithiumIon => "lithium ion",
            Self::ZincBromine => "zinc bromine",
            Self::MetalAir => "metal air",
            Self::LithiumIronSulfide => "lithium / iron sulfide",
            Self::SodiumBeta => "sodium beta",
            Self::Unknown(code) => return write!(f, "unknown chemistry {code:04b}"),
        };
        f.write_str(name)
    }
}

/// Electrolyte gravity of a flooded lead-acid battery (bit y).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Gravity {
    /// y = 0.
    Normal,
    /// y = 1.
    High,
}

/// Plate construction of a flooded lead-acid battery (bit z).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Plate {
    /// z = 0.
    Flat,
    /// z = 1.
    Tubular,
}

/// Kind of a maintenance-free lead-acid battery (bits yz).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MaintenanceFree {
    /// yz = 00: absorbed glass mat.
    Agm,
    /// yz = 01: gel.
    Gel,
    /// yz = 10: hybrid.
    Hybrid,
    /// yz = 11: unused by CiA 418; kept.
    Unused,
}

/// Lead-acid sub-type (bit w, then y and z).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LeadAcid {
    /// w = 0: flooded.
    Flooded {
        /// Bit y.
        gravity: Gravity,
        /// Bit z.
        plate: Plate,
    },
    /// w = 1: maintenance free, kind in bits yz.
    MaintenanceFree(MaintenanceFree),
}

/// Nickel-cadmium cell construction (bit w).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NickelCadmiumCell {
    /// w = 0.
    Vented,
    /// w = 1.
    Sealed,
}

/// Nickel-cadmium plate construction (bit z).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NickelCadmiumPlate {
    /// z = 0.
    Pocket,
    /// z = 1.
    Sintered,
}

/// Silver-oxide couple (bits yz).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SilverOxide {
    /// yz = 00: silver zinc.
    AgZn,
    /// yz = 01: silver cadmium.
    AgCd,
    /// yz = 10: silver iron.
    AgFe,
    /// yz = 11: unused by CiA 418; kept.
    Unused,
}

/// Battery type, 6020h sub 1, one byte `cccc wxyz` (CiA 418 appendix A).
///
/// Each variant keeps the bits CiA 418 leaves reserved in `reserved`, at
/// their position in the byte (lead acid: bit x = 0x04; nickel cadmium: bits
/// x and y = 0x06; silver oxide: bits w and x = 0x0C; the other chemistries:
/// all of wxyz = 0x0F). Unlisted chemistry codes decode to
/// [`BatteryType::Unknown`] with the whole byte. So every byte round-trips;
/// encoding ignores `reserved` bits outside the variant's mask.
///
/// ```
/// use canopen_codec::cia418::{BatteryType, Gravity, LeadAcid, Plate, Chemistry};
/// let flooded = BatteryType::LeadAcid {
///     kind: LeadAcid::Flooded { gravity: Gravity::Normal, plate: Plate::Flat },
///     reserved: 0,
/// };
/// assert_eq!(u8::from(flooded), 0b0001_0000);
/// assert_eq!(BatteryType::from(0b0001_0000), flooded);
/// assert_eq!(flooded.chemistry(), Chemistry::LeadAcid);
/// assert_eq!(BatteryType::from(0x4F), BatteryType::Unknown(0x4F));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BatteryType {
    /// 0001: lead acid.
    LeadAcid {
        /// Flooded or maintenance-free, with its sub-type.
        kind: LeadAcid,
        /// Reserved bit x (mask 0x04).
        reserved: u8,
    },
    /// 0010: nickel cadmium.
    NickelCadmium {
        /// Bit w.
        cell: NickelCadmiumCell,
        /// Bit z.
        plate: NickelCadmiumPlate,
        /// Reserved bits x, y (mask 0x06).
        reserved: u8,
    },
    /// 0011: nickel zinc.
    NickelZinc {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 0101: nickel iron.
    NickelIron {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 0110: silver oxide.
    SilverOxide {
        /// Bits yz.
        couple: SilverOxide,
        /// Reserved bits w, x (mask 0x0C).
        reserved: u8,
    },
    /// 0111: nickel hydrogen.
    NickelHydrogen {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1000: nickel metal hydride.
    NickelMetalHydride {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1001: zinc / alkaline / manganese dioxide.
    ZincAlkalineManganeseDioxide {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1010: lithium ion.
    LithiumIon {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1011: zinc bromine.
    ZincBromine {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1100: metal air.
    MetalAir {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1101: lithium / iron sulfide.
    LithiumIronSulfide {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// 1110: sodium beta.
    SodiumBeta {
        /// Reserved bits wxyz (mask 0x0F).
        reserved: u8,
    },
    /// Chemistry 0000, 0100 or 1111: the whole byte, kept.
    Unknown(u8),
}

const W: u8 = 0b1000;
const Y: u8 = 0b0010;
const Z: u8 = 0b0001;
const YZ: u8 = Y | Z;

/// The variant fields coded in bits of the nibble `wxyz` (CiA 418
/// appendix A): for each, the bits `$mask` and the code of every value in
/// place (`Type: mask => Value code, ...`). `from_wxyz` reads a field from
/// the nibble (its codes cover every value of the bits), `wxyz` gives the
/// field's bits in place.
macro_rules! nibble_fields {
    ($($ty:ident: $mask:ident => $($value:ident $code:expr),+;)*) => {
        $(
            impl $ty {
                /// The value the nibble's bits code.
                const fn from_wxyz(sub: u8) -> Self {
                    let bits = sub & $mask;
                    $(
                        if bits == $code {
                            return Self::$value;
                        }
                    )+
                    // Not reached: the codes cover every value of the bits.
                    nibble_fields!(@last $($value)+)
                }

                /// The value's bits in place in the nibble.
                const fn wxyz(self) -> u8 {
                    match self {
                        $(Self::$value => $code,)+
                    }
                }
            }
        )*
    };
    (@last $first:ident $($rest:ident)*) => {
        Self::$first
    };
}

nibble_fields! {
    Gravity: Y => Normal 0, High Y;
    Plate: Z => Flat 0, Tubular Z;
    MaintenanceFree: YZ => Agm 0b00, Gel 0b01, Hybrid 0b10, Unused 0b11;
    NickelCadmiumCell: W => Vented 0, Sealed W;
    NickelCadmiumPlate: Z => Pocket 0, Sintered Z;
    SilverOxide: YZ => AgZn 0b00, AgCd 0b01, AgFe 0b10, Unused 0b11;
}

impl BatteryType {
    /// Decodes a battery-type byte (total: every byte has a meaning).
    #[must_use]
    pub const fn from_u8(raw: u8) -> Self {
        let sub = raw & 0x0F;
        match Chemistry::from_code(raw >> 4) {
            Chemistry::LeadAcid => {
                let kind = if sub & W == 0 {
                    LeadAcid::Flooded {
                        gravity: Gravity::from_wxyz(sub),
                        plate: Plate::from_wxyz(sub),
                    }
                } else {
                    LeadAcid::MaintenanceFree(MaintenanceFree::from_wxyz(sub))
                };
                Self::LeadAcid {
                    kind,
                    reserved: sub & 0b0100,
                }
            }
            Chemistry::NickelCadmium => Self::NickelCadmium {
                cell: NickelCadmiumCell::from_wxyz(sub),
                plate: NickelCadmiumPlate::from_wxyz(sub),
                reserved: sub & 0b0110,
            },
            Chemistry::SilverOxide => Self::SilverOxide {
                couple: SilverOxide::from_wxyz(sub),
                reserved: sub & 0b1100,
            },
            Chemistry::NickelZinc => Self::NickelZinc { reserved: sub },
            Chemistry::NickelIron => Self::NickelIron { reserved: sub },
            Chemistry::NickelHydrogen => Self::NickelHydrogen { reserved: sub },
            Chemistry::NickelMetalHydride => Self::NickelMetalHydride { reserved: sub },
            Chemistry::ZincAlkalineManganeseDioxide => {
                Self::ZincAlkalineManganeseDioxide { reserved: sub }
            }
            Chemistry::LithiumIon => Self::LithiumIon { reserved: sub },
            Chemistry::ZincBromine => Self::ZincBromine { reserved: sub },
            Chemistry::MetalAir => Self::MetalAir { reserved: sub },
            Chemistry::LithiumIronSulfide => Self::LithiumIronSulfide { reserved: sub },
            Chemistry::SodiumBeta => Self::SodiumBeta { reserved: sub },
            Chemistry::Unknown(_) => Self::Unknown(raw),
        }
    }

    /// Encodes the byte; `reserved` bits outside the variant's mask are
    /// ignored.
    #[must_use]
    pub const fn to_u8(self) -> u8 {
        // The codes as constants (not a `Chemistry` then its `code`: a
        // second switch).
        let (code, sub) = match self {
            Self::LeadAcid { kind, reserved } => {
                let bits = match kind {
                    LeadAcid::Flooded { gravity, plate } => gravity.wxyz() | plate.wxyz(),
                    LeadAcid::MaintenanceFree(m) => W | m.wxyz(),
                };
                (
                    const { Chemistry::LeadAcid.code() },
                    bits | (reserved & 0b0100),
                )
            }
            Self::NickelCadmium {
                cell,
                plate,
                reserved,
            } => (
                const { Chemistry::NickelCadmium.code() },
                cell.wxyz() | plate.wxyz() | (reserved & 0b0110),
            ),
            Self::SilverOxide { couple, reserved } => (
                const { Chemistry::SilverOxide.code() },
                couple.wxyz() | (reserved & 0b1100),
            ),
            Self::NickelZinc { reserved } => (const { Chemistry::NickelZinc.code() }, reserved),
            Self::NickelIron { reserved } => (const { Chemistry::NickelIron.code() }, reserved),
            Self::NickelHydrogen { reserved } => {
                (const { Chemistry::NickelHydrogen.code() }, reserved)
            }
            Self::NickelMetalHydride { reserved } => {
                (const { Chemistry::NickelMetalHydride.code() }, reserved)
            }
            Self::ZincAlkalineManganeseDioxide { reserved } => (
                const { Chemistry::ZincAlkalineManganeseDioxide.code() },
                reserved,
            ),
            Self::LithiumIon { reserved } => (const { Chemistry::LithiumIon.code() }, reserved),
            Self::ZincBromine { reserved } => (const { Chemistry::ZincBromine.code() }, reserved),
            Self::MetalAir { reserved } => (const { Chemistry::MetalAir.code() }, reserved),
            Self::LithiumIronSulfide { reserved } => {
                (const { Chemistry::LithiumIronSulfide.code() }, reserved)
            }
            Self::SodiumBeta { reserved } => (const { Chemistry::SodiumBeta.code() }, reserved),
            Self::Unknown(raw) => return raw,
        };
        code << 4 | (sub & 0x0F)
    }

    /// The chemistry nibble.
    #[must_use]
    pub const fn chemistry(self) -> Chemistry {
        Chemistry::from_code(self.to_u8() >> 4)
    }

    /// Decodes the 1-byte value of 6020h sub 1.
    pub fn decode(data: &[u8]) -> Result<Self, DecodeError> {
        read_u8(data).map(Self::from_u8)
    }

    /// The 1-byte value of 6020h sub 1.
    #[must_use]
    pub const fn encode(self) -> [u8; 1] {
        [self.to_u8()]
    }
}

crate::bytes::raw_word!(BatteryType: u8, BatteryType::from_u8, BatteryType::to_u8);

/// Why an object's sub-index value did not decode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum ObjectError {
    /// The object has no such sub-index.
    #[error("object {index:04X}h has no sub-index {sub}")]
    NoSuchSubIndex {
        /// Object index.
        index: u16,
        /// Sub-index asked for.
        sub: u8,
    },
    /// The bytes have the wrong length for the sub-index's data type.
    #[error(transparent)]
    Decode(#[from] DecodeError),
}

/// One sub-index value of 6020h battery parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BatteryParameterValue {
    /// Sub 0: highest sub-index supported, U8 (4 on a conforming module).
    HighestSubIndex(u8),
    /// Sub 1: battery type, U8.
    BatteryType(BatteryType),
    /// Sub 2: Ah capacity, U16, 1 Ah per bit.
    AhCapacity(u16),
    /// Sub 3: maximum charge current, U16, 1 A per bit.
    MaxChargeCurrent(u16),
    /// Sub 4: number of cells, U16.
    NumberOfCells(u16),
}

impl BatteryParameterValue {
    /// The sub-index this value belongs to.
    #[must_use]
    pub const fn sub_index(self) -> u8 {
        match self {
            Self::HighestSubIndex(_) => 0,
            Self::BatteryType(_) => BatteryParameters::SUB_BATTERY_TYPE,
            Self::AhCapacity(_) => BatteryParameters::SUB_AH_CAPACITY,
            Self::MaxChargeCurrent(_) => BatteryParameters::SUB_MAX_CHARGE_CURRENT,
            Self::NumberOfCells(_) => BatteryParameters::SUB_NUMBER_OF_CELLS,
        }
    }

    /// Decodes the little-endian bytes of sub-index `sub` of 6020h.
    pub fn decode(sub: u8, data: &[u8]) -> Result<Self, ObjectError> {
        Ok(match sub {
            0 => Self::HighestSubIndex(read_u8(data)?),
            BatteryParameters::SUB_BATTERY_TYPE => {
                Self::BatteryType(BatteryType::from_u8(read_u8(data)?))
            }
            BatteryParameters::SUB_AH_CAPACITY => Self::AhCapacity(read_u16(data)?),
            BatteryParameters::SUB_MAX_CHARGE_CURRENT => Self::MaxChargeCurrent(read_u16(data)?),
            BatteryParameters::SUB_NUMBER_OF_CELLS => Self::NumberOfCells(read_u16(data)?),
            _ => {
                return Err(ObjectError::NoSuchSubIndex {
                    index: BATTERY_PARAMETERS,
                    sub,
                })
            }
        })
    }

    /// The little-endian bytes (1 for U8 subs, 2 for U16 subs).
    #[must_use]
    pub fn encode(self) -> InlineData<2> {
        let (word, len) = self.word();
        let bytes = word.to_le_bytes();
        InlineData::new(bytes.get(..usize::from(len)).unwrap_or(&bytes)).unwrap_or_default()
    }

    /// The value as a number and its length in bytes (1 for U8 subs, 2 for
    /// U16 subs): what [`encode`](Self::encode) writes little-endian.
    ///
    /// ```
    /// use canopen_codec::cia418::BatteryParameterValue;
    /// assert_eq!(BatteryParameterValue::AhCapacity(600).word(), (600, 2));
    /// assert_eq!(BatteryParameterValue::HighestSubIndex(4).word(), (4, 1));
    /// ```
    #[must_use]
    pub const fn word(self) -> (u16, u8) {
        match self {
            Self::HighestSubIndex(v) => (v as u16, 1),
            Self::BatteryType(t) => (t.to_u8() as u16, 1),
            Self::AhCapacity(v) | Self::MaxChargeCurrent(v) | Self::NumberOfCells(v) => (v, 2),
        }
    }
}

/// 6020h battery parameters, record `BatteryPar` (CiA 418 sections 7.2.1,
/// 7.3.4). All four entries are mandatory and read-only.
///
/// ```
/// use canopen_codec::cia418::{BatteryParameterValue, BatteryParameters, BatteryType};
/// let mut p = BatteryParameters::default();
/// // An SDO upload of 6020h sub 2 returned `58 02`: 600 Ah.
/// let v = BatteryParameterValue::decode(2, &[0x58, 0x02]).unwrap();
/// p.set(v);
/// assert_eq!(p.ah_capacity, 600);
/// assert_eq!(p.get(2).unwrap().encode().as_slice(), &[0x58, 0x02]);
/// assert_eq!(p.get(0), Some(BatteryParameterValue::HighestSubIndex(4)));
/// assert_eq!(p.get(5), None);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BatteryParameters {
    /// Sub 1: battery type.
    pub battery_type: BatteryType,
    /// Sub 2: nominal capacity, 1 Ah per bit.
    pub ah_capacity: u16,
    /// Sub 3: maximum charge current, 1 A per bit.
    pub max_charge_current: u16,
    /// Sub 4: number of cells.
    pub number_of_cells: u16,
}

impl Default for BatteryParameters {
    /// All zero (battery type 0, an unknown chemistry).
    fn default() -> Self {
        BatteryParameters {
            battery_type: BatteryType::Unknown(0),
            ah_capacity: 0,
            max_charge_current: 0,
            number_of_cells: 0,
        }
    }
}

impl BatteryParameters {
    /// Value of sub 0, highest sub-index supported.
    pub const HIGHEST_SUB_INDEX: u8 = 4;
    /// Sub-index of the battery type.
    pub const SUB_BATTERY_TYPE: u8 = 1;
    /// Sub-index of the Ah capacity.
    pub const SUB_AH_CAPACITY: u8 = 2;
    /// Sub-index of the maximum charge current.
    pub const SUB_MAX_CHARGE_CURRENT: u8 = 3;
    /// Sub-index of the number of cells.
    pub const SUB_NUMBER_OF_CELLS: u8 = 4;

    /// The value of sub-index `sub` (0..=4), `None` for any other.
    #[must_use]
    pub const fn get(&self, sub: u8) -> Option<BatteryParameterValue> {
        Some(match sub {
            0 => BatteryParameterValue::HighestSubIndex(Self::HIGHEST_SUB_INDEX),
            Self::SUB_BATTERY_TYPE => BatteryParameterValue::BatteryType(self.battery_type),
            Self::SUB_AH_CAPACITY => BatteryParameterValue::AhCapacity(self.ah_capacity),
            Self::SUB_MAX_CHARGE_CURRENT => {
                BatteryParameterValue::MaxChargeCurrent(self.max_charge_current)
            }
            Self::SUB_NUMBER_OF_CELLS => BatteryParameterValue::NumberOfCells(self.number_of_cells),
            _ => return None,
        })
    }

    /// Stores a sub-index value. Sub 0 is fixed (4): setting
    /// [`BatteryParameterValue::HighestSubIndex`] changes nothing and returns
    /// `false`; every other value returns `true`.
    pub fn set(&mut self, value: BatteryParameterValue) -> bool {
        match value {
            BatteryParameterValue::HighestSubIndex(_) => return false,
            BatteryParameterValue::BatteryType(t) => self.battery_type = t,
            BatteryParameterValue::AhCapacity(v) => self.ah_capacity = v,
            BatteryParameterValue::MaxChargeCurrent(v) => self.max_charge_current = v,
            BatteryParameterValue::NumberOfCells(v) => self.number_of_cells = v,
        }
        true
    }

    /// Decodes the bytes of sub-index `sub` and stores the value.
    pub fn decode_sub(&mut self, sub: u8, data: &[u8]) -> Result<(), ObjectError> {
        self.set(BatteryParameterValue::decode(sub, data)?);
        Ok(())
    }

    /// The value of sub-index `sub` as a number and its length in bytes
    /// (what [`BatteryParameterValue::word`] gives for [`get`](Self::get)),
    /// `None` for an unknown sub.
    ///
    /// ```
    /// use canopen_codec::cia418::BatteryParameters;
    /// let p = BatteryParameters { ah_capacity: 600, ..Default::default() };
    /// assert_eq!(p.sub_word(2), Some((600, 2)));
    /// assert_eq!(p.sub_word(0), Some((4, 1)));
    /// assert_eq!(p.sub_word(5), None);
    /// ```
    #[must_use]
    pub const fn sub_word(&self, sub: u8) -> Option<(u16, u8)> {
        Some(match sub {
            0 => (Self::HIGHEST_SUB_INDEX as u16, 1),
            Self::SUB_BATTERY_TYPE => (self.battery_type.to_u8() as u16, 1),
            Self::SUB_AH_CAPACITY => (self.ah_capacity, 2),
            Self::SUB_MAX_CHARGE_CURRENT => (self.max_charge_current, 2),
            Self::SUB_NUMBER_OF_CELLS => (self.number_of_cells, 2),
            _ => return None,
        })
    }

    /// The little-endian bytes of sub-index `sub`, `None` for an unknown sub.
    #[must_use]
    pub fn encode_sub(&self, sub: u8) -> Option<InlineData<2>> {
        self.get(sub).map(BatteryParameterValue::encode)
    }
}
