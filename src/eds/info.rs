//! The information sections of a description: `[FileInfo]`,
//! `[DeviceInfo]` (CiA 306, sections 4.2 and 4.3) and a DCF's
//! `[DeviceComissioning]`.
//!
//! Each section is one table: a row per key the model reads (the field,
//! the CiA 306 key name, the type), from which its struct and its reading
//! follow. Every key is also kept as written in the section's `keys`, which
//! is what the writer writes back, so a key added to a table is read,
//! written and round-tripped by that one row.

use alloc::string::{String, ToString};
use alloc::vec::Vec;

use super::value::parse_int;
use super::Keys;

/// How a key's text becomes a field: as written for a name, a CiA 306
/// number (decimal or `0x` hex) that fits the field for a number.
trait KeyValue: Sized {
    fn read(text: &str) -> Option<Self>;
}

impl KeyValue for String {
    fn read(text: &str) -> Option<Self> {
        Some(text.to_string())
    }
}

macro_rules! key_number {
    ($($t:ty),*) => {$(
        impl KeyValue for $t {
            fn read(text: &str) -> Option<Self> {
                parse_int(text).and_then(|v| <$t>::try_from(v).ok())
            }
        }
    )*};
}
key_number!(u8, u16, u32);

/// One information section: `struct { field: Type = "Key", ... }`, then
/// the fields computed from several keys (`field: Type = function`). Each
/// key field is `None` when the key is absent or does not fit.
macro_rules! info_section {
    (
        $(#[$doc:meta])*
        $name:ident {
            $( $(#[$fdoc:meta])* $field:ident: $ty:ty = $key:literal, )*
        }
        $( computed {
            $( $(#[$cdoc:meta])* $cfield:ident: $cty:ty = $compute:path, )*
        } )?
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Default, PartialEq, Eq)]
        pub struct $name {
            $(
                #[doc = concat!("`", $key, "`.")]
                $(#[$fdoc])*
                pub $field: Option<$ty>,
            )*
            $($( $(#[$cdoc])* pub $cfield: $cty, )*)?
            /// Every key of the section, as written.
            pub keys: Keys,
        }

        impl $name {
            /// The section read from its keys (any case; a later
            /// duplicate wins).
            pub(super) fn from_keys(keys: Keys) -> Self {
                Self {
                    $( $field: keys.get($key).and_then(<$ty as KeyValue>::read), )*
                    $($( $cfield: $compute(&keys), )*)?
                    keys,
                }
            }
        }
    };
}

info_section! {
    /// `[FileInfo]` (CiA 306, section 4.2 "File information").
    FileInfo {
        file_name: String = "FileName",
        file_version: String = "FileVersion",
        eds_version: String = "EDSVersion",
        description: String = "Description",
        created_by: String = "CreatedBy",
    }
}

info_section! {
    /// `[DeviceInfo]` (CiA 306, section 4.3 "General device information").
    DeviceInfo {
        vendor_name: String = "VendorName",
        vendor_number: u32 = "VendorNumber",
        product_name: String = "ProductName",
        product_number: u32 = "ProductNumber",
        revision_number: u32 = "RevisionNumber",
        nr_of_rx_pdo: u16 = "NrOfRXPDO",
        nr_of_tx_pdo: u16 = "NrOfTXPDO",
    }
    computed {
        /// The bit rates in kbit/s whose `BaudRate_<n>` key is 1, ascending.
        baud_rates: Vec<u16> = baud_rates,
        /// `LSS_Supported`.
        lss_supported: bool = lss_supported,
    }
}

info_section! {
    /// `[DeviceComissioning]` of a DCF (CiA 306's own spelling, which the
    /// writer keeps), also read as `[DeviceCommissioning]`.
    Commissioning {
        /// Decimal or `0x` hex.
        node_id: u8 = "NodeID",
        node_name: String = "NodeName",
        /// In kbit/s.
        baudrate: u16 = "Baudrate",
        net_number: u32 = "NetNumber",
    }
}

/// The rates `n` of the `BaudRate_<n>` keys set to a non-zero number.
fn baud_rates(keys: &Keys) -> Vec<u16> {
    let mut rates: Vec<u16> = keys
        .0
        .iter()
        .filter_map(|(k, v)| {
            let rate = k
                .get(..9)?
                .eq_ignore_ascii_case("BaudRate_")
                .then(|| k.get(9..))??;
            (parse_int(v)? != 0).then(|| rate.parse().ok())?
        })
        .collect();
    rates.sort_unstable();
    rates.dedup();
    rates
}

/// `LSS_Supported` set to a non-zero number.
fn lss_supported(keys: &Keys) -> bool {
    keys.get("LSS_Supported")
        .and_then(parse_int)
        .is_some_and(|v| v != 0)
}
