//! The PDO side of a device at run time: its four TPDO producers kept in
//! step with the PDO configuration and the object values ([`TpdoSet`]),
//! and the reception of its RPDOs ([`RpdoReceiver`]). Both implement
//! [`Machine`]; the device that owns the object dictionary reads the mapped
//! objects for the TPDOs ([`TpdoSet::refresh`]) and writes what the
//! receiver reports into them ([`RpdoReceiver::apply`]).

use core::convert::Infallible;

use super::comm::PdoDirection;
use super::config::{PdoConfig, PdoDictionary};
use super::mapping::PdoMapping;
use super::od_io::{read_mapped, write_mapped, RpdoError};
use super::producer::TpdoProducer;
use crate::bytes::Payload;
use crate::cob_id::PdoNumber;
use crate::frame::{CanFrame, CanId};
use crate::machine::Machine;
use crate::od::ObjectDictionary;
use crate::queue::EventQueue;
use crate::time::Timestamp;

const PDO_NUMBERS: [PdoNumber; 4] = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3];

/// TPDO 0..3 of a device, one [`TpdoProducer`] each. SYNC frames reach
/// every producer through [`Machine::handle_frame`].
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
    /// TPDO the configuration lacks is unconfigured). Call it after every
    /// change of 1800h-1803h.
    pub fn reconfigure(&mut self, now: Timestamp, config: &PdoConfig) {
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

    /// A SYNC recognised by the caller (the device core's SYNC consumer on
    /// 1005h's identifier, or its own SYNC producer): the synchronous TPDOs
    /// send here, whatever identifier their producers listen to.
    pub fn handle_sync(&mut self, now: Timestamp) {
        for p in &mut self.producers {
            p.handle_sync(now);
        }
    }

    /// Stops and forgets every producer (a reset).
    pub fn reset(&mut self) {
        *self = Self::new();
    }
}

impl Machine for TpdoSet {
    type Event = Infallible;

    /// SYNC frames drive the synchronous TPDOs; others are ignored.
    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        for p in &mut self.producers {
            p.handle_frame(now, frame);
        }
    }

    fn handle_timeout(&mut self, now: Timestamp) {
        for p in &mut self.producers {
            p.handle_timeout(now);
        }
    }

    /// The next TPDO to send (TPDO 0 first).
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.producers
            .iter_mut()
            .find_map(TpdoProducer::poll_transmit)
    }

    /// The earliest TPDO deadline.
    fn poll_timeout(&self) -> Option<Timestamp> {
        self.producers
            .iter()
            .filter_map(TpdoProducer::poll_timeout)
            .min()
    }

    fn poll_event(&mut self) -> Option<Infallible> {
        None
    }

    fn events_dropped(&self) -> u64 {
        0
    }
}

/// A frame received on one of the device's valid RPDOs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RpdoFrame {
    /// The RPDO number (from 0).
    pub pdo: PdoNumber,
    /// Its data bytes.
    pub data: Payload,
}

/// Receives RPDO 0..3 of a device: recognises frames on the valid RPDO
/// COB-IDs while enabled (NMT operational, CiA 301) and reports each as an
/// [`RpdoFrame`] event; the owner of the object dictionary writes it with
/// [`RpdoReceiver::apply`]. Remote frames are ignored; when two RPDOs share
/// a COB-ID (a misconfiguration) the lower number wins.
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::pdo::{PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoMapping, PdoSlot, RpdoReceiver};
/// use canopen_codec::{CanFrame, PdoNumber, Timestamp};
/// let mut config = PdoConfig::new();
/// let comm = PdoCommParams::event_driven(PdoCobId::standard(0x20A), 0);
/// config.insert(PdoDirection::Receive, PdoNumber::P0, PdoSlot::new(comm, &PdoMapping::EMPTY));
/// let mut rx = RpdoReceiver::new();
/// rx.reconfigure(&config);
/// rx.set_enabled(true);
/// rx.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x20A, &[1, 2]).unwrap());
/// let got = rx.poll_event().unwrap();
/// assert_eq!((got.pdo, got.data.as_slice()), (PdoNumber::P0, &[1u8, 2][..]));
/// ```
#[derive(Debug, Clone)]
pub struct RpdoReceiver {
    ids: [Option<CanId>; 4],
    enabled: bool,
    events: EventQueue<RpdoFrame, 4>,
}

impl Default for RpdoReceiver {
    fn default() -> Self {
        Self::new()
    }
}

impl RpdoReceiver {
    /// No RPDO configured, disabled.
    #[must_use]
    pub const fn new() -> Self {
        RpdoReceiver {
            ids: [None; 4],
            enabled: false,
            events: EventQueue::new(RpdoFrame {
                pdo: PdoNumber::P0,
                data: Payload::EMPTY,
            }),
        }
    }

    /// Takes the COB-IDs of the valid RPDOs from `config`. Call it after
    /// every change of 1400h-1403h.
    pub fn reconfigure(&mut self, config: &PdoConfig) {
        for (pdo, id) in PDO_NUMBERS.into_iter().zip(self.ids.iter_mut()) {
            *id = config
                .get(PdoDirection::Receive, pdo)
                .filter(|s| s.is_valid())
                .and_then(|s| s.comm.cob_id.can_id());
        }
    }

    /// Whether RPDOs are processed (NMT operational).
    pub fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
    }

    /// Writes a received RPDO's fields into the mapped objects
    /// ([`write_mapped`]) with the mapping `config` has for it now; `Ok(true)`
    /// when the frame is longer than the mapping. `None` when the RPDO is
    /// no longer configured.
    pub fn apply<D: ObjectDictionary>(
        rpdo: &RpdoFrame,
        pdos: &mut PdoDictionary<D>,
    ) -> Option<Result<bool, RpdoError>> {
        let mapping: PdoMapping = pdos.config.get(PdoDirection::Receive, rpdo.pdo)?.mapping();
        Some(write_mapped(
            &mapping,
            rpdo.data.as_slice(),
            &mut pdos.inner,
        ))
    }
}

impl Machine for RpdoReceiver {
    type Event = RpdoFrame;

    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        if !self.enabled || frame.is_remote() {
            return;
        }
        let id = Some(frame.id());
        let Some(pdo) = PDO_NUMBERS
            .into_iter()
            .zip(self.ids)
            .find_map(|(n, cob)| (cob == id).then_some(n))
        else {
            return;
        };
        if let Some(data) = Payload::new(frame.data()) {
            self.events.push(RpdoFrame { pdo, data });
        }
    }

    /// The receiver has no timers.
    fn handle_timeout(&mut self, _now: Timestamp) {}

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        None
    }

    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    fn poll_event(&mut self) -> Option<RpdoFrame> {
        self.events.pop()
    }

    fn events_dropped(&self) -> u64 {
        self.events.dropped()
    }
}
