//! The device core on its [`ParameterStorage`] (feature `store`): what a
//! 1010h/1011h write does, the records loaded at boot and at the resets,
//! the LSS slave's store configuration. The rules and the record format
//! are in [`store`](super::store).

use super::store::{
    apply_app, apply_comm, encode_app, encode_comm, ParameterGroup, ParameterStorage, RecordError,
    StorageError, StorageEvent, RECORD_CAPACITY,
};
use super::{Device, DeviceEvent, DeviceSpec, PowerOnValues, Profile};
use crate::abort::AbortCode;
use crate::clock::Timestamp;
use crate::nmt::ResetKind;
use crate::od::index::STORE_PARAMETERS;
use crate::sdo::AbortOrigin;

/// What loading the stored records at a reset did: communication,
/// application.
pub(super) type StorageReport = [Option<StorageEvent>; 2];

/// The storage a device is given: the application's, for the device's
/// lifetime (a firmware's static, a leaked box).
pub(super) type Storage = Option<&'static mut dyn ParameterStorage>;

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// Gives the device its parameter storage (before [`boot`](Self::boot),
    /// which loads the stored records): 1010h and 1011h then store and
    /// restore on command, and the LSS slave's store configuration is
    /// answered through it. Without one (the default) 1010h/1011h read 0
    /// and a "save" or "load" is refused with 08000020h. Feature `store`.
    pub fn set_storage(&mut self, storage: &'static mut dyn ParameterStorage) {
        self.storage = Some(storage);
        self.mark_storable();
    }

    /// Takes the storage back (the device has none after it).
    pub fn take_storage(&mut self) -> Option<&'static mut dyn ParameterStorage> {
        let storage = self.storage.take();
        self.mark_storable();
        storage
    }

    /// Whether the device has a storage.
    #[must_use]
    pub fn has_storage(&self) -> bool {
        self.storage.is_some()
    }

    /// Tells 1010h/1011h which groups can be stored.
    pub(super) fn mark_storable(&mut self) {
        let has = self.storage.is_some();
        let fits = |b: &[u8]| b.len() <= RECORD_CAPACITY - 12;
        let app = has && S::Objects::parameter_bytes(&self.power_on).is_some_and(fits);
        self.od_mut().inner.comm.set_storable(has, app);
    }

    /// The groups 1010h/1011h sub `sub` names (sub 1: both, the
    /// application's if it can be stored).
    fn groups(&self, sub: u8) -> [Option<ParameterGroup>; 2] {
        let app = self.comm().store_capability(3) != 0;
        let app = app.then_some(ParameterGroup::Application);
        match sub {
            1 => [Some(ParameterGroup::Communication), app],
            2 => [Some(ParameterGroup::Communication), None],
            _ => [app, None],
        }
    }

    /// A "save" to 1010h or a "load" to 1011h sub `sub` (the dictionary
    /// checked the signature and the capability): stores or erases the
    /// groups. A storage that fails turns the SDO answer into 06060000h
    /// (CiA 301 sections 7.5.2.13/7.5.2.14) and is an error here.
    pub(super) fn store_command<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        profile: &mut P,
    ) -> Result<(), StorageError> {
        for group in self.groups(sub).into_iter().flatten() {
            let (result, done) = if index == STORE_PARAMETERS {
                (self.save_group(group), StorageEvent::Stored(group))
            } else {
                let erased = match self.storage.as_deref_mut() {
                    Some(storage) => storage.erase(group),
                    None => Err(StorageError::Medium),
                };
                (erased, StorageEvent::Erased(group))
            };
            if let Err(error) = result {
                let code = AbortCode::HardwareError;
                self.server.refuse_completed_download(index, sub, code);
                let failed = StorageEvent::Failed { group, error };
                self.emit(now, DeviceEvent::Storage(failed), profile);
                let origin = AbortOrigin::Local;
                let aborted = DeviceEvent::SdoAborted {
                    index,
                    sub,
                    code,
                    origin,
                };
                self.emit(now, aborted, profile);
                return Err(error);
            }
            self.emit(now, DeviceEvent::Storage(done), profile);
        }
        Ok(())
    }

    /// Stores `group`'s values as they are now.
    fn save_group(&mut self, group: ParameterGroup) -> Result<(), StorageError> {
        let mut buf = [0u8; RECORD_CAPACITY];
        let len = match group {
            ParameterGroup::Communication => encode_comm(&mut buf, self.comm(), self.pdo_config())?,
            _ => {
                let snapshot = self.objects().snapshot();
                let bytes = S::Objects::parameter_bytes(&snapshot).unwrap_or(&[]);
                encode_app(&mut buf, S::Objects::parameter_layout(), bytes)?
            }
        };
        let storage = self.storage.as_deref_mut().ok_or(StorageError::Medium)?;
        storage.save(group, buf.get(..len).unwrap_or(&[]))
    }

    /// At boot and at a reset, over the power-on values: the stored
    /// communication record, and with reset node (and boot) the
    /// application record.
    pub(super) fn load_stored(&mut self, kind: ResetKind) -> StorageReport {
        let comm = self.load_group(ParameterGroup::Communication);
        let app = if kind == ResetKind::Node {
            self.load_group(ParameterGroup::Application)
        } else {
            None
        };
        [comm, app]
    }

    /// Loads one record: nothing stored is no event; a record that is
    /// wrong is ignored, the power-on values stay.
    pub(super) fn load_group(&mut self, group: ParameterGroup) -> Option<StorageEvent> {
        let mut buf = [0u8; RECORD_CAPACITY];
        let len = match self.storage.as_deref_mut()?.load(group, &mut buf) {
            Ok(0) => return None,
            Ok(len) => len,
            Err(error) => return Some(StorageEvent::Failed { group, error }),
        };
        // A storage that claims more than the buffer holds gives an empty,
        // truncated record.
        let record = buf.get(..len).unwrap_or(&[]);
        let result = match group {
            ParameterGroup::Communication => {
                let od = self.od_mut();
                apply_comm(record, &mut od.inner.comm, &mut od.config)
            }
            _ => {
                let mut snapshot = self.objects().snapshot();
                let layout = S::Objects::parameter_layout();
                match S::Objects::parameter_bytes_mut(&mut snapshot) {
                    Some(bytes) => apply_app(record, layout, bytes)
                        .map(|()| self.od_mut().inner.app.restore(&snapshot)),
                    None => Err(RecordError::Value),
                }
            }
        };
        Some(match result {
            Ok(()) => StorageEvent::Loaded(group),
            Err(error) => StorageEvent::Ignored { group, error },
        })
    }

    /// Reports what loading the records did.
    pub(super) fn report_storage<P: Profile<S, Q, T, R>>(
        &mut self,
        now: Timestamp,
        report: StorageReport,
        profile: &mut P,
    ) {
        for event in report.into_iter().flatten() {
            self.emit(now, DeviceEvent::Storage(event), profile);
        }
    }
}

#[cfg(feature = "lss")]
mod lss {
    use super::super::store::{decode_lss, encode_lss, ParameterGroup, StorageEvent};
    use super::super::{Device, DeviceEvent, DeviceSpec, Profile};
    use super::RECORD_CAPACITY;
    use crate::clock::Timestamp;
    use crate::cob_id::NodeId;
    use crate::lss::{LssErrorCode, LssStatus};

    impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
        /// CiA 305 store configuration: the pending node-ID and bit timing
        /// stored through the device's storage and answered; without a
        /// storage the request is the application's (the LSS event).
        pub(in crate::device) fn store_lss<P: Profile<S, Q, T, R>>(
            &mut self,
            now: Timestamp,
            node: Option<NodeId>,
            bit_timing: Option<(u8, u8)>,
            profile: &mut P,
        ) {
            let Some(storage) = self.storage.as_deref_mut() else {
                return;
            };
            let mut buf = [0u8; RECORD_CAPACITY];
            let group = ParameterGroup::Lss;
            let saved = encode_lss(&mut buf, node, bit_timing)
                .and_then(|len| storage.save(group, buf.get(..len).unwrap_or(&[])));
            let (status, event) = match saved {
                Ok(()) => (LssStatus::OK, StorageEvent::Stored(group)),
                Err(error) => (
                    LssStatus::new(LssErrorCode::StorageAccess),
                    StorageEvent::Failed { group, error },
                ),
            };
            if let Some(lss) = self.lss.as_mut() {
                lss.answer_store(status);
            }
            self.emit(now, DeviceEvent::Storage(event), profile);
        }

        /// At boot: the LSS slave takes the stored node-ID and bit timing.
        pub(in crate::device) fn load_lss(&mut self) -> Option<StorageEvent> {
            self.lss.as_ref()?;
            let mut buf = [0u8; RECORD_CAPACITY];
            let group = ParameterGroup::Lss;
            let len = match self.storage.as_deref_mut()?.load(group, &mut buf) {
                Ok(0) => return None,
                Ok(len) => len,
                Err(error) => return Some(StorageEvent::Failed { group, error }),
            };
            let lss = self.lss.as_mut()?;
            Some(match decode_lss(buf.get(..len).unwrap_or(&[])) {
                Ok((node, bit_timing)) => {
                    lss.load_stored(node, bit_timing);
                    StorageEvent::Loaded(group)
                }
                Err(error) => StorageEvent::Ignored { group, error },
            })
        }
    }
}
