//! Helpers the benches share (each bench uses one of them; the other is
//! dead code there).

// Client and server on the library's simulated bus (feature `sim`).
#[cfg(feature = "sim")]
#[allow(dead_code)]
pub mod sdo_pair;
#[allow(dead_code)]
pub mod tpdo3;
