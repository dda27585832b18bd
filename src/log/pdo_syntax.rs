//! The `--pdo COBID=INDEX:SUB:BITS,...` syntax and the real capture's
//! mapping in it, shared by `canopen-decode` and `canopen-replay`.

use crate::pdo::{MappingEntry, PdoMapping, MAX_ENTRIES};
use std::prelude::rust_2021::*;

/// The mapping of the real capture, from tests/data/CAPTURES.md, in
/// `--pdo` syntax. Unnamed padding uses CiA 301 dummy entries (0005h
/// UNSIGNED8, 0006h UNSIGNED16). 0x28A's layout is not published: it stays
/// unmapped (raw).
pub const CAPTURE_PDOS: [&str; 4] = [
    "18A=2002:0:16,2101:0:16,2006:0:16,6:0:16",
    "38A=2060:0:32,2200:0:16,6080:0:8,5:0:8",
    "20A=2FFA:1:8,6081:0:8,4201:0:8,2276:0:16,6070:0:16,6000:0:8",
    "30A=2FFA:1:8,2FFA:1:8,2002:0:16,2101:0:16,6010:0:16",
];

fn hex<T: TryFrom<u32>>(s: &str, what: &str, max: u32) -> Result<T, String> {
    let digits = s
        .strip_prefix("0x")
        .or_else(|| s.strip_prefix("0X"))
        .unwrap_or(s);
    u32::from_str_radix(digits, 16)
        .ok()
        .filter(|v| *v <= max && !digits.starts_with('+'))
        .and_then(|v| T::try_from(v).ok())
        .ok_or(format!("{what} '{s}' is not hex 0..={max:X}"))
}

/// Parses `COBID=INDEX:SUB:BITS,...`.
pub fn parse_pdo(arg: &str) -> Result<(u16, PdoMapping), String> {
    let fail = |why: String| format!("--pdo '{arg}': {why}");
    let (cob, list) = arg
        .split_once('=')
        .ok_or_else(|| fail("expected COBID=INDEX:SUB:BITS,...".into()))?;
    let cob_id: u16 = hex(cob.trim(), "COB-ID", 0x7FF).map_err(fail)?;
    let mut entries = Vec::new();
    for item in list.split(',') {
        let parts: Vec<&str> = item.trim().split(':').collect();
        let [index, sub, bits] = parts[..] else {
            return Err(fail(format!(
                "entry '{item}' is not INDEX:SUB:BITS (hex:hex:decimal)"
            )));
        };
        let index: u16 = hex(index, "index", 0xFFFF).map_err(fail)?;
        let sub: u8 = hex(sub, "sub-index", 0xFF).map_err(fail)?;
        let bits: u8 = bits
            .parse()
            .ok()
            .filter(|b| (1..=64).contains(b))
            .ok_or_else(|| fail(format!("bits '{bits}' is not a decimal 1..=64")))?;
        entries.push(MappingEntry::new(index, sub, bits));
    }
    if entries.len() > MAX_ENTRIES {
        return Err(fail(format!(
            "{} entries, at most {MAX_ENTRIES}",
            entries.len()
        )));
    }
    let mapping = PdoMapping::new(&entries).map_err(|e| fail(e.to_string()))?;
    Ok((cob_id, mapping))
}
