//! Property tests of the codecs through the public API: `Message` and
//! the codecs beneath it, CiA 418, PDO packing, LSS, the heartbeat consumer and
//! node guarding. Each records its failures in
//! `tests/proptest-regressions/<name>.txt`.

#[path = "../common/mod.rs"]
mod common;

mod cia418;
mod guarding;
mod heartbeat;
mod lss;
mod message;
mod pdo;
