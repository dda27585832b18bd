//! The names of a network manager's objects: CiA 302-2 "Network
//! management" (section 4.2, 1F80h-1F89h) and CiA 302-3 "Configuration and
//! program download" (section 4, 1F22h, 1F52h-1F56h), each entry named and
//! sized by its row of the communication table ([`comm::COMM_OBJECTS`]);
//! the decoder (`comm_objects`) explains the values.

use std::prelude::rust_2021::*;

use crate::od::index::{
    BOOT_TIME, CONCISE_DCF, EXPECTED_APPLICATION_SW_DATE, EXPECTED_APPLICATION_SW_TIME,
    EXPECTED_SOFTWARE_IDENTIFICATION, NMT_SLAVE_ASSIGNMENT, NMT_STARTUP, REQUEST_NMT,
    REQUEST_NODE_GUARDING, SERIAL_NUMBER_IDENTIFICATION, VERIFY_APPLICATION_SOFTWARE,
};
use crate::od::{comm, Address};
use crate::program::PROGRAM_SOFTWARE_IDENTIFICATION;

/// How a value of one of the manager's entries reads in words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Meaning {
    /// The highest sub-index of an ARRAY or RECORD.
    Count,
    /// Days since 1 January 1984 (1F52h sub 1, 1F53h).
    Date,
    /// Milliseconds after midnight (1F52h sub 2, 1F54h).
    Time,
    /// The 1F80h bits.
    NmtStartup,
    /// A plain number (1F82h, 1F83h).
    Decimal,
    /// A time in ms (1F89h).
    Ms,
    /// A 32-bit word in hex (identities, 1F81h).
    Hex,
}

/// Whether `index` is one of the manager's objects this module names.
pub(super) const fn is_manager_object(index: u16) -> bool {
    matches!(
        index,
        CONCISE_DCF | VERIFY_APPLICATION_SOFTWARE..=PROGRAM_SOFTWARE_IDENTIFICATION | NMT_STARTUP..=BOOT_TIME
    )
}

/// The name of `address`, one of the manager's objects (its row's name,
/// "of node N" added for an entry per node and "N" for one per program or
/// concise DCF), its size in bytes (0: variable) and how its value reads.
pub(super) fn entry(address: Address) -> (String, u8, Meaning) {
    let Address { index, sub } = address;
    let Some(row) = comm::find(address) else {
        return (format!("{address:#}"), 0, Meaning::Hex);
    };
    let heads = sub == 0 && row.compound.is_some();
    let name = match index {
        _ if heads => format!("{}: highest sub-index", row.short),
        EXPECTED_APPLICATION_SW_DATE..=EXPECTED_SOFTWARE_IDENTIFICATION
        | NMT_SLAVE_ASSIGNMENT..=SERIAL_NUMBER_IDENTIFICATION => {
            format!("{} of node {sub}", row.short)
        }
        CONCISE_DCF | PROGRAM_SOFTWARE_IDENTIFICATION => format!("{} {sub}", row.short),
        _ => row.short.to_string(),
    };
    let meaning = match (index, sub) {
        _ if heads => Meaning::Count,
        (VERIFY_APPLICATION_SOFTWARE, 1) | (EXPECTED_APPLICATION_SW_DATE, _) => Meaning::Date,
        (VERIFY_APPLICATION_SOFTWARE, 2) | (EXPECTED_APPLICATION_SW_TIME, _) => Meaning::Time,
        (NMT_STARTUP, _) => Meaning::NmtStartup,
        (REQUEST_NMT | REQUEST_NODE_GUARDING, _) => Meaning::Decimal,
        (BOOT_TIME, _) => Meaning::Ms,
        _ => Meaning::Hex,
    };
    (name, row.size(), meaning)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::od::comm::COMM_OBJECTS;

    #[test]
    fn every_entry_is_named_and_sized_by_its_row() {
        let rows: Vec<_> = COMM_OBJECTS
            .iter()
            .filter(|r| is_manager_object(r.address.index))
            .collect();
        // 1F22h, 1F52h-1F56h, 1F80h-1F89h.
        let objects = rows.iter().filter(|r| r.address.sub == 0).count();
        assert_eq!(objects, 16);
        for row in rows {
            for sub in [row.address.sub, row.last_sub] {
                let address = Address::new(row.address.index, sub);
                let (name, size, _) = entry(address);
                assert!(name.starts_with(row.short), "{address}: {name}");
                assert_eq!(size, row.size(), "{address}");
            }
        }
        let product = entry(Address::new(0x1F86, 5));
        assert_eq!(product, ("product code of node 5".into(), 4, Meaning::Hex));
        let date = entry(Address::new(0x1F53, 127));
        let want = "expected application software date of node 127";
        assert_eq!(date, (want.into(), 4, Meaning::Date));
        let dcf = entry(Address::new(0x1F22, 3));
        assert_eq!(dcf, ("concise DCF 3".into(), 0, Meaning::Hex));
        let count = entry(Address::new(0x1F81, 0));
        let want = "NMT slave assignment: highest sub-index";
        assert_eq!(count, (want.into(), 1, Meaning::Count));
    }
}
