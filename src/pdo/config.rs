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
//! (which also says which objects are PDO-mappable, and how long).
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

use super::comm::{PdoCommParams, PdoDirection};
use super::mapping::{MappingEntry, MappingError, PdoMapping, MAX_ENTRIES};
use crate::cob_id::PdoNumber;
use crate::od::{Access, ObjectDictionary, ObjectInfo, SizeRule, WriteBuffer};
use crate::sdo::AbortCode;

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

    /// The active mapping (the first `count` entries). Always valid: a count
    /// is only accepted when its entries form a valid mapping.
    #[must_use]
    pub fn mapping(&self) -> PdoMapping {
        PdoMapping::new(self.entries.get(..usize::from(self.count)).unwrap_or(&[]))
            .unwrap_or(PdoMapping::EMPTY)
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

/// The PDO configuration of a device: up to 4 RPDOs and 4 TPDOs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PdoConfig {
    rpdo: [Option<PdoSlot>; 4],
    tpdo: [Option<PdoSlot>; 4],
}

impl PdoConfig {
    /// A device without PDOs.
    #[must_use]
    pub const fn new() -> Self {
        PdoConfig {
            rpdo: [None; 4],
            tpdo: [None; 4],
        }
    }

    /// Removes every PDO (what [`new`](Self::new) gives), in place: no
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
        for slot in self.rpdo.iter_mut().chain(self.tpdo.iter_mut()) {
            *slot = None;
        }
    }

    /// Adds (or replaces) a PDO.
    pub fn insert(&mut self, dir: PdoDirection, n: PdoNumber, slot: PdoSlot) -> &mut Self {
        if let Some(s) = self.slots_mut(dir).get_mut(usize::from(n.raw())) {
            *s = Some(slot);
        }
        self
    }

    /// A PDO's configuration, if the device has it.
    #[must_use]
    pub fn get(&self, dir: PdoDirection, n: PdoNumber) -> Option<&PdoSlot> {
        self.slots(dir).get(usize::from(n.raw()))?.as_ref()
    }

    /// The same, mutably (the application's own changes; no rules applied).
    pub fn get_mut(&mut self, dir: PdoDirection, n: PdoNumber) -> Option<&mut PdoSlot> {
        self.slots_mut(dir).get_mut(usize::from(n.raw()))?.as_mut()
    }

    fn slots(&self, dir: PdoDirection) -> &[Option<PdoSlot>; 4] {
        match dir {
            PdoDirection::Receive => &self.rpdo,
            PdoDirection::Transmit => &self.tpdo,
        }
    }

    fn slots_mut(&mut self, dir: PdoDirection) -> &mut [Option<PdoSlot>; 4] {
        match dir {
            PdoDirection::Receive => &mut self.rpdo,
            PdoDirection::Transmit => &mut self.tpdo,
        }
    }
}

/// An [`ObjectDictionary`] serving the PDO objects from a [`PdoConfig`] with
/// the reconfiguration rules, and everything else from `D`.
#[derive(Debug, Clone)]
pub struct PdoDictionary<D> {
    /// The PDO configuration.
    pub config: PdoConfig,
    /// The application's dictionary (all other objects).
    pub inner: D,
    pending: WriteBuffer,
}

impl<D: ObjectDictionary> PdoDictionary<D> {
    /// Layers `config` over `inner`.
    pub const fn new(config: PdoConfig, inner: D) -> Self {
        PdoDictionary {
            config,
            inner,
            pending: WriteBuffer::new(),
        }
    }

    fn pdo_object(&self, index: u16) -> Option<(PdoDirection, PdoNumber, bool, &PdoSlot)> {
        let (dir, n, is_mapping) = PdoDirection::from_index(index)?;
        Some((dir, n, is_mapping, self.config.get(dir, n)?))
    }

    /// Applies a complete write of `data` to a PDO object, or refuses it.
    fn apply(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<(), AbortCode> {
        let (dir, n, is_mapping) =
            PdoDirection::from_index(index).ok_or(AbortCode::ObjectDoesNotExist)?;
        let slot = *self
            .config
            .get(dir, n)
            .ok_or(AbortCode::ObjectDoesNotExist)?;
        let new = if is_mapping {
            self.apply_mapping(slot, sub, data)?
        } else {
            apply_comm(slot, sub, data)?
        };
        if let Some(s) = self.config.get_mut(dir, n) {
            *s = new;
        }
        Ok(())
    }

    fn apply_mapping(&self, mut slot: PdoSlot, sub: u8, data: &[u8]) -> Result<PdoSlot, AbortCode> {
        if sub as usize > MAX_ENTRIES {
            return Err(AbortCode::SubIndexDoesNotExist);
        }
        let want = if sub == 0 { 1 } else { 4 };
        check_len(data, want)?;
        if slot.is_valid() {
            return Err(AbortCode::UnsupportedAccess);
        }
        if sub == 0 {
            let count = data.first().copied().unwrap_or(0);
            if count == 0 {
                slot.count = 0;
                return Ok(slot);
            }
            if slot.count != 0 {
                return Err(AbortCode::UnsupportedAccess);
            }
            if usize::from(count) > MAX_ENTRIES {
                return Err(AbortCode::PdoLengthExceeded);
            }
            let entries = slot.entries.get(..usize::from(count)).unwrap_or(&[]);
            if let Some(e) = entries.iter().find(|e| e.is_empty() || e.bits == 0) {
                return Err(MappingError::EmptyEntry { entry: *e }.abort_code());
            }
            let mapping = PdoMapping::new(entries).map_err(MappingError::abort_code)?;
            mapping
                .check(&self.inner)
                .map_err(MappingError::abort_code)?;
            slot.count = count;
            return Ok(slot);
        }
        if slot.count != 0 {
            return Err(AbortCode::UnsupportedAccess);
        }
        let raw = match *data {
            [a, b, c, d] => u32::from_le_bytes([a, b, c, d]),
            _ => return Err(AbortCode::DataTypeLengthTooLow),
        };
        let entry = MappingEntry::from_u32(raw);
        if !entry.is_empty() {
            entry.check(&self.inner).map_err(MappingError::abort_code)?;
        }
        if let Some(e) = slot.entries.get_mut(usize::from(sub) - 1) {
            *e = entry;
        }
        Ok(slot)
    }
}

fn check_len(data: &[u8], want: usize) -> Result<(), AbortCode> {
    match data.len() {
        n if n > want => Err(AbortCode::DataTypeLengthTooHigh),
        n if n < want => Err(AbortCode::DataTypeLengthTooLow),
        _ => Ok(()),
    }
}

fn apply_comm(mut slot: PdoSlot, sub: u8, data: &[u8]) -> Result<PdoSlot, AbortCode> {
    let old = slot.comm;
    slot.comm.decode_sub(sub, data)?;
    match sub {
        1 => {
            let new = slot.comm.cob_id;
            if new.is_valid() && new.can_id().is_none() {
                return Err(AbortCode::InvalidValue);
            }
            if old.cob_id.is_valid() && new.is_valid() && !old.cob_id.same_identifier(new) {
                return Err(AbortCode::InvalidValue);
            }
        }
        3 if old.cob_id.is_valid() && slot.comm.inhibit_time_100us != old.inhibit_time_100us => {
            return Err(AbortCode::InvalidValue);
        }
        _ => {}
    }
    Ok(slot)
}

impl<D: ObjectDictionary> ObjectDictionary for PdoDictionary<D> {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        let Some((_, _, is_mapping, _)) = self.pdo_object(index) else {
            if PdoDirection::from_index(index).is_some() {
                return Err(AbortCode::ObjectDoesNotExist);
            }
            return self.inner.info(index, sub);
        };
        let len = if is_mapping {
            match sub {
                0 => 1,
                1..=8 => 4,
                _ => return Err(AbortCode::SubIndexDoesNotExist),
            }
        } else {
            PdoCommParams::sub_len(sub).ok_or(AbortCode::SubIndexDoesNotExist)?
        };
        let access = if !is_mapping && sub == 0 {
            Access::ReadOnly
        } else {
            Access::ReadWrite
        };
        Ok(ObjectInfo {
            access,
            len,
            size: SizeRule::Fixed(len),
            pdo_mappable: false,
        })
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let Some((_, _, is_mapping, slot)) = self.pdo_object(index) else {
            if PdoDirection::from_index(index).is_some() {
                return Err(AbortCode::ObjectDoesNotExist);
            }
            return self.inner.read(index, sub, offset, buf);
        };
        let value: crate::bytes::InlineData<4> = if is_mapping {
            match sub {
                0 => crate::bytes::InlineData::new(&[slot.count]),
                s => slot
                    .entry(s)
                    .and_then(|e| crate::bytes::InlineData::new(&e.to_u32().to_le_bytes())),
            }
        } else {
            slot.comm.encode_sub(sub)
        }
        .ok_or(AbortCode::SubIndexDoesNotExist)?;
        Ok(crate::od::read_at(value.as_slice(), offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        if self.pdo_object(index).is_none() {
            if PdoDirection::from_index(index).is_some() {
                return Err(AbortCode::ObjectDoesNotExist);
            }
            return self.inner.write(index, sub, offset, data);
        }
        // PDO objects are at most 4 bytes: buffer until finish_write.
        self.pending.write(index, sub, offset, data)
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        if self.pdo_object(index).is_none() {
            return self.inner.finish_write(index, sub, len);
        }
        let mut pending = self.pending;
        self.pending.clear();
        let data = pending.take(index, sub);
        self.apply(index, sub, data.get(..len.min(data.len())).unwrap_or(&[]))
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        if self.pdo_object(index).is_none() {
            return self.inner.abort_write(index, sub);
        }
        self.pending.clear();
    }
}
