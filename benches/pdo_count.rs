//! The `pdo` bench's Delta-Q TPDO 3 typed unpack, run a given number of
//! times without a timer: a harness for callgrind.
//!
//! ```text
//! cargo bench --bench pdo_count --no-run
//! valgrind --tool=callgrind --toggle-collect='pdo_count::decode_tpdo3' \
//!     target/release/deps/pdo_count-HASH 100000
//! ```
//!
//! Instructions per PDO = collected / runs. Without arguments (as `cargo
//! bench` runs it) it decodes once.

use std::hint::black_box;

use canopen_codec::deltaq::{BatteryVoltageLegacy, ChargingCurrent, ExtendedChargeStatus};
use canopen_codec::pdo::{MappingEntry, PdoMapping};

/// The charger TPDO 3 as three typed values (`None`: "no value"), as the
/// `pdo` bench decodes it.
#[inline(never)]
fn decode_tpdo3(
    m: &PdoMapping,
    payload: &[u8],
) -> Option<(
    Option<ChargingCurrent>,
    Option<BatteryVoltageLegacy>,
    ExtendedChargeStatus,
)> {
    let u = m.unpack(payload).ok()?;
    let raw16 = |i| u.raw(i).and_then(|r| u16::try_from(r).ok());
    Some((
        ChargingCurrent::from_raw(raw16(0)?),
        BatteryVoltageLegacy::from_raw(raw16(1)?),
        ExtendedChargeStatus::from_u16(raw16(2)?),
    ))
}

fn main() {
    let n: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(1);
    let m = PdoMapping::new(&[
        MappingEntry::new(0x2002, 0, 16),
        MappingEntry::new(0x2100, 0, 16),
        MappingEntry::new(0x2006, 0, 16),
    ])
    .expect("TPDO 3 mapping");
    let frame = [0x74u8, 0x13, 0x45, 0x4E, 0x70, 0x00];
    let mut some = 0u64;
    for _ in 0..n {
        some += u64::from(black_box(decode_tpdo3(black_box(&m), black_box(&frame))).is_some());
    }
    println!("{n} decodes, {some} with values");
}
