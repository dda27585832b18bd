//! [`FixedDictionary`]: the one dictionary of devices whose application
//! objects are all fixed-size values of 1, 2 or 4 bytes (CiA 301 basic
//! data types up to UNSIGNED32), held in the device's own fields. The CiA
//! 418 battery module and the Delta-Q charger declare their objects with
//! it: each says, through [`FixedObjects`], what an object is
//! ([`FixedEntry`]: access, value, length, PDO mapping) and how a complete
//! value is stored; the SDO read and write path, the download buffer and
//! the power-on values NMT reset node restores are here, once.
//!
//! Rules (CiA 301 7.2.4.3, SDO abort codes): a missing object is 06020000h,
//! a missing sub-index 06090011h, a write to a `ro`/`const` object
//! 06010002h, a value longer or shorter than the object 06070012h /
//! 06070013h, all given when the download completes; a value is stored
//! whole at [`finish_write`](ObjectDictionary::finish_write), so a refused
//! or aborted download changes nothing.

use super::{Access, ObjectDictionary, ObjectInfo, WriteBuffer};
use crate::abort::AbortCode;

/// One sub-object as a [`FixedObjects`] dictionary finds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FixedEntry {
    /// Access rights.
    pub access: Access,
    /// The value, little-endian: its first [`len`](Self::len) bytes.
    pub word: u32,
    /// Bytes: 1, 2 or 4.
    pub len: u8,
    /// True if the object may be mapped into a PDO.
    pub mappable: bool,
    /// The dictionary's own tag for where the value is stored (e.g. the
    /// row of its table), handed back to [`FixedObjects::store`].
    pub slot: u8,
}

impl FixedEntry {
    /// An object of `len` bytes holding `word`, not PDO-mappable, slot 0.
    #[must_use]
    pub const fn new(access: Access, word: u32, len: u8) -> Self {
        FixedEntry {
            access,
            word,
            len,
            mappable: false,
            slot: 0,
        }
    }

    /// What the SDO server is told about it.
    #[must_use]
    pub const fn info(&self) -> ObjectInfo {
        ObjectInfo {
            pdo_mappable: self.mappable,
            ..ObjectInfo::fixed(self.access, self.len as usize)
        }
    }
}

/// One single-value object (sub 0 only) of a dictionary's table: a row
/// says once what SDO info, reads and writes of the object use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FixedObject {
    /// The object's index.
    pub index: u16,
    /// Bytes: 1, 2 or 4.
    pub width: u8,
    /// Access rights.
    pub access: Access,
    /// True if the object may be mapped into a PDO.
    pub mappable: bool,
}

impl FixedObject {
    /// A row of a table.
    #[must_use]
    pub const fn new(index: u16, width: u8, access: Access, mappable: bool) -> Self {
        FixedObject {
            index,
            width,
            access,
            mappable,
        }
    }

    /// The entry of `index`/`sub` in `table`, the value read by `value`
    /// from the row number (which becomes the entry's
    /// [`slot`](FixedEntry::slot)); `None` when `index` has no row, and a
    /// sub-index other than 0 is 06090011h.
    ///
    /// ```
    /// use canopen_codec::od::{Access, FixedObject};
    /// use canopen_codec::sdo::AbortCode;
    /// const TABLE: [FixedObject; 2] = [
    ///     FixedObject::new(0x6000, 1, Access::ReadOnly, true),
    ///     FixedObject::new(0x6010, 2, Access::ReadWrite, true),
    /// ];
    /// let entry = FixedObject::lookup(&TABLE, 0x6010, 0, |row| 200 + row as u32).unwrap().unwrap();
    /// assert_eq!((entry.word, entry.len, entry.slot), (201, 2, 1));
    /// assert_eq!(FixedObject::lookup(&TABLE, 0x6010, 1, |_| 0), Some(Err(AbortCode::SubIndexDoesNotExist)));
    /// assert_eq!(FixedObject::lookup(&TABLE, 0x6020, 0, |_| 0), None);
    /// ```
    pub fn lookup(
        table: &[FixedObject],
        index: u16,
        sub: u8,
        value: impl FnOnce(usize) -> u32,
    ) -> Option<Result<FixedEntry, AbortCode>> {
        let (row, object) = table.iter().enumerate().find(|(_, o)| o.index == index)?;
        if sub != 0 {
            return Some(Err(AbortCode::SubIndexDoesNotExist));
        }
        Some(Ok(FixedEntry {
            access: object.access,
            word: value(row),
            len: object.width,
            mappable: object.mappable,
            slot: row as u8,
        }))
    }
}

/// The objects of a [`FixedDictionary`]: what each sub-object is, how a
/// complete value is checked and stored, and which ones NMT reset node
/// restores.
pub trait FixedObjects {
    /// The power-on values of [`PARAMETERS`](Self::PARAMETERS), their
    /// little-endian bytes one after the other (`[u8; N]`, N the sum of
    /// their lengths).
    type Parameters: Copy + Default + AsRef<[u8]> + AsMut<[u8]>;

    /// The sub-objects NMT reset node sets back to their value at boot:
    /// the parameters an SDO download or an RPDO can change (CiA 301
    /// 7.3.2.2.1). The others (the application's measurements and
    /// identity) keep the value the application last set, so no stale
    /// boot-time reading is published until its next update.
    const PARAMETERS: &'static [(u16, u8)];

    /// Describes `index`/`sub` with its current value, or 06020000h /
    /// 06090011h.
    fn entry(&self, index: u16, sub: u8) -> Result<FixedEntry, AbortCode>;

    /// Checks a complete value of the right length for a writable object
    /// before it is stored: the profile's value ranges (default: any value).
    fn check(&self, index: u16, sub: u8, word: u32) -> Result<(), AbortCode> {
        let _ = (index, sub, word);
        Ok(())
    }

    /// Stores `word` (its first `entry.len` bytes) as the value of the
    /// writable object `entry` describes (found as `index`/`sub`).
    fn store(&mut self, entry: &FixedEntry, index: u16, sub: u8, word: u32);
}

/// Objects `O` served as an [`ObjectDictionary`], with the buffer of the
/// download in progress. It dereferences to `O`, whose fields are the
/// application's to read and write.
///
/// ```
/// use canopen_codec::od::{Access, FixedDictionary, FixedEntry, FixedObject, FixedObjects, ObjectDictionary};
/// use canopen_codec::sdo::AbortCode;
///
/// /// A setpoint the bus writes (2000h, U16 rw) and a reading (2001h, U8 ro).
/// #[derive(Debug, Clone, Copy, Default)]
/// struct Objects { setpoint: u16, reading: u8 }
///
/// const TABLE: [FixedObject; 2] = [
///     FixedObject::new(0x2000, 2, Access::ReadWrite, true),
///     FixedObject::new(0x2001, 1, Access::ReadOnly, true),
/// ];
///
/// impl FixedObjects for Objects {
///     type Parameters = [u8; 2];
///     const PARAMETERS: &'static [(u16, u8)] = &[(0x2000, 0)];
///     fn entry(&self, index: u16, sub: u8) -> Result<FixedEntry, AbortCode> {
///         let value = |row| if row == 0 { u32::from(self.setpoint) } else { u32::from(self.reading) };
///         FixedObject::lookup(&TABLE, index, sub, value).unwrap_or(Err(AbortCode::ObjectDoesNotExist))
///     }
///     fn store(&mut self, _: &FixedEntry, _: u16, _: u8, word: u32) {
///         self.setpoint = word as u16; // the one writable object
///     }
/// }
///
/// let mut od = FixedDictionary::new(Objects::default());
/// let at_boot = od.parameters();
/// od.write(0x2000, 0, 0, &[0xE8, 0x03]).unwrap();
/// od.finish_write(0x2000, 0, 2).unwrap();
/// od.reading = 7; // the application's
/// assert_eq!((od.setpoint, od.info(0x2001, 0).unwrap().len), (1000, 1));
/// od.write(0x2001, 0, 0, &[1]).unwrap();
/// assert_eq!(od.finish_write(0x2001, 0, 1), Err(AbortCode::WriteOfReadOnlyObject));
/// od.restore_parameters(&at_boot); // NMT reset node
/// assert_eq!((od.setpoint, od.reading), (0, 7));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FixedDictionary<O> {
    objects: O,
    pending: WriteBuffer,
}

impl<O: Default> Default for FixedDictionary<O> {
    fn default() -> Self {
        Self::new(O::default())
    }
}

impl<O> FixedDictionary<O> {
    /// Serves `objects`.
    #[must_use]
    pub const fn new(objects: O) -> Self {
        FixedDictionary {
            objects,
            pending: WriteBuffer::new(),
        }
    }

    /// The objects.
    #[must_use]
    pub const fn objects(&self) -> &O {
        &self.objects
    }
}

impl<O: FixedObjects> FixedDictionary<O> {
    /// The values of [`FixedObjects::PARAMETERS`] as they are now (taken
    /// at boot, restored by reset node: [`FixedDictionary`]'s example).
    #[must_use]
    pub fn parameters(&self) -> O::Parameters {
        let mut values = O::Parameters::default();
        let mut bytes = values.as_mut();
        for &(index, sub) in O::PARAMETERS {
            let Ok(e) = self.objects.entry(index, sub) else {
                continue;
            };
            let word = e.word.to_le_bytes();
            let n = usize::from(e.len).min(word.len()).min(bytes.len());
            let (value, rest) = core::mem::take(&mut bytes).split_at_mut(n);
            value.copy_from_slice(word.get(..n).unwrap_or(&[]));
            bytes = rest;
        }
        values
    }

    /// Sets the values of [`FixedObjects::PARAMETERS`] back to `values`
    /// (what [`parameters`](Self::parameters) gave); stored as they are,
    /// without the range checks of a download.
    pub fn restore_parameters(&mut self, values: &O::Parameters) {
        let mut bytes = values.as_ref();
        for &(index, sub) in O::PARAMETERS {
            let Ok(e) = self.objects.entry(index, sub) else {
                continue;
            };
            let n = usize::from(e.len).min(bytes.len());
            let (value, rest) = bytes.split_at(n);
            let mut word = [0u8; 4];
            crate::bytes::copy_payload(&mut word, value);
            self.objects.store(&e, index, sub, u32::from_le_bytes(word));
            bytes = rest;
        }
    }
}

super::layered_over!(FixedDictionary<O>, objects);

impl<O: FixedObjects> ObjectDictionary for FixedDictionary<O> {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        Ok(self.objects.entry(index, sub)?.info())
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let e = self.objects.entry(index, sub)?;
        let bytes = e.word.to_le_bytes();
        let value = bytes.get(..usize::from(e.len)).unwrap_or(&bytes);
        Ok(super::read_at(value, offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        // Checked whole at `finish_write` (object, access, length), where
        // the value is stored whole.
        self.pending.write(index, sub, offset, data)
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let e = match self.objects.entry(index, sub) {
            Ok(e) => e,
            Err(code) => {
                self.pending.clear();
                return Err(code);
            }
        };
        let size = usize::from(e.len);
        let word = self
            .pending
            .downloaded_value(e.access, size, index, sub, len)?;
        self.objects.check(index, sub, word)?;
        self.objects.store(&e, index, sub, word);
        Ok(())
    }

    fn abort_write(&mut self, _: u16, _: u8) {
        self.pending.clear();
    }
}
