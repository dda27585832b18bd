//! The device side of PDO configuration: objects 1400h-1403h, 1600h-1603h,
//! 1800h-1803h and 1A00h-1A03h as an [`ObjectDictionary`] layer that
//! enforces the CiA 301 PDO mapping procedure when the SDO server writes
//! them: the mapping of a PDO changes only while its COB-ID has bit 31 set
//! (not valid) and its sub-index 0 is 0; sub 0 then takes 1..=8 entries
//! whose objects are mappable, non-zero and 64 bits at most in total (the
//! procedure "Delta-Q IC Series CANopen interface specification rev 2.0",
//! section 4.6.2, spells out for the charger).
//!
//! [`PdoDictionary`] wraps the application's dictionary `D`: it serves the
//! PDO objects from its [`PdoConfig`] and passes every other index to `D`
//! (which also says which objects are PDO-mappable, and how long). The
//! configuration has room for `T` TPDOs and `R` RPDOs ([`PdoConfig`]): the
//! objects of a PDO past them, or of one it has room for but does not
//! have, do not exist (06020000h).
//!
//! # Rules and abort codes
//!
//! | write | refused when | abort code |
//! |---|---|---|
//! | comm. sub 0, mapping sub 0 of a missing PDO | always | 06010002h / 06020000h |
//! | comm. sub 1 (COB-ID) | the PDO is valid and the new value is valid with another identifier | 06090030h |
//! | comm. sub 1 | a valid 11-bit COB-ID with bits 28-11 set | 06090030h |
//! | comm. sub 2 (transmission type) | 241-253 (reserved, RTR-only) | 06090030h |
//! | comm. sub 3 (inhibit time) | the PDO is valid | 06090030h |
//! | mapping sub 0 or 1-8 | the PDO is valid (COB-ID bit 31 clear) | 06010000h |
//! | mapping sub 1-8 | sub 0 is not 0 | 06010000h |
//! | mapping sub 1-8 | the object does not exist / sub-index does not / is not mappable or too short | 06020000h / 06090011h / 06040041h |
//! | mapping sub 0 = n > 0 | sub 0 was not 0 (every change goes through 0) | 06010000h |
//! | mapping sub 0 = n | n > 8 | 06040042h |
//! | mapping sub 0 = n | a counted entry is zero | 06090030h |
//! | mapping sub 0 = n | the counted entries exceed 64 bits | 06040042h |
//! | any | wrong length | 06070012h / 06070013h |
//!
//! 06010000h for writes the PDO's state forbids follows CANopenNode
//! (Lely answers 06090030h); the other codes are the ones CiA 301 names.
//! Values are applied only when the whole download is accepted
//! ([`ObjectDictionary::finish_write`]); a refused write changes nothing.

use super::comm::{PdoCobId, PdoCommParams, PdoDirection, TransmissionType};
use super::mapping::{MappingEntry, MappingError, PdoMapping, MAX_BITS, MAX_ENTRIES};
use crate::abort::AbortCode;
use crate::cob_id::PdoNumber;
use crate::od::index::{TPDO_COMMUNICATION, TPDO_MAPPING};
use crate::od::{comm, Access, Address, ObjectDictionary, ObjectInfo, WriteBuffer};

/// The access rights of a PDO parameter sub-index as the communication
/// table ([`comm::COMM_OBJECTS`]) gives them, read when the crate is built
/// (RPDOs and TPDOs alike; the tests hold them equal).
const fn table_access(index: u16, sub: u8) -> Access {
    match comm::find(Address::new(index, sub)) {
        Some(row) => row.access,
        None => panic!("the communication table has a row for every PDO parameter"),
    }
}
/// Sub-index 0 of a communication parameter (the highest sub-index).
const COMM_COUNT_ACCESS: Access = table_access(TPDO_COMMUNICATION, 0);
/// Sub-indexes 1-6 of a communication parameter.
const COMM_ACCESS: Access = table_access(TPDO_COMMUNICATION, 1);
/// Sub-index 0 of a mapping parameter (the number of entries).
const MAPPING_COUNT_ACCESS: Access = table_access(TPDO_MAPPING, 0);
/// The entries of a mapping parameter.
const MAPPING_ACCESS: Access = table_access(TPDO_MAPPING, 1);

/// One PDO's configuration: communication parameters and mapping entries
/// (all 8 sub-indexes are kept, counted or not).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PdoSlot {
    /// Communication parameters.
    pub comm: PdoCommParams,
    entries: [MappingEntry; MAX_ENTRIES],
    count: u8,
}

impl PdoSlot {
    /// A slot with these parameters and mapping.
    #[must_use]
    pub fn new(comm: PdoCommParams, mapping: &PdoMapping) -> Self {
        let mut entries = [MappingEntry::default(); MAX_ENTRIES];
        for (e, m) in entries.iter_mut().zip(mapping.entries()) {
            *e = *m;
        }
        PdoSlot {
            comm,
            entries,
            count: mapping.len() as u8,
        }
    }

    /// A slot with these parameters and the mapping `entries` of a
    /// profile's default table ([`DefaultPdo::entries`](super::DefaultPdo::entries):
    /// index, sub-index, bits; the first [`MAX_ENTRIES`]), written straight
    /// into the slot without a [`PdoMapping`] built and checked first (a
    /// device's reset writes its default PDOs in place). The entries must
    /// form a valid mapping, which the profile checks for its whole table at
    /// compile time with [`table_mapping_valid`](Self::table_mapping_valid).
    #[must_use]
    pub(crate) const fn from_table(comm: PdoCommParams, entries: &[(u16, u8, u8)]) -> Self {
        let mut slot = PdoSlot {
            comm,
            entries: [MappingEntry::new(0, 0, 0); MAX_ENTRIES],
            count: 0,
        };
        while (slot.count as usize) < entries.len() && (slot.count as usize) < MAX_ENTRIES {
            let (index, sub, bits) = entries[slot.count as usize];
            slot.entries[slot.count as usize] = MappingEntry::new(index, sub, bits);
            slot.count += 1;
        }
        slot
    }

    /// True when `entries` (index, sub-index, bits) form a valid mapping:
    /// the rules of [`PdoMapping::new`], in a `const fn` (a profile's check
    /// of its default table for [`from_table`](Self::from_table)).
    #[must_use]
    pub(crate) const fn table_mapping_valid(entries: &[(u16, u8, u8)]) -> bool {
        if entries.len() > MAX_ENTRIES {
            return false;
        }
        let (mut i, mut total) = (0, 0u32);
        while i < entries.len() {
            let (_, _, bits) = entries[i];
            if bits == 0 {
                return false;
            }
            total += bits as u32;
            i += 1;
        }
        total <= MAX_BITS
    }

    /// The active mapping (the first `count` entries). Always valid: a count
    /// is only accepted when its entries form a valid mapping.
    #[must_use]
    pub fn mapping(&self) -> PdoMapping {
        PdoMapping::new(self.mapped()).unwrap_or(PdoMapping::EMPTY)
    }

    /// The counted entries (a valid mapping, see [`Self::mapping`]),
    /// without building a [`PdoMapping`]: the run-time paths.
    #[inline]
    pub(crate) fn mapped(&self) -> &[MappingEntry] {
        self.entries.get(..usize::from(self.count)).unwrap_or(&[])
    }

    /// Mapping sub-index 0.
    #[must_use]
    pub const fn count(&self) -> u8 {
        self.count
    }

    /// Mapping sub-index `sub` (1..=8), counted or not.
    #[must_use]
    pub fn entry(&self, sub: u8) -> Option<MappingEntry> {
        self.entries.get(usize::from(sub).checked_sub(1)?).copied()
    }

    /// True when the COB-ID's bit 31 is clear.
    #[must_use]
    pub const fn is_valid(&self) -> bool {
        self.comm.cob_id.is_valid()
    }
}

/// The PDO configuration of a device: `R` RPDOs and `T` TPDOs (at most 4
/// each, the PDO numbers [`PdoNumber`] has; default 4 and 4). A PDO
/// number the device does not have has no slot: [`get`](Self::get) gives
/// `None`, [`insert`](Self::insert) ignores it, and over SDO its objects
/// do not exist (CiA 301: the PDO objects exist for the PDOs a device has).
///
/// ```
/// use canopen_codec::pdo::{PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoMapping, PdoSlot};
/// use canopen_codec::PdoNumber;
/// // 3 TPDOs and 3 RPDOs (a CiA 418 battery module).
/// let mut pdos = PdoConfig::<3, 3>::empty();
/// let comm = PdoCommParams::event_driven(PdoCobId::from_u32(0x184), 100);
/// pdos.insert(PdoDirection::Transmit, PdoNumber::P2, PdoSlot::new(comm, &PdoMapping::EMPTY));
/// pdos.insert(PdoDirection::Transmit, PdoNumber::P3, PdoSlot::new(comm, &PdoMapping::EMPTY));
/// assert!(pdos.get(PdoDirection::Transmit, PdoNumber::P2).is_some());
/// assert_eq!(pdos.get(PdoDirection::Transmit, PdoNumber::P3), None); // no TPDO 3
/// assert_eq!(PdoConfig::<3, 3>::count(PdoDirection::Receive), 3);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PdoConfig<const T: usize = 4, const R: usize = 4> {
    /// RPDO 0..R.
    rpdos: [Option<PdoSlot>; R],
    /// TPDO 0..T.
    tpdos: [Option<PdoSlot>; T],
}

impl Default for PdoConfig {
    fn default() -> Self {
        Self::new()
    }
}

impl PdoConfig {
    /// A device without PDOs, with room for 4 TPDOs and 4 RPDOs (other
    /// counts: [`empty`](Self::empty)).
    #[must_use]
    pub const fn new() -> Self {
        Self::empty()
    }
}

impl<const T: usize, const R: usize> PdoConfig<T, R> {
    /// A device without PDOs, with room for `T` TPDOs and `R` RPDOs. Counts
    /// above 4 do not compile (no PDO number has the slots past 4).
    #[must_use]
    pub const fn empty() -> Self {
        const { assert!(T <= 4 && R <= 4, "at most 4 TPDOs and 4 RPDOs") };
        PdoConfig {
            rpdos: [None; R],
            tpdos: [None; T],
        }
    }

    /// How many PDOs of `dir` the configuration has room for (`T` or `R`).
    #[must_use]
    pub const fn count(dir: PdoDirection) -> usize {
        match dir {
            PdoDirection::Receive => R,
            PdoDirection::Transmit => T,
        }
    }

    /// Removes every PDO (what [`empty`](Self::empty) gives), in place: no
    /// empty configuration built in a temporary and copied (a device's NMT
    /// reset restores its PDOs into the live one).
    ///
    /// ```
    /// use canopen_codec::pdo::{PdoCobId, PdoCommParams, PdoConfig, PdoDirection, PdoMapping, PdoSlot};
    /// use canopen_codec::PdoNumber;
    /// let mut pdos = PdoConfig::new();
    /// let comm = PdoCommParams::event_driven(PdoCobId::from_u32(0x181), 100);
    /// pdos.insert(PdoDirection::Transmit, PdoNumber::P0, PdoSlot::new(comm, &PdoMapping::EMPTY));
    /// pdos.clear();
    /// assert_eq!(pdos, PdoConfig::new());
    /// ```
    pub fn clear(&mut self) {
        for slot in self.rpdos.iter_mut().chain(&mut self.tpdos) {
            *slot = None;
        }
    }

    /// Copies the PDOs of `other` this configuration has room for, and
    /// removes the others (a configuration of other counts restored into
    /// this one).
    pub fn copy_from<const T2: usize, const R2: usize>(&mut self, other: &PdoConfig<T2, R2>) {
        self.clear();
        for (d, s) in self.rpdos.iter_mut().zip(&other.rpdos) {
            *d = *s;
        }
        for (d, s) in self.tpdos.iter_mut().zip(&other.tpdos) {
            *d = *s;
        }
    }

    #[inline]
    fn slots_mut(&mut self, dir: PdoDirection) -> &mut [Option<PdoSlot>] {
        match dir {
            PdoDirection::Receive => &mut self.rpdos,
            PdoDirection::Transmit => &mut self.tpdos,
        }
    }

    /// Adds (or replaces) a PDO; a number the configuration has no room
    /// for is ignored.
    pub fn insert(&mut self, dir: PdoDirection, n: PdoNumber, slot: PdoSlot) -> &mut Self {
        if let Some(s) = self.slots_mut(dir).get_mut(usize::from(n.raw())) {
            *s = Some(slot);
        }
        self
    }

    /// A PDO's configuration, if the device has it.
    #[must_use]
    #[inline(never)]
    pub fn get(&self, dir: PdoDirection, n: PdoNumber) -> Option<&PdoSlot> {
        let slots: &[Option<PdoSlot>] = match dir {
            PdoDirection::Receive => &self.rpdos,
            PdoDirection::Transmit => &self.tpdos,
        };
        slots.get(usize::from(n.raw()))?.as_ref()
    }

    /// The same, mutably (the application's own changes; no rules applied).
    #[inline(never)]
    pub fn get_mut(&mut self, dir: PdoDirection, n: PdoNumber) -> Option<&mut PdoSlot> {
        self.slots_mut(dir).get_mut(usize::from(n.raw()))?.as_mut()
    }

    /// TPDO 0..T.
    #[inline]
    pub(crate) fn tpdos(&self) -> &[Option<PdoSlot>; T] {
        &self.tpdos
    }

    /// RPDO 0..R.
    #[inline]
    pub(crate) fn rpdos(&self) -> &[Option<PdoSlot>; R] {
        &self.rpdos
    }
}

/// An [`ObjectDictionary`] serving the PDO objects from a [`PdoConfig`] with
/// the reconfiguration rules, and everything else from `D`.
#[derive(Debug, Clone)]
pub struct PdoDictionary<D, const T: usize = 4, const R: usize = 4> {
    /// The PDO configuration.
    pub config: PdoConfig<T, R>,
    /// The application's dictionary (all other objects).
    pub inner: D,
    pending: WriteBuffer,
}

impl<D: ObjectDictionary, const T: usize, const R: usize> PdoDictionary<D, T, R> {
    /// Layers `config` over `inner`.
    pub const fn new(config: PdoConfig<T, R>, inner: D) -> Self {
        PdoDictionary {
            config,
            inner,
            pending: WriteBuffer::new(),
        }
    }

    /// Access, value (a little-endian word) and length of PDO object
    /// `index`/`sub`: the one lookup `info`, `read`, `write` and
    /// `finish_write` share. `None` for an index of the application's
    /// dictionary; 06020000h for the objects of a PDO the device does not
    /// have, 06090011h for a sub-index the object does not have.
    fn entry(&self, index: u16, sub: u8) -> Option<Result<(Access, u32, usize), AbortCode>> {
        let (dir, n, is_mapping) = PdoDirection::from_index(index)?;
        let Some(slot) = self.config.get(dir, n) else {
            return Some(Err(AbortCode::ObjectDoesNotExist));
        };
        let value = match (is_mapping, sub) {
            (true, 0) => Some((u32::from(slot.count), 1)),
            (true, s) => slot.entry(s).map(|e| (e.to_u32(), 4)),
            (false, s) => slot.comm.sub_word(s),
        };
        let access = match (is_mapping, sub) {
            (false, 0) => COMM_COUNT_ACCESS,
            (false, _) => COMM_ACCESS,
            (true, 0) => MAPPING_COUNT_ACCESS,
            (true, _) => MAPPING_ACCESS,
        };
        Some(match value {
            Some((word, len)) => Ok((access, word, len)),
            None => Err(AbortCode::SubIndexDoesNotExist),
        })
    }
}

/// The rules for a write of `raw` (its length checked) to mapping
/// sub-index `sub` (0..=8) (see the module docs); `slot` changes only
/// when the write is accepted.
fn apply_mapping<D: ObjectDictionary + ?Sized>(
    slot: &mut PdoSlot,
    sub: u8,
    raw: u32,
    od: &D,
) -> Result<(), AbortCode> {
    if slot.is_valid() {
        return Err(AbortCode::UnsupportedAccess);
    }
    if sub == 0 && raw == 0 {
        slot.count = 0;
        return Ok(());
    }
    // Every change goes through sub 0 = 0.
    if slot.count != 0 {
        return Err(AbortCode::UnsupportedAccess);
    }
    if sub == 0 {
        let count = raw as usize;
        let entries = slot
            .entries
            .get(..count)
            .ok_or(AbortCode::PdoLengthExceeded)?;
        let mut bits = 0u32;
        for e in entries {
            if e.bits == 0 {
                return Err(MappingError::EmptyEntry { entry: *e }.abort_code());
            }
            bits += u32::from(e.bits);
        }
        if bits > MAX_BITS {
            return Err(AbortCode::PdoLengthExceeded);
        }
        for e in entries {
            e.check_abort(od)?;
        }
        slot.count = raw as u8;
        return Ok(());
    }
    let entry = MappingEntry::from_u32(raw);
    if !entry.is_empty() {
        entry.check_abort(od)?;
    }
    if let Some(e) = slot.entries.get_mut(usize::from(sub) - 1) {
        *e = entry;
    }
    Ok(())
}

/// The rules for a write of `word` (its length checked) to communication
/// sub-index `sub` (1..=5; 0 is read-only); `slot` changes only when the
/// write is accepted.
fn apply_comm(slot: &mut PdoSlot, sub: u8, word: u32) -> Result<(), AbortCode> {
    let comm = &mut slot.comm;
    let old_cob = comm.cob_id;
    // Each value is its sub-index's width: the casts keep all of it.
    match sub {
        1 => {
            let new_cob = PdoCobId::from_u32(word);
            if new_cob.is_valid()
                && (new_cob.can_id().is_none()
                    || (old_cob.is_valid() && !old_cob.same_identifier(new_cob)))
            {
                return Err(AbortCode::InvalidValue);
            }
            comm.cob_id = new_cob;
        }
        2 => comm.transmission_type = TransmissionType::from_u8(word as u8)?,
        3 => {
            if old_cob.is_valid() && word as u16 != comm.inhibit_time_100us {
                return Err(AbortCode::InvalidValue);
            }
            comm.inhibit_time_100us = word as u16;
        }
        4 => comm.reserved = word as u8,
        5 => comm.event_timer_ms = word as u16,
        _ => return Err(AbortCode::WriteOfReadOnlyObject),
    }
    Ok(())
}

impl<D: ObjectDictionary, const T: usize, const R: usize> ObjectDictionary
    for PdoDictionary<D, T, R>
{
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        let Some(object) = self.entry(index, sub) else {
            return self.inner.info(index, sub);
        };
        let (access, _, len) = object?;
        Ok(ObjectInfo::fixed(access, len))
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let Some(object) = self.entry(index, sub) else {
            return self.inner.read(index, sub, offset, buf);
        };
        let (_, word, len) = object?;
        let bytes = word.to_le_bytes();
        let value = bytes.get(..len).unwrap_or(&bytes);
        Ok(crate::od::read_at(value, offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let Some(object) = self.entry(index, sub) else {
            return self.inner.write(index, sub, offset, data);
        };
        object?;
        // PDO objects are at most 4 bytes: buffered until finish_write,
        // which checks them whole.
        self.pending.write(index, sub, offset, data)
    }

    /// Applies the buffered write to a PDO object, or refuses it (and
    /// changes nothing: the rules are checked before any change).
    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let Some(object) = self.entry(index, sub) else {
            return self.inner.finish_write(index, sub, len);
        };
        let (access, _, size) = self.pending.unless_refused(object)?;
        let word = self
            .pending
            .downloaded_value(access, size, index, sub, len)?;
        // The object exists: `entry` found its PDO.
        let Some((dir, n, is_mapping)) = PdoDirection::from_index(index) else {
            return Err(AbortCode::ObjectDoesNotExist);
        };
        let slot = self
            .config
            .get_mut(dir, n)
            .ok_or(AbortCode::ObjectDoesNotExist)?;
        if is_mapping {
            apply_mapping(slot, sub, word, &self.inner)
        } else {
            apply_comm(slot, sub, word)
        }
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        if super::comm::is_pdo_index(index) {
            self.pending.clear();
        } else {
            self.inner.abort_write(index, sub);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slot(id: u32) -> PdoSlot {
        PdoSlot::new(
            PdoCommParams::event_driven(PdoCobId::from_u32(id), 0),
            &PdoMapping::EMPTY,
        )
    }

    /// The PDO objects through the dictionary itself (no SDO server in
    /// between): every sub-index's access, length and value, and every
    /// refusal's code; a refused write changes nothing and leaves nothing
    /// buffered.
    #[test]
    fn pdo_objects_through_the_dictionary() {
        use Access::{ReadOnly as Ro, ReadWrite as Rw};
        let mut config = PdoConfig::<1, 1>::empty();
        let mapping = PdoMapping::new(&[MappingEntry::new(0x2000, 0, 16)]).unwrap();
        let comm = PdoCommParams::event_driven(PdoCobId::from_u32(0x8000_0181), 100);
        config.insert(
            PdoDirection::Transmit,
            PdoNumber::P0,
            PdoSlot::new(comm, &mapping),
        );
        let mut od = PdoDictionary::new(config, crate::od::fixture::Word::<2>(7));
        let mut buf = [0u8; 4];
        let rows: [(u16, u8, Access, &[u8]); 8] = [
            (0x1800, 0, Ro, &[5]),
            (0x1800, 1, Rw, &[0x81, 0x01, 0, 0x80]),
            (0x1800, 2, Rw, &[255]),
            (0x1800, 3, Rw, &[0, 0]),
            (0x1800, 4, Rw, &[0]),
            (0x1800, 5, Rw, &[100, 0]),
            (0x1A00, 0, Rw, &[1]),
            (0x1A00, 1, Rw, &[0x10, 0x00, 0x00, 0x20]),
        ];
        for (index, sub, access, value) in rows {
            let info = od.info(index, sub).unwrap();
            assert_eq!(
                (info.access, info.len, info.pdo_mappable),
                (access, value.len(), false)
            );
            assert_eq!(od.read(index, sub, 0, &mut buf), Ok(value.len()));
            assert_eq!(&buf[..value.len()], value, "{index:04X}h:{sub}");
        }
        assert_eq!(
            od.read(0x1A00, 2, 0, &mut buf),
            Ok(4),
            "an uncounted entry reads"
        );
        let before = od.config;
        let finish = |od: &mut PdoDictionary<crate::od::fixture::Word<2>, 1, 1>,
                      index: u16,
                      sub: u8,
                      data: &[u8]| {
            od.write(index, sub, 0, data)
                .and_then(|()| od.finish_write(index, sub, data.len()))
        };
        let refused: [(u16, u8, &[u8], AbortCode); 13] = [
            (0x1800, 0, &[5], AbortCode::WriteOfReadOnlyObject),
            (0x1800, 1, &[0x81, 0x01, 0], AbortCode::DataTypeLengthTooLow),
            (0x1800, 3, &[1, 0, 0], AbortCode::DataTypeLengthTooHigh),
            (0x1800, 2, &[241], AbortCode::InvalidValue),
            (0x1800, 2, &[253], AbortCode::InvalidValue),
            // A valid 11-bit COB-ID with bits 28-11 set.
            (0x1800, 1, &[0x81, 0x09, 0, 0], AbortCode::InvalidValue),
            (0x1800, 6, &[0], AbortCode::SubIndexDoesNotExist),
            (0x1A00, 9, &[0; 4], AbortCode::SubIndexDoesNotExist),
            (0x1A00, 0, &[0, 0], AbortCode::DataTypeLengthTooHigh),
            // Sub 0 is 1: entries change only while it is 0.
            (0x1A00, 1, &[0x10, 0, 0, 0x20], AbortCode::UnsupportedAccess),
            (0x1A00, 0, &[2], AbortCode::UnsupportedAccess),
            // No TPDO 2, no RPDO 1 at all.
            (0x1801, 1, &[0; 4], AbortCode::ObjectDoesNotExist),
            (0x1400, 1, &[0; 4], AbortCode::ObjectDoesNotExist),
        ];
        for (index, sub, data, code) in refused {
            assert_eq!(
                finish(&mut od, index, sub, data),
                Err(code),
                "{index:04X}h:{sub} {data:?}"
            );
            assert_eq!(od.config, before, "{index:04X}h:{sub}: nothing changed");
        }
        // Through sub 0 = 0: an entry of a missing object or sub-index,
        // or one too long for its object, is refused with its code.
        assert_eq!(finish(&mut od, 0x1A00, 0, &[0]), Ok(()));
        for (entry, code) in [
            (0x2100_0010u32, AbortCode::ObjectDoesNotExist),
            (0x2000_0110, AbortCode::SubIndexDoesNotExist),
            (0x2000_0020, AbortCode::ObjectCannotBeMapped),
        ] {
            assert_eq!(finish(&mut od, 0x1A00, 1, &entry.to_le_bytes()), Err(code));
        }
        assert_eq!(
            finish(&mut od, 0x1A00, 1, &0x2000_0008u32.to_le_bytes()),
            Ok(())
        );
        assert_eq!(finish(&mut od, 0x1A00, 0, &[1]), Ok(()));
        // A valid PDO: its inhibit time and identifier are fixed.
        assert_eq!(finish(&mut od, 0x1800, 1, &[0x81, 0x01, 0, 0]), Ok(()));
        assert_eq!(
            finish(&mut od, 0x1800, 3, &[1, 0]),
            Err(AbortCode::InvalidValue)
        );
        assert_eq!(
            finish(&mut od, 0x1800, 1, &[0x82, 0x01, 0, 0]),
            Err(AbortCode::InvalidValue)
        );
        assert_eq!(
            finish(&mut od, 0x1A00, 0, &[0]),
            Err(AbortCode::UnsupportedAccess)
        );
        assert_eq!(finish(&mut od, 0x1800, 5, &[0xE8, 0x03]), Ok(()));
        let slot = od
            .config
            .get(PdoDirection::Transmit, PdoNumber::P0)
            .unwrap();
        assert_eq!(slot.comm.event_timer_ms, 1000);
        assert!(slot.is_valid());
        assert_eq!(slot.mapped(), &[MappingEntry::new(0x2000, 0, 8)]);
        // An aborted value leaves nothing for the next finish.
        od.write(0x1800, 5, 0, &[1, 0]).unwrap();
        od.abort_write(0x1800, 5);
        assert_eq!(
            od.finish_write(0x1800, 5, 2),
            Err(AbortCode::DataTypeLengthTooLow)
        );
        // Other indexes are the inner dictionary's.
        assert_eq!(od.read(0x2000, 0, 0, &mut buf), Ok(2));
        assert_eq!(od.info(0x2001, 0), Err(AbortCode::ObjectDoesNotExist));
    }

    const NUMBERS: [PdoNumber; 4] = [PdoNumber::P0, PdoNumber::P1, PdoNumber::P2, PdoNumber::P3];
    const DIRECTIONS: [PdoDirection; 2] = [PdoDirection::Receive, PdoDirection::Transmit];

    /// Every PDO number in both directions against counts 2 + 1 (and 0 + 0):
    /// room below the count, none at or above it, nothing panics, and the
    /// two directions never share a slot.
    #[test]
    fn room_follows_the_counts() {
        let mut pdos = PdoConfig::<2, 1>::empty();
        assert_eq!(
            (
                PdoConfig::<2, 1>::count(PdoDirection::Transmit),
                PdoConfig::<2, 1>::count(PdoDirection::Receive)
            ),
            (2, 1)
        );
        for dir in DIRECTIONS {
            for n in NUMBERS {
                let id =
                    0x100 * u32::from(n.raw()) + if dir == PdoDirection::Receive { 1 } else { 2 };
                pdos.insert(dir, n, slot(id));
            }
        }
        for dir in DIRECTIONS {
            for n in NUMBERS {
                let room = usize::from(n.raw()) < PdoConfig::<2, 1>::count(dir);
                let got = pdos.get(dir, n).map(|s| s.comm.cob_id.to_u32());
                let id =
                    0x100 * u32::from(n.raw()) + if dir == PdoDirection::Receive { 1 } else { 2 };
                assert_eq!(got, room.then_some(id), "{dir:?} {n}");
                assert_eq!(pdos.get_mut(dir, n).is_some(), room);
            }
        }
        let mut none = PdoConfig::<0, 0>::empty();
        for dir in DIRECTIONS {
            for n in NUMBERS {
                none.insert(dir, n, slot(0x181));
                assert_eq!(none.get(dir, n), None);
            }
        }
    }

    /// A configuration copied into one of other counts keeps the PDOs both
    /// have room for and loses the others; copied back, the lost ones stay
    /// lost.
    #[test]
    fn copy_between_counts() {
        let mut full = PdoConfig::new();
        for dir in DIRECTIONS {
            for n in NUMBERS {
                full.insert(dir, n, slot(0x180 + u32::from(n.raw())));
            }
        }
        let mut small = PdoConfig::<3, 2>::empty();
        small.insert(PdoDirection::Transmit, PdoNumber::P0, slot(0x555));
        small.copy_from(&full);
        assert_eq!(
            small.get(PdoDirection::Transmit, PdoNumber::P0),
            full.get(PdoDirection::Transmit, PdoNumber::P0)
        );
        assert!(small.get(PdoDirection::Transmit, PdoNumber::P2).is_some());
        assert!(small.get(PdoDirection::Receive, PdoNumber::P2).is_none());
        let mut back = PdoConfig::new();
        back.copy_from(&full);
        back.copy_from(&small);
        assert!(back.get(PdoDirection::Transmit, PdoNumber::P3).is_none());
        assert!(back.get(PdoDirection::Receive, PdoNumber::P1).is_some());
        assert!(back.get(PdoDirection::Receive, PdoNumber::P2).is_none());
        back.clear();
        assert_eq!(back, PdoConfig::new());
    }
}
