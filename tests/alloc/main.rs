//! Everything that counts allocations, under the one counting
//! `#[global_allocator]` of this binary ([`counting`], per thread, so that the
//! harness's other threads do not disturb a measurement): the decode and encode
//! paths never allocate, the EDS reader allocates in proportion to the file,
//! and the real capture's PDOs (decoded and formatted without allocating).

#[path = "../common/mod.rs"]
mod common;
mod counting;

#[cfg(feature = "alloc")]
mod eds_alloc;
mod no_alloc;
mod pdo_capture;
