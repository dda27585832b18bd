//! Program download on the charger (Delta-Q IC Series CANopen interface
//! specification rev 2.0, program download: "based on CiA 302-3" with
//! objects 1F50h, 1F51h and 1F57h; its application note is not part of
//! this repository, so the public CiA 302-3 definitions are used, with
//! 1F56h for the software identification: see
//! [`program`](crate::program)). With feature
//! `program-download` the charger's application dictionary is its
//! [`ChargerDictionary`] behind [`ProgramObjects`], and a charger given a
//! [`ProgramStore`](crate::program::ProgramStore)
//! ([`Charger::with_program_store`]) serves the four objects over it;
//! without a store (or without the feature) they do not exist
//! (06020000h).

#[cfg(feature = "program-download")]
use super::{Charger, ChargerConfig};
use crate::deltaq::charger_objects::ChargerDictionary;
#[cfg(feature = "program-download")]
use crate::device::{ProgramObjects, ProgramStoreRef, DEFAULT_QUEUE_CAPACITY};

/// The charger's application dictionary as its device core serves it:
/// [`ChargerDictionary`] behind the program download objects (feature
/// `program-download`); it dereferences to the [`ChargerDictionary`].
#[cfg(feature = "program-download")]
pub type ChargerAppDictionary = ProgramObjects<ChargerDictionary>;

/// The charger's application dictionary as its device core serves it
/// (without feature `program-download`: the [`ChargerDictionary`] itself).
#[cfg(not(feature = "program-download"))]
pub type ChargerAppDictionary = ChargerDictionary;

#[cfg(feature = "program-download")]
impl Charger<DEFAULT_QUEUE_CAPACITY> {
    /// The charger of `config` that takes program downloads into `store`
    /// (not yet booted). Feature `program-download`.
    #[must_use]
    pub fn with_program_store(config: ChargerConfig, store: ProgramStoreRef) -> Self {
        let mut charger = Charger::new(config);
        charger.set_program_store(store);
        charger
    }
}

#[cfg(feature = "program-download")]
impl<const Q: usize> Charger<Q> {
    /// Serves 1F50h, 1F51h, 1F56h and 1F57h over `store` from now on (the
    /// program stopped). Feature `program-download`.
    pub fn set_program_store(&mut self, store: ProgramStoreRef) {
        self.device_mut().objects_mut().attach(store);
    }
}
