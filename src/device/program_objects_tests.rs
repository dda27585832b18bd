//! [`ProgramObjects`] over a RAM store: the objects, the commands, the
//! streamed image and the failures.

use super::*;
use crate::program::Crc32;

/// An application dictionary with one object, 2000h.
#[derive(Debug, Default)]
struct App;

impl ObjectDictionary for App {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        match (index, sub) {
            (0x2000, 0) => Ok(ObjectInfo::fixed(Access::ReadWrite, 1)),
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }
    fn read(&mut self, index: u16, sub: u8, _: usize, buf: &mut [u8]) -> Result<usize, AbortCode> {
        self.info(index, sub)?;
        Ok(read_at(&[7], 0, buf))
    }
    fn write(&mut self, index: u16, sub: u8, _: usize, _: &[u8]) -> Result<(), AbortCode> {
        self.info(index, sub).map(|_| ())
    }
}

/// 64 bytes of RAM "flash"; fails a write at `fail_at` if set.
struct Ram {
    image: [u8; 64],
    len: usize,
    fail_at: Option<usize>,
    started: bool,
}

impl ProgramStore for Ram {
    fn capacity(&self) -> usize {
        self.image.len()
    }
    fn software_id(&self) -> Option<u32> {
        None
    }
    fn clear(&mut self) -> Result<(), FlashError> {
        self.image = [0xFF; 64];
        Ok(())
    }
    fn write(&mut self, offset: usize, bytes: &[u8]) -> Result<(), FlashError> {
        if self.fail_at.is_some_and(|at| offset >= at) {
            return Err(FlashError::FlashWriteError);
        }
        let slot = self
            .image
            .get_mut(offset..offset + bytes.len())
            .ok_or(FlashError::GeneralAddressError)?;
        slot.copy_from_slice(bytes);
        self.len = offset + bytes.len();
        Ok(())
    }
    fn finish(&mut self, len: usize) -> Result<u32, FlashError> {
        Ok(Crc32::of(
            self.image.get(..len).ok_or(FlashError::DataFormatError)?,
        ))
    }
    fn start(&mut self) -> Result<(), FlashError> {
        self.started = true;
        Ok(())
    }
    fn stop(&mut self) -> Result<(), FlashError> {
        self.started = false;
        Ok(())
    }
}

fn with_store(fail_at: Option<usize>) -> ProgramObjects<App> {
    let mut od = ProgramObjects::new(App);
    let ram = Ram {
        image: [0; 64],
        len: 0,
        fail_at,
        started: false,
    };
    od.attach(std::boxed::Box::leak(std::boxed::Box::new(ram)));
    od
}

fn read_u32(od: &mut ProgramObjects<App>, index: u16, sub: u8) -> Result<u32, AbortCode> {
    let mut buf = [0u8; 4];
    let n = od.read(index, sub, 0, &mut buf)?;
    assert_eq!(n, od.info(index, sub)?.len);
    Ok(u32::from_le_bytes(buf))
}

fn command(od: &mut ProgramObjects<App>, value: u8) -> Result<(), AbortCode> {
    od.write(PROGRAM_CONTROL, 1, 0, &[value])?;
    od.finish_write(PROGRAM_CONTROL, 1, 1)
}

fn download(od: &mut ProgramObjects<App>, image: &[u8]) -> Result<(), AbortCode> {
    od.info(PROGRAM_DATA, 1)?.check_download_len(image.len())?;
    for (i, chunk) in image.chunks(7).enumerate() {
        if let Err(code) = od.write(PROGRAM_DATA, 1, i * 7, chunk) {
            od.abort_write(PROGRAM_DATA, 1);
            return Err(code);
        }
    }
    od.finish_write(PROGRAM_DATA, 1, image.len())
}

#[test]
fn without_a_store_the_objects_do_not_exist() {
    let mut od = ProgramObjects::new(App);
    for index in [0x1F50, 0x1F51, 0x1F56, 0x1F57] {
        assert_eq!(od.info(index, 1), Err(AbortCode::ObjectDoesNotExist));
        assert_eq!(
            read_u32(&mut od, index, 1),
            Err(AbortCode::ObjectDoesNotExist)
        );
    }
    assert_eq!(read_u32(&mut od, 0x2000, 0), Ok(7));
}

#[test]
fn objects_and_sub_indices() {
    let mut od = with_store(None);
    for index in [0x1F50, 0x1F51, 0x1F56, 0x1F57] {
        assert_eq!(od.info(index, 0), Ok(ObjectInfo::fixed(Access::Const, 1)));
        assert_eq!(read_u32(&mut od, index, 0), Ok(1));
        assert_eq!(od.info(index, 2), Err(AbortCode::SubIndexDoesNotExist));
        assert_eq!(
            od.write(index, 0, 0, &[2]),
            Err(AbortCode::WriteOfReadOnlyObject)
        );
    }
    let data = od.info(0x1F50, 1).unwrap();
    assert_eq!(
        (data.access, data.size),
        (Access::WriteOnly, SizeRule::Variable { max: 64 })
    );
    assert_eq!(
        read_u32(&mut od, 0x1F50, 1),
        Err(AbortCode::ReadOfWriteOnlyObject)
    );
    assert_eq!(
        od.write(0x1F56, 1, 0, &[0; 4]),
        Err(AbortCode::WriteOfReadOnlyObject)
    );
    // The application's objects are still there.
    assert_eq!(read_u32(&mut od, 0x2000, 0), Ok(7));
    // No program at power-on: "no program available", "no valid program".
    assert_eq!(read_u32(&mut od, 0x1F51, 1), Ok(3));
    assert_eq!(read_u32(&mut od, 0x1F56, 1), Ok(0));
    assert_eq!(read_u32(&mut od, 0x1F57, 1), Ok(1 << 1));
}

#[test]
fn the_whole_sequence() {
    let mut od = with_store(None);
    let image: [u8; 40] = core::array::from_fn(|i| i as u8 * 3);
    command(&mut od, 0).unwrap();
    command(&mut od, 3).unwrap();
    assert_eq!(read_u32(&mut od, 0x1F57, 1), Ok(0));
    od.write(PROGRAM_DATA, 1, 0, &image[..7]).unwrap();
    // In progress while the segments arrive.
    assert_eq!(read_u32(&mut od, 0x1F57, 1), Ok(1));
    od.abort_write(PROGRAM_DATA, 1);
    assert_eq!(od.status().error(), Some(FlashError::NoValidProgram));
    download(&mut od, &image).unwrap();
    assert_eq!(read_u32(&mut od, 0x1F57, 1), Ok(0));
    assert_eq!(read_u32(&mut od, 0x1F56, 1), Ok(Crc32::of(&image)));
    command(&mut od, 1).unwrap();
    assert_eq!(od.state(), ProgramState::Started);
    assert_eq!(read_u32(&mut od, 0x1F51, 1), Ok(1));
    // Started: no download, no clear.
    assert_eq!(
        od.info(0x1F50, 1),
        Err(AbortCode::DataCannotBeStoredDeviceState)
    );
    assert_eq!(
        command(&mut od, 3),
        Err(AbortCode::DataCannotBeStoredDeviceState)
    );
    command(&mut od, 2).unwrap();
    assert_eq!(od.state(), ProgramState::Started);
    assert_eq!(command(&mut od, 4), Err(AbortCode::InvalidValue));
    command(&mut od, 0).unwrap();
    assert_eq!(read_u32(&mut od, 0x1F51, 1), Ok(0));
    command(&mut od, 3).unwrap();
    assert_eq!(read_u32(&mut od, 0x1F51, 1), Ok(3));
}

#[test]
fn start_without_a_program_is_refused() {
    let mut od = with_store(None);
    assert_eq!(
        command(&mut od, 1),
        Err(AbortCode::DataCannotBeStoredDeviceState)
    );
    assert_eq!(od.status().error(), Some(FlashError::NoValidProgram));
    assert_eq!(od.state(), ProgramState::NoProgram);
    download(&mut od, b"ok").unwrap();
    command(&mut od, 3).unwrap();
    assert_eq!(od.software_id(), None);
    assert_eq!(
        command(&mut od, 2),
        Err(AbortCode::DataCannotBeStoredDeviceState)
    );
}

#[test]
fn a_failing_store_is_in_the_flash_status() {
    let mut od = with_store(Some(14));
    let image = [0x55u8; 30];
    assert_eq!(
        download(&mut od, &image),
        Err(AbortCode::DataCannotBeStored)
    );
    let status = FlashStatus::from_raw(read_u32(&mut od, 0x1F57, 1).unwrap());
    assert_eq!(
        (status.in_progress(), status.error()),
        (false, Some(FlashError::FlashWriteError))
    );
    assert_eq!(read_u32(&mut od, 0x1F56, 1), Ok(0));
    // Too long for the store: refused by its size rule.
    assert_eq!(
        download(&mut od, &[0; 65]),
        Err(AbortCode::DataTypeLengthTooHigh)
    );
}

#[test]
fn a_control_value_of_the_wrong_length_is_refused() {
    let mut od = with_store(None);
    assert_eq!(
        od.write(PROGRAM_CONTROL, 1, 0, &[1, 0]),
        Err(AbortCode::DataTypeLengthMismatch)
    );
    assert_eq!(
        od.finish_write(PROGRAM_CONTROL, 1, 0),
        Err(AbortCode::DataTypeLengthTooLow)
    );
}
