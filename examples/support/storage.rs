//! `--storage FILE` of the example programs: a [`ParameterStorage`] in a
//! file, so that 1010h "save" (and the LSS store configuration) survive a
//! restart of the program with the same file, and 1011h "load" erases.
//!
//! The file holds the device's records one after the other, each as its
//! group number (1 communication, 2 application, 3 LSS), its length (U16,
//! little-endian) and the record (whose own format, checksum included, is
//! the library's: `canopen_codec::device::store`). It is rewritten whole
//! (a temporary file renamed over it) on every save and erase. A file that
//! ends inside an entry keeps the entries before it; a record the device
//! finds wrong is ignored by the device, with an event.
#![allow(dead_code)]

use std::fs;
use std::io;
use std::path::PathBuf;

use canopen_codec::device::{ParameterGroup, ParameterStorage, StorageError};

/// The records of a device in one file.
#[derive(Debug)]
pub struct FileStorage {
    path: PathBuf,
    /// Communication, application, LSS (empty: none).
    records: [Vec<u8>; 3],
}

fn slot(group: ParameterGroup) -> usize {
    usize::from(group.raw().saturating_sub(1)).min(2)
}

impl FileStorage {
    /// The storage in `path`: its records if the file exists, none if not.
    pub fn open(path: impl Into<PathBuf>) -> io::Result<Self> {
        let path = path.into();
        let mut records: [Vec<u8>; 3] = Default::default();
        match fs::read(&path) {
            Ok(bytes) => {
                let mut rest = bytes.as_slice();
                while let [group, lo, hi, tail @ ..] = rest {
                    let len = usize::from(u16::from_le_bytes([*lo, *hi]));
                    let Some(record) = tail.get(..len) else { break };
                    if let Some(r) = records.get_mut(usize::from(group.saturating_sub(1))) {
                        *r = record.to_vec();
                    }
                    rest = tail.get(len..).unwrap_or(&[]);
                }
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
        Ok(FileStorage { path, records })
    }

    /// [`open`](Self::open), for the device's lifetime (the program's).
    pub fn open_for_device(path: &str) -> Result<&'static mut Self, String> {
        Self::open(path)
            .map(|s| Box::leak(Box::new(s)))
            .map_err(|e| format!("--storage {path}: {e}"))
    }

    fn write(&self) -> Result<(), StorageError> {
        let mut bytes = Vec::new();
        for (i, record) in self.records.iter().enumerate() {
            if record.is_empty() {
                continue;
            }
            let len = u16::try_from(record.len()).map_err(|_| StorageError::Medium)?;
            bytes.push(i as u8 + 1);
            bytes.extend_from_slice(&len.to_le_bytes());
            bytes.extend_from_slice(record);
        }
        let mut tmp = self.path.clone().into_os_string();
        tmp.push(".tmp");
        fs::write(&tmp, &bytes)
            .and_then(|()| fs::rename(&tmp, &self.path))
            .map_err(|e| {
                eprintln!("storage: {}: {e}", self.path.display());
                StorageError::Medium
            })
    }
}

impl ParameterStorage for FileStorage {
    fn save(&mut self, group: ParameterGroup, record: &[u8]) -> Result<(), StorageError> {
        self.records[slot(group)] = record.to_vec();
        self.write()
    }

    fn load(&mut self, group: ParameterGroup, buf: &mut [u8]) -> Result<usize, StorageError> {
        let record = &self.records[slot(group)];
        let room = buf.len();
        let dst = buf.get_mut(..record.len()).ok_or(StorageError::NoRoom {
            need: record.len(),
            room,
        })?;
        dst.copy_from_slice(record);
        Ok(record.len())
    }

    fn erase(&mut self, group: ParameterGroup) -> Result<(), StorageError> {
        self.records[slot(group)].clear();
        self.write()
    }
}
