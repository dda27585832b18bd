//! EDS and DCF (CiA 306): our own nodes' EDS written and read back, a
//! DCF served whole, property tests of the writer and reader, real device
//! descriptions from the shared data folder, and an EDS dictionary served over
//! SDO (`common::sdo::SdoPair`).

#[path = "../common/mod.rs"]
mod common;

#[cfg(feature = "sim")]
mod dcf;
#[cfg(feature = "std")]
mod export;
#[cfg(feature = "alloc")]
mod props;
#[cfg(feature = "alloc")]
mod real;
#[cfg(feature = "sim")]
mod sdo;
