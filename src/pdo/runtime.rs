//! The PDO side of a device at run time, shared by the battery module and
//! the charger: its four TPDO producers kept in step with the PDO
//! configuration and the object values, and received RPDOs written into the
//! objects.

use super::comm::PdoDirection;
use super::config::{PdoConfig, PdoDictionary};
use super::od_io::{read_mapped, write_mapped, RpdoError};
use super::producer::TpdoProducer;
use crate::cob_id::PdoNumber;
use crate::frame::CanFrame;
use crate::od::ObjectDictionary;
use crate::time::Timestamp;

const PDO_NUMBERS: [PdoNumber; 4] = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3];

/// TPDO 0..3 of a device, one [`TpdoProducer`] each.
#[derive(Debug, Clone)]
pub struct TpdoSet {
    producers: [TpdoProducer; 4],
}

impl Default for TpdoSet {
    fn default() -> Self {
        Self::new()
    }
}

impl TpdoSet {
    /// Four unconfigured producers.
    #[must_use]
    pub const fn new() -> Self {
        TpdoSet {
            producers: [const { TpdoProducer::new() }; 4],
        }
    }

    /// Gives each producer its TPDO's current communication parameters (a
    /// TPDO the configuration lacks is unconfigured).
    pub fn sync(&mut self, now: Timestamp, config: &PdoConfig) {
        for (pdo, producer) in PDO_NUMBERS.into_iter().zip(self.producers.iter_mut()) {
            match config.get(PdoDirection::Transmit, pdo).map(|s| s.comm) {
                Some(comm) if producer.comm() != Some(&comm) => producer.configure(now, comm),
                None if producer.comm().is_some() => producer.unconfigure(),
                _ => {}
            }
        }
    }

    /// Reads every TPDO's payload from the mapped objects; a changed payload
    /// is an event for its producer.
    pub fn refresh<D: ObjectDictionary>(&mut self, now: Timestamp, pdos: &mut PdoDictionary<D>) {
        for (pdo, producer) in PDO_NUMBERS.into_iter().zip(self.producers.iter_mut()) {
            let Some(slot) = pdos.config.get(PdoDirection::Transmit, pdo) else {
                continue;
            };
            let mapping = slot.mapping();
            if let Ok(payload) = read_mapped(&mapping, &mut pdos.inner) {
                producer.set_payload(now, payload);
            }
        }
    }

    /// Whether the TPDOs may run (operational, and whatever else the device requires).
    pub fn set_operational(&mut self, now: Timestamp, run: bool) {
        for p in &mut self.producers {
            p.set_operational(now, run);
        }
    }

    /// A SYNC was received.
    pub fn handle_sync(&mut self, now: Timestamp) {
        for p in &mut self.producers {
            p.handle_sync(now);
        }
    }

    /// Time has passed.
    pub fn handle_timeout(&mut self, now: Timestamp) {
        for p in &mut self.producers {
            p.handle_timeout(now);
        }
    }

    /// The next TPDO to send.
    #[must_use]
    pub fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.producers
            .iter_mut()
            .find_map(TpdoProducer::poll_transmit)
    }

    /// The earliest TPDO deadline.
    #[must_use]
    pub fn poll_timeout(&self) -> Option<Timestamp> {
        self.producers
            .iter()
            .filter_map(TpdoProducer::poll_timeout)
            .min()
    }
}

/// If `frame` is one of the device's valid RPDOs, writes its fields into the
/// mapped objects ([`write_mapped`]) and says which RPDO it was and how it
/// went (`Ok(true)`: longer than the mapping). The first matching RPDO wins
/// (two RPDOs on one COB-ID is a misconfiguration).
pub fn receive_rpdo<D: ObjectDictionary>(
    pdos: &mut PdoDictionary<D>,
    frame: &CanFrame,
) -> Option<(PdoNumber, Result<bool, RpdoError>)> {
    let pdo = PDO_NUMBERS.into_iter().find(|n| {
        pdos.config
            .get(PdoDirection::Receive, *n)
            .is_some_and(|s| s.is_valid() && s.comm.cob_id.can_id() == Some(frame.id()))
    })?;
    let mapping = pdos.config.get(PdoDirection::Receive, pdo)?.mapping();
    Some((pdo, write_mapped(&mapping, frame.data(), &mut pdos.inner)))
}
