//! [`ProgramObjects`]: an application dictionary with the program download
//! objects of CiA 302-3 (1F50h, 1F51h, 1F56h, 1F57h; see
//! [`program`](crate::program)) in front, served over the application's
//! [`ProgramStore`] (feature `program-download`).
//!
//! The image is streamed, not buffered: every SDO segment of a download
//! into 1F50h sub 1 goes to [`ProgramStore::write`] at its offset, and the
//! end of the transfer to [`ProgramStore::finish`].
//!
//! **Choices** (CiA 302-3 leaves them to the device):
//!
//! - 1F51h commands act at once (the store is synchronous): a read gives
//!   1 (started), 0 (stopped with a valid program) or 3 (stopped, no
//!   program available: none at power-on, cleared, or a download that
//!   failed or is in progress).
//! - Start (1) and reset (2) need a valid program (one the store had at
//!   power-on, or a download that finished): without one they are aborted
//!   with 08000022h and 1F57h says "no valid program" (1). Clear (3) is
//!   accepted only while stopped (08000022h otherwise). Any other value is
//!   06090030h.
//! - A store that fails (write, finish, clear, start) aborts the transfer
//!   with 08000020h "data cannot be transferred or stored to the
//!   application"; 1F57h holds its [`FlashError`]. A download aborted
//!   half-way leaves "no valid program" unless the store reported its own
//!   error.
//! - A download starts by clearing 1F56h (0, no valid program) and setting
//!   the in-progress bit of 1F57h; 1F56h is the store's identification
//!   once [`ProgramStore::finish`] accepts the image.
//! - NMT resets leave the program state alone: it is the application's,
//!   not a communication parameter.

use super::PowerOnValues;
use crate::abort::AbortCode;
use crate::od::{read_at, Access, ObjectDictionary, ObjectInfo, SizeRule};
use crate::program::{
    FlashError, FlashStatus, ProgramCommand, ProgramState, ProgramStore,
    FLASH_STATUS_IDENTIFICATION, PROGRAM_1, PROGRAM_CONTROL, PROGRAM_DATA,
    PROGRAM_SOFTWARE_IDENTIFICATION,
};

/// The store a device serves its program download objects over: owned by
/// the application for the life of the program (a firmware's static, a
/// leaked `Box`).
pub type ProgramStoreRef = &'static mut (dyn ProgramStore + Send);

/// The application's dictionary `A` with the program download objects in
/// front: with a store attached ([`attach`](Self::attach)) 1F50h, 1F51h,
/// 1F56h and 1F57h are served over it; without one they are `A`'s (which
/// normally does not have them: 06020000h). It dereferences to `A`, so the
/// application's getters and fields read as before.
///
/// ```
/// # #[cfg(feature = "alloc")] {
/// use canopen_codec::program::{FlashError, ProgramStore};
/// use canopen_codec::device::ProgramObjects;
/// use canopen_codec::od::{MemoryDictionary, ObjectDictionary};
/// use canopen_codec::sdo::AbortCode;
///
/// /// 16 bytes of "flash".
/// #[derive(Default)]
/// struct Flash([u8; 16]);
/// impl ProgramStore for Flash {
///     fn capacity(&self) -> usize { 16 }
///     fn software_id(&self) -> Option<u32> { None }
///     fn clear(&mut self) -> Result<(), FlashError> { self.0 = [0xFF; 16]; Ok(()) }
///     fn write(&mut self, offset: usize, bytes: &[u8]) -> Result<(), FlashError> {
///         let end = offset + bytes.len();
///         self.0.get_mut(offset..end).ok_or(FlashError::GeneralAddressError)?.copy_from_slice(bytes);
///         Ok(())
///     }
///     fn finish(&mut self, len: usize) -> Result<u32, FlashError> { Ok(len as u32) }
///     fn start(&mut self) -> Result<(), FlashError> { Ok(()) }
/// }
///
/// let mut od = ProgramObjects::new(MemoryDictionary::new());
/// assert_eq!(od.info(0x1F50, 1), Err(AbortCode::ObjectDoesNotExist));
/// od.attach(Box::leak(Box::new(Flash::default())));
/// od.write(0x1F50, 1, 0, b"abc").unwrap();
/// od.finish_write(0x1F50, 1, 3).unwrap();
/// assert_eq!(od.software_id(), Some(3));
/// # }
/// ```
pub struct ProgramObjects<A> {
    app: A,
    store: Option<ProgramStoreRef>,
    state: ProgramState,
    /// 1F56h: `Some` while the program in flash is valid.
    software_id: Option<u32>,
    status: FlashStatus,
    /// The 1F51h value being written (one byte).
    command: Option<u8>,
}

impl<A: core::fmt::Debug> core::fmt::Debug for ProgramObjects<A> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ProgramObjects")
            .field("app", &self.app)
            .field("store", &self.store.is_some())
            .field("state", &self.state)
            .field("software_id", &self.software_id)
            .field("status", &self.status)
            .finish()
    }
}

/// A copy of the application's objects and of the program's state,
/// without the store (it is the application's, exclusively): the copy
/// serves no program download objects (e.g. for an EDS of the other
/// objects).
impl<A: Clone> Clone for ProgramObjects<A> {
    fn clone(&self) -> Self {
        ProgramObjects {
            store: None,
            app: self.app.clone(),
            ..*self
        }
    }
}

impl<A: Default> Default for ProgramObjects<A> {
    fn default() -> Self {
        Self::new(A::default())
    }
}

crate::od::layered_over!(ProgramObjects<A>, app);

impl<A> ProgramObjects<A> {
    /// `app` with no store: no program download objects.
    #[must_use]
    pub const fn new(app: A) -> Self {
        ProgramObjects {
            app,
            store: None,
            state: ProgramState::Stopped,
            software_id: None,
            status: FlashStatus::OK,
            command: None,
        }
    }

    /// Serves the program download objects over `store` from now on: the
    /// program is stopped, 1F56h is the store's
    /// [`software_id`](ProgramStore::software_id), 1F57h "no error" (or
    /// "no valid program" when it has none).
    pub fn attach(&mut self, store: ProgramStoreRef) {
        self.software_id = store.software_id();
        self.status = if self.software_id.is_some() {
            FlashStatus::OK
        } else {
            FlashStatus::new(false, Some(FlashError::NoValidProgram))
        };
        self.state = ProgramState::Stopped;
        self.command = None;
        self.store = Some(store);
    }

    /// True with a store attached.
    #[must_use]
    pub const fn has_store(&self) -> bool {
        self.store.is_some()
    }

    /// 1F51h: the program's state (stopped without a valid program is
    /// [`ProgramState::NoProgram`]).
    #[must_use]
    pub const fn state(&self) -> ProgramState {
        match (self.state, self.software_id) {
            (ProgramState::Stopped, None) => ProgramState::NoProgram,
            (state, _) => state,
        }
    }

    /// 1F56h: the software identification of the valid program, if any.
    #[must_use]
    pub const fn software_id(&self) -> Option<u32> {
        self.software_id
    }

    /// 1F57h: the flash status.
    #[must_use]
    pub const fn status(&self) -> FlashStatus {
        self.status
    }

    /// The application's dictionary.
    #[must_use]
    pub const fn app(&self) -> &A {
        &self.app
    }

    /// The store, when `index`/`sub` is one of the program objects it
    /// serves, with its entry; `None` for every other object (they are
    /// `A`'s). An error is the abort for a program object.
    fn program_entry(&self, index: u16, sub: u8) -> Option<Result<ObjectInfo, AbortCode>> {
        let store = self.store.as_ref()?;
        let u32_ro = ObjectInfo::fixed(Access::ReadOnly, 4);
        let entry = match (index, sub) {
            (
                PROGRAM_DATA
                | PROGRAM_CONTROL
                | PROGRAM_SOFTWARE_IDENTIFICATION
                | FLASH_STATUS_IDENTIFICATION,
                0,
            ) => Ok(ObjectInfo::fixed(Access::Const, 1)),
            // CiA 302-3: a download only while the program is stopped.
            (PROGRAM_DATA, PROGRAM_1) if self.state != ProgramState::Stopped => {
                Err(AbortCode::DataCannotBeStoredDeviceState)
            }
            (PROGRAM_DATA, PROGRAM_1) => Ok(ObjectInfo {
                access: Access::WriteOnly,
                len: 0,
                size: SizeRule::Variable {
                    max: store.capacity(),
                },
                pdo_mappable: false,
            }),
            (PROGRAM_CONTROL, PROGRAM_1) => Ok(ObjectInfo::fixed(Access::ReadWrite, 1)),
            (PROGRAM_SOFTWARE_IDENTIFICATION | FLASH_STATUS_IDENTIFICATION, PROGRAM_1) => {
                Ok(u32_ro)
            }
            (
                PROGRAM_DATA
                | PROGRAM_CONTROL
                | PROGRAM_SOFTWARE_IDENTIFICATION
                | FLASH_STATUS_IDENTIFICATION,
                _,
            ) => Err(AbortCode::SubIndexDoesNotExist),
            _ => return None,
        };
        Some(entry)
    }

    /// Records a store's failure in 1F57h: the abort for the transfer.
    fn failed(&mut self, error: FlashError) -> AbortCode {
        self.status = FlashStatus::new(false, Some(error));
        AbortCode::DataCannotBeStored
    }

    /// A 1F51h command, written whole.
    fn control(&mut self, command: ProgramCommand) -> Result<(), AbortCode> {
        let Some(store) = self.store.as_mut() else {
            return Err(AbortCode::ObjectDoesNotExist);
        };
        let valid = self.software_id.is_some();
        let result = match command {
            ProgramCommand::Stop => store.stop().map(|()| ProgramState::Stopped),
            ProgramCommand::Start | ProgramCommand::Reset if !valid => {
                self.status = FlashStatus::new(false, Some(FlashError::NoValidProgram));
                return Err(AbortCode::DataCannotBeStoredDeviceState);
            }
            // Starting a started program changes nothing.
            ProgramCommand::Start if self.state == ProgramState::Started => return Ok(()),
            ProgramCommand::Start => store.start().map(|()| ProgramState::Started),
            ProgramCommand::Reset => store.reset().map(|()| ProgramState::Started),
            ProgramCommand::Clear if self.state != ProgramState::Stopped => {
                return Err(AbortCode::DataCannotBeStoredDeviceState);
            }
            ProgramCommand::Clear => {
                self.software_id = None;
                store.clear().map(|()| ProgramState::Stopped)
            }
            ProgramCommand::Unknown(_) => return Err(AbortCode::InvalidValue),
        };
        match result {
            Ok(state) => {
                self.state = state;
                if command == ProgramCommand::Clear {
                    self.status = FlashStatus::OK;
                }
                Ok(())
            }
            Err(e) => Err(self.failed(e)),
        }
    }
}

impl<A: ObjectDictionary> ObjectDictionary for ProgramObjects<A> {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        match self.program_entry(index, sub) {
            Some(entry) => entry,
            None => self.app.info(index, sub),
        }
    }

    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let Some(entry) = self.program_entry(index, sub) else {
            return self.app.read(index, sub, offset, buf);
        };
        if !entry?.access.is_readable() {
            return Err(AbortCode::ReadOfWriteOnlyObject);
        }
        let word: u32 = match (index, sub) {
            (_, 0) => 1,
            (PROGRAM_CONTROL, _) => u8::from(self.state()).into(),
            (PROGRAM_SOFTWARE_IDENTIFICATION, _) => self.software_id.unwrap_or(0),
            _ => self.status.raw(),
        };
        let bytes = word.to_le_bytes();
        let len = if index == PROGRAM_CONTROL || sub == 0 {
            1
        } else {
            4
        };
        Ok(read_at(bytes.get(..len).unwrap_or(&[]), offset, buf))
    }

    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let Some(entry) = self.program_entry(index, sub) else {
            return self.app.write(index, sub, offset, data);
        };
        if !entry?.access.is_writable() {
            return Err(AbortCode::WriteOfReadOnlyObject);
        }
        if index == PROGRAM_CONTROL {
            self.command = match (offset, data) {
                (0, [value]) => Some(*value),
                _ => return Err(AbortCode::DataTypeLengthMismatch),
            };
            return Ok(());
        }
        if offset == 0 {
            // A new image: the old one is gone.
            self.software_id = None;
            self.status = FlashStatus::new(true, None);
        }
        let Some(store) = self.store.as_mut() else {
            return Err(AbortCode::ObjectDoesNotExist);
        };
        store.write(offset, data).map_err(|e| self.failed(e))
    }

    fn finish_write(&mut self, index: u16, sub: u8, len: usize) -> Result<(), AbortCode> {
        let Some(entry) = self.program_entry(index, sub) else {
            return self.app.finish_write(index, sub, len);
        };
        entry?;
        if index == PROGRAM_CONTROL {
            let command = self.command.take().ok_or(AbortCode::DataTypeLengthTooLow)?;
            return self.control(command.into());
        }
        if len == 0 {
            // An empty image: no write was made.
            self.software_id = None;
        }
        let Some(store) = self.store.as_mut() else {
            return Err(AbortCode::ObjectDoesNotExist);
        };
        match store.finish(len) {
            Ok(id) => {
                self.software_id = Some(id);
                self.status = FlashStatus::OK;
                Ok(())
            }
            Err(e) => Err(self.failed(e)),
        }
    }

    fn abort_write(&mut self, index: u16, sub: u8) {
        if self.program_entry(index, sub).is_none() {
            return self.app.abort_write(index, sub);
        }
        self.command = None;
        if index == PROGRAM_DATA {
            // Half an image is no program (a store's own error stays).
            self.software_id = None;
            if self.status.error().is_none() {
                self.status = FlashStatus::new(false, Some(FlashError::NoValidProgram));
            } else {
                self.status = FlashStatus::from_raw(self.status.raw() & !1);
            }
        }
    }
}

/// Reset node restores `A`'s power-on values; the program state is not a
/// parameter and stays.
impl<A: PowerOnValues> PowerOnValues for ProgramObjects<A> {
    type Snapshot = A::Snapshot;

    fn snapshot(&self) -> A::Snapshot {
        self.app.snapshot()
    }

    fn restore(&mut self, snapshot: &A::Snapshot) {
        self.app.restore(snapshot);
    }
}

#[cfg(test)]
#[path = "program_objects_tests.rs"]
mod tests;
