//! The PDO side of a device at run time: its TPDO producers kept in
//! step with the PDO configuration and the object values ([`TpdoSet`]),
//! and the reception of its RPDOs ([`RpdoReceiver`]). Both implement
//! [`Machine`]; the device that owns the object dictionary reads the mapped
//! objects for the TPDOs ([`TpdoSet::refresh`]) and writes what the
//! receiver reports into them ([`RpdoReceiver::apply`]).

use core::convert::Infallible;

use super::comm::PdoDirection;
use super::config::{PdoConfig, PdoDictionary};
#[cfg(feature = "alloc")]
use super::od_io::holds_entries;
use super::od_io::{read_entries, write_entries, RpdoError};
use super::producer::TpdoProducer;
use crate::bytes::Payload;
use crate::clock::{earliest, Timestamp};
use crate::cob_id::PdoNumber;
use crate::frame::{data_frame_identity, CanFrame};
use crate::machine::Machine;
use crate::od::ObjectDictionary;
use crate::wire::Codec;

/// TPDO 0..T of a device (default 4), one [`TpdoProducer`] each. SYNC
/// frames reach every producer through [`Machine::handle_frame`].
#[derive(Debug, Clone)]
pub struct TpdoSet<const T: usize = 4> {
    producers: [TpdoProducer; T],
}

impl Default for TpdoSet {
    fn default() -> Self {
        Self::new()
    }
}

impl TpdoSet {
    /// Four unconfigured producers (other counts: [`empty`](Self::empty)).
    #[must_use]
    pub const fn new() -> Self {
        Self::empty()
    }
}

impl<const T: usize> TpdoSet<T> {
    /// `T` unconfigured producers.
    #[must_use]
    pub const fn empty() -> Self {
        TpdoSet {
            producers: [const { TpdoProducer::new() }; T],
        }
    }

    /// Gives each producer its TPDO's current communication parameters (a
    /// TPDO the configuration lacks is unconfigured). Call it after every
    /// change of 1800h-1803h.
    pub fn reconfigure<const R: usize>(&mut self, now: Timestamp, config: &PdoConfig<T, R>) {
        for (slot, producer) in config.tpdos().iter().zip(self.producers.iter_mut()) {
            // Both are no-ops for a producer configured so already.
            match slot {
                Some(s) => producer.configure(now, s.comm),
                None => producer.unconfigure(),
            }
        }
    }

    /// Reads every valid TPDO's payload from the mapped objects; a changed
    /// payload is an event for its producer. A TPDO whose COB-ID is not
    /// valid sends nothing and is not read: the refresh before the
    /// [`reconfigure`](Self::reconfigure) that follows its becoming valid
    /// reads it (the device core refreshes first whenever the PDO
    /// configuration changes). Runs after every input of a device: a
    /// mapping is trusted as the configuration keeps it (valid), not
    /// checked again.
    pub fn refresh<D: ObjectDictionary, const R: usize>(
        &mut self,
        now: Timestamp,
        pdos: &mut PdoDictionary<D, T, R>,
    ) {
        for (slot, producer) in pdos.config.tpdos().iter().zip(self.producers.iter_mut()) {
            let Some(slot) = slot.as_ref().filter(|s| s.is_valid()) else {
                continue;
            };
            if let Ok((word, len)) = read_entries(slot.mapped(), &mut pdos.inner) {
                producer.set_payload_word(now, word, len);
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
        for p in &mut self.producers {
            *p = TpdoProducer::new();
        }
    }
}

impl<const T: usize> Machine for TpdoSet<T> {
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
        earliest(self.producers.iter().map(TpdoProducer::poll_timeout))
    }

    crate::machine::queued_outputs!(events: none);

    fn frames_dropped(&self) -> u64 {
        self.producers
            .iter()
            .fold(0, |n, p| n.saturating_add(p.frames_dropped()))
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

/// Receives RPDO 0..R of a device (default 4): recognises frames on the valid RPDO
/// COB-IDs while enabled (NMT operational, CiA 301) and reports each as an
/// [`RpdoFrame`] event; the owner of the object dictionary writes it with
/// [`RpdoReceiver::apply`]. Remote frames are ignored; when two RPDOs share
/// a COB-ID (a misconfiguration) the lower number wins.
///
/// A frame is at most one RPDO, so the receiver holds one event: drain it
/// ([`Machine::poll_event`]) after every `handle_frame`, as the device core
/// does. An undrained event is replaced by the next one and counted in
/// [`Machine::events_dropped`].
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
/// assert_eq!(rx.poll_event(), None);
/// ```
#[derive(Debug, Clone)]
pub struct RpdoReceiver<const R: usize = 4> {
    /// Each RPDO's COB-ID as a data frame's identifier word, `u32::MAX`
    /// (which no frame has) when not valid.
    ids: [u32; R],
    /// Events replaced undrained (saturating; a device never lets one be).
    dropped: u32,
    event: Option<RpdoFrame>,
    enabled: bool,
}

/// The identifier word of no frame.
const NO_ID: u32 = u32::MAX;

impl Default for RpdoReceiver {
    fn default() -> Self {
        Self::new()
    }
}

impl RpdoReceiver {
    /// Four RPDOs, none configured, disabled (other counts:
    /// [`empty`](Self::empty)).
    #[must_use]
    pub const fn new() -> Self {
        Self::empty()
    }
}

impl<const R: usize> RpdoReceiver<R> {
    /// `R` RPDOs, none configured, disabled.
    #[must_use]
    pub const fn empty() -> Self {
        RpdoReceiver {
            ids: [NO_ID; R],
            dropped: 0,
            event: None,
            enabled: false,
        }
    }

    /// Takes the COB-IDs of the valid RPDOs from `config`. Call it after
    /// every change of 1400h-1403h.
    pub fn reconfigure<const T: usize>(&mut self, config: &PdoConfig<T, R>) {
        for (slot, id) in config.rpdos().iter().zip(self.ids.iter_mut()) {
            *id = slot
                .as_ref()
                .filter(|s| s.is_valid())
                .and_then(|s| s.comm.cob_id.can_id())
                .map_or(NO_ID, data_frame_identity);
        }
    }

    /// Whether RPDOs are processed (NMT operational).
    pub fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
    }

    /// Writes a received RPDO's fields into the mapped objects
    /// ([`write_mapped`](super::write_mapped)) with the mapping `config`
    /// has for it now; `Ok(true)` when the frame is longer than the
    /// mapping. `None` when the RPDO is no longer configured.
    pub fn apply<D: ObjectDictionary, const T: usize>(
        rpdo: &RpdoFrame,
        pdos: &mut PdoDictionary<D, T, R>,
    ) -> Option<Result<bool, RpdoError>> {
        Self::apply_data(rpdo.pdo, rpdo.data.as_slice(), pdos)
    }

    /// [`apply`](Self::apply) of RPDO `pdo`'s `data` (the device core's
    /// path: straight from the frame, no [`RpdoFrame`] made).
    #[inline]
    pub(crate) fn apply_data<D: ObjectDictionary, const T: usize>(
        pdo: PdoNumber,
        data: &[u8],
        pdos: &mut PdoDictionary<D, T, R>,
    ) -> Option<Result<bool, RpdoError>> {
        let slot = pdos.config.get(PdoDirection::Receive, pdo)?;
        Some(write_entries(slot.mapped(), data, &mut pdos.inner))
    }

    /// Whether RPDO `pdo`'s mapped objects already hold the fields of
    /// `data` (writing it would change no value; `false` for a PDO the
    /// configuration lacks, a short `data` or an unreadable object).
    #[cfg(feature = "alloc")]
    #[inline]
    pub(crate) fn holds_data<D: ObjectDictionary, const T: usize>(
        pdo: PdoNumber,
        data: &[u8],
        pdos: &mut PdoDictionary<D, T, R>,
    ) -> bool {
        pdos.config
            .get(PdoDirection::Receive, pdo)
            .is_some_and(|slot| holds_entries(slot.mapped(), data, &mut pdos.inner))
    }

    /// The RPDO `frame` is on while enabled, if any: what `handle_frame`
    /// and `poll_event` report, without the event slot (the device core
    /// applies it at once).
    #[inline]
    pub(crate) fn rpdo_of(&self, frame: &CanFrame) -> Option<PdoNumber> {
        if !self.enabled {
            return None;
        }
        // A remote frame's word has the remote flag: it matches no RPDO.
        let word = frame.identity();
        self.ids
            .iter()
            .position(|&id| id == word)
            .and_then(|n| PdoNumber::new(n as u8))
    }
}

impl<const R: usize> Machine for RpdoReceiver<R> {
    type Event = RpdoFrame;

    fn handle_frame(&mut self, _now: Timestamp, frame: &CanFrame) {
        let Some(pdo) = self.rpdo_of(frame) else {
            return;
        };
        if self.event.is_some() {
            self.dropped = self.dropped.saturating_add(1);
        }
        self.event = Some(RpdoFrame {
            pdo,
            data: Payload::parse_frame(frame).unwrap_or_default(),
        });
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
        self.event.take()
    }

    fn events_dropped(&self) -> u64 {
        u64::from(self.dropped)
    }

    /// Always 0: the receiver sends nothing.
    fn frames_dropped(&self) -> u64 {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::CanId;
    use crate::pdo::{PdoCobId, PdoCommParams, PdoMapping, PdoSlot};

    const PDO_NUMBERS: [PdoNumber; 4] =
        [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3];

    fn receiver(cob_ids: [u32; 4]) -> RpdoReceiver {
        let mut config = PdoConfig::new();
        for (n, raw) in PDO_NUMBERS.into_iter().zip(cob_ids) {
            let comm = PdoCommParams::event_driven(PdoCobId::from_u32(raw), 0);
            config.insert(
                PdoDirection::Receive,
                n,
                PdoSlot::new(comm, &PdoMapping::EMPTY),
            );
        }
        let mut rx = RpdoReceiver::new();
        rx.reconfigure(&config);
        rx.set_enabled(true);
        rx
    }

    /// The device drains the receiver after every frame; one event slot is
    /// enough because no frame is more than one RPDO: every identifier,
    /// data or remote, 11 or 29 bits, with two RPDOs sharing a COB-ID,
    /// one not valid and one extended, gives at most one event, and
    /// nothing is ever dropped.
    #[test]
    fn a_frame_is_at_most_one_rpdo() {
        let mut rx = receiver([0x201, 0x201, 0x8000_0301, 0x2000_0401]);
        let mut seen = 0;
        let ids = (0..=0x7FFu32)
            .map(|id| CanId::Standard(id as u16))
            .chain([0x201, 0x301, 0x401, 0x1FFF_FFFF].map(CanId::Extended));
        for id in ids {
            for frame in [
                CanFrame::new(id, &[id.raw() as u8]),
                CanFrame::remote(id, 1),
            ] {
                rx.handle_frame(Timestamp::ZERO, &frame.unwrap());
                if let Some(e) = rx.poll_event() {
                    seen += 1;
                    let want = match id {
                        CanId::Standard(0x201) => PdoNumber::P0,
                        CanId::Extended(0x401) => PdoNumber::P3,
                        other => panic!("event for {other}"),
                    };
                    assert_eq!((e.pdo, e.data.as_slice()), (want, &[id.raw() as u8][..]));
                }
                assert_eq!(rx.poll_event(), None, "{id}: a second event");
            }
        }
        assert_eq!((seen, rx.events_dropped()), (2, 0));
    }

    /// Undrained, the newest frame is kept and the older one counted.
    #[test]
    fn an_undrained_event_is_replaced_and_counted() {
        let mut rx = receiver([0x201, 0x202, 0x8000_0000, 0x8000_0000]);
        rx.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x201, &[1]).unwrap());
        rx.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x202, &[2]).unwrap());
        let e = rx.poll_event().unwrap();
        assert_eq!((e.pdo, e.data.as_slice()), (PdoNumber::P1, &[2u8][..]));
        assert_eq!((rx.poll_event(), rx.events_dropped()), (None, 1));
        rx.set_enabled(false);
        rx.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x201, &[1]).unwrap());
        assert_eq!(rx.poll_event(), None, "disabled");
    }
}

#[cfg(test)]
mod deadline_tests {
    use super::*;
    use crate::pdo::{PdoCobId, PdoCommParams, PdoMapping, PdoSlot};

    /// The set's deadline is its producers' earliest: none or the
    /// earliest event timer.
    #[test]
    fn the_deadline_is_the_earliest_event_timer() {
        let mut set: TpdoSet<4> = TpdoSet::empty();
        assert_eq!(set.poll_timeout(), None);
        let mut config: PdoConfig<4, 4> = PdoConfig::new();
        for (n, ms) in [(PdoNumber::P0, 300), (PdoNumber::P2, 200)] {
            let comm = PdoCommParams::event_driven(PdoCobId::from_u32(0x180 + ms), ms as u16);
            config.insert(
                PdoDirection::Transmit,
                n,
                PdoSlot::new(comm, &PdoMapping::EMPTY),
            );
        }
        set.reconfigure(Timestamp::ZERO, &config);
        set.set_operational(Timestamp::ZERO, true);
        let earliest = Some(Timestamp::from_millis(200));
        assert_eq!(set.poll_timeout(), earliest);
        set.set_operational(Timestamp::ZERO, false);
        assert_eq!(set.poll_timeout(), None);
    }
}
