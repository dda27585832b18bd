//! A [`ProgramStore`] on a file: what a program download into the virtual
//! charger writes (CiA 302-3 1F50h sub 1), so a real tool's download can be
//! checked byte for byte. Its software identification (1F56h) is the
//! CRC-32 (zlib's) of the file.
#![allow(dead_code)]

use std::fs::{File, OpenOptions};
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use canopen_codec::device::program::{Crc32, FlashError, ProgramStore};

/// The largest image taken: 1 MiB.
pub const CAPACITY: usize = 1 << 20;

/// The program image in `path` (a directory gets `program-1.bin` in it).
#[derive(Debug)]
pub struct FileProgramStore {
    path: PathBuf,
    file: Option<File>,
}

impl FileProgramStore {
    /// The store at `path`: an existing directory holds `program-1.bin`;
    /// any other path is the image file itself.
    pub fn new(path: &Path) -> Self {
        let path = if path.is_dir() {
            path.join("program-1.bin")
        } else {
            path.to_path_buf()
        };
        FileProgramStore { path, file: None }
    }

    /// Where the image is written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn open(&mut self) -> Result<&mut File, FlashError> {
        if self.file.is_none() {
            let file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&self.path)
                .map_err(|_| FlashError::GeneralAddressError)?;
            self.file = Some(file);
        }
        self.file.as_mut().ok_or(FlashError::GeneralAddressError)
    }
}

impl ProgramStore for FileProgramStore {
    fn capacity(&self) -> usize {
        CAPACITY
    }

    fn software_id(&self) -> Option<u32> {
        std::fs::read(&self.path)
            .ok()
            .map(|image| Crc32::of(&image))
    }

    fn clear(&mut self) -> Result<(), FlashError> {
        self.open()?
            .set_len(0)
            .map_err(|_| FlashError::FlashWriteError)?;
        eprintln!("program store: {} cleared", self.path.display());
        Ok(())
    }

    fn write(&mut self, offset: usize, bytes: &[u8]) -> Result<(), FlashError> {
        let file = self.open()?;
        file.seek(SeekFrom::Start(offset as u64))
            .and_then(|_| file.write_all(bytes))
            .map_err(|_| FlashError::FlashWriteError)
    }

    fn finish(&mut self, len: usize) -> Result<u32, FlashError> {
        let file = self.open()?;
        file.set_len(len as u64)
            .and_then(|()| file.flush())
            .map_err(|_| FlashError::FlashWriteError)?;
        let image = std::fs::read(&self.path).map_err(|_| FlashError::FlashWriteError)?;
        if image.len() != len {
            return Err(FlashError::DataFormatError);
        }
        let id = Crc32::of(&image);
        eprintln!(
            "program store: {} bytes written to {}, CRC-32 {id:08X}h",
            len,
            self.path.display()
        );
        Ok(id)
    }

    fn start(&mut self) -> Result<(), FlashError> {
        eprintln!("program store: program started");
        Ok(())
    }

    fn stop(&mut self) -> Result<(), FlashError> {
        eprintln!("program store: program stopped");
        Ok(())
    }
}
