//! Program download (CiA 302-3 "CANopen additional application layer
//! functions, part 3: configuration and program download", the program
//! download objects): what the bus says and the [`ProgramStore`] the
//! application implements over its flash.
//!
//! CiA 302-3 is not part of this repository; these are its public,
//! well-known definitions (the objects as CANopen masters and bootloaders
//! use them), and the choices made where they leave room are marked
//! **Choice**.
//!
//! | object | type | what |
//! |---|---|---|
//! | 1F50h sub 1 | DOMAIN, wo | program data: the image, downloaded segmented or by block |
//! | 1F51h sub 1 | U8, rw | program control: write a [`ProgramCommand`] (0 stop, 1 start, 2 reset, 3 clear), read the [`ProgramState`] (0 stopped, 1 started, 3 no program available) |
//! | 1F56h sub 1 | U32, ro | program software identification (here the store's ident of the image, e.g. its CRC-32) |
//! | 1F57h sub 1 | U32, ro | flash status identification ([`FlashStatus`]) |
//!
//! Sub 0 of each is the number of programs, `const` 1. A download into
//! 1F50h is accepted only while the program is stopped; otherwise the
//! initiate is aborted with 08000022h ("data cannot be transferred or
//! stored to the application because of the present device state").
//!
//! The 1F57h word ([`FlashStatus`]):
//!
//! | bits | meaning |
//! |---|---|
//! | 0 | 1: a download (or a clear) is in progress |
//! | 1-7 | error code ([`FlashError::code`]): 0 no error, 1 no valid program, 2 data format unknown, 3 data format error or CRC error, 4 flash not cleared before write, 5 flash write error, 6 general address error, 7 flash secured (write access currently forbidden), 8-63 reserved, 64-127 manufacturer-specific |
//! | 8-31 | manufacturer-specific (kept, not interpreted) |
//!
//! A leaf below the SDO layer and the device core, which both use it:
//! the objects are served by [`ProgramObjects`](crate::device::ProgramObjects)
//! (feature `program-download`) in front of an application dictionary; a
//! master drives the sequence with
//! [`sdo::ProgramDownload`](crate::sdo::ProgramDownload).

/// 1F50h program data (DOMAIN per program).
pub const PROGRAM_DATA: u16 = 0x1F50;
/// 1F51h program control (U8 per program).
pub const PROGRAM_CONTROL: u16 = 0x1F51;
/// 1F56h program software identification (U32 per program).
pub const PROGRAM_SOFTWARE_IDENTIFICATION: u16 = 0x1F56;
/// 1F57h flash status identification (U32 per program).
pub const FLASH_STATUS_IDENTIFICATION: u16 = 0x1F57;
/// The sub-index of program 1, the one program a
/// [`ProgramObjects`](crate::device::ProgramObjects) serves.
pub const PROGRAM_1: u8 = 1;

/// What a [`ProgramStore`] reports when an operation on its flash fails:
/// the error field of 1F57h (bits 1-7, CiA 302-3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum FlashError {
    /// 1: no valid program.
    #[error("no valid program")]
    NoValidProgram,
    /// 2: data format unknown.
    #[error("data format unknown")]
    DataFormatUnknown,
    /// 3: data format error or data CRC error.
    #[error("data format error or CRC error")]
    DataFormatError,
    /// 4: flash not cleared before write.
    #[error("flash not cleared before write")]
    FlashNotCleared,
    /// 5: flash write error.
    #[error("flash write error")]
    FlashWriteError,
    /// 6: general address error.
    #[error("general address error")]
    GeneralAddressError,
    /// 7: flash secured (write access currently forbidden).
    #[error("flash secured")]
    FlashSecured,
    /// Any other code 8..=127 (8-63 reserved, 64-127 manufacturer-specific).
    #[error("flash error code {0}")]
    Other(u8),
}

impl FlashError {
    /// The 7-bit code of bits 1-7 of 1F57h (an `Other` code above 127 is
    /// cut to 7 bits).
    #[must_use]
    pub const fn code(self) -> u8 {
        match self {
            FlashError::NoValidProgram => 1,
            FlashError::DataFormatUnknown => 2,
            FlashError::DataFormatError => 3,
            FlashError::FlashNotCleared => 4,
            FlashError::FlashWriteError => 5,
            FlashError::GeneralAddressError => 6,
            FlashError::FlashSecured => 7,
            FlashError::Other(code) => code & 0x7F,
        }
    }

    /// The error of a 7-bit code; 0 (no error) is `None`.
    #[must_use]
    pub const fn from_code(code: u8) -> Option<Self> {
        Some(match code & 0x7F {
            0 => return None,
            1 => FlashError::NoValidProgram,
            2 => FlashError::DataFormatUnknown,
            3 => FlashError::DataFormatError,
            4 => FlashError::FlashNotCleared,
            5 => FlashError::FlashWriteError,
            6 => FlashError::GeneralAddressError,
            7 => FlashError::FlashSecured,
            other => FlashError::Other(other),
        })
    }
}

/// The 1F57h flash status identification word (see the module docs for
/// the bits). Lossless: every bit of the raw word is kept.
///
/// ```
/// use canopen_codec::program::{FlashError, FlashStatus};
/// let s = FlashStatus::from_raw(0x0000_000A);
/// assert_eq!((s.in_progress(), s.error()), (false, Some(FlashError::FlashWriteError)));
/// assert_eq!(FlashStatus::new(true, None).raw(), 1);
/// assert!(FlashStatus::OK.is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct FlashStatus(u32);

impl FlashStatus {
    /// No download in progress, no error.
    pub const OK: Self = FlashStatus(0);

    /// The word of a status: `in_progress` (bit 0) and `error` (bits 1-7).
    #[must_use]
    pub const fn new(in_progress: bool, error: Option<FlashError>) -> Self {
        let code = match error {
            Some(e) => e.code() as u32,
            None => 0,
        };
        FlashStatus(code << 1 | in_progress as u32)
    }

    /// The status of a raw 1F57h value.
    #[must_use]
    pub const fn from_raw(raw: u32) -> Self {
        FlashStatus(raw)
    }

    /// The raw 1F57h value.
    #[must_use]
    pub const fn raw(self) -> u32 {
        self.0
    }

    /// Bit 0: a download or clear is in progress.
    #[must_use]
    pub const fn in_progress(self) -> bool {
        self.0 & 1 != 0
    }

    /// Bits 1-7: the error, `None` for 0 (no error).
    #[must_use]
    pub const fn error(self) -> Option<FlashError> {
        FlashError::from_code((self.0 >> 1) as u8)
    }

    /// Bits 8-31, manufacturer-specific.
    #[must_use]
    pub const fn manufacturer(self) -> u32 {
        self.0 >> 8
    }

    /// Not in progress and no error: the program in flash is complete.
    #[must_use]
    pub const fn is_ok(self) -> bool {
        self.0 & 0xFF == 0
    }
}

/// A 1F51h program control command (the value written).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ProgramCommand {
    /// 0: stop the program.
    Stop,
    /// 1: start the program.
    Start,
    /// 2: reset the program (stop, then start).
    Reset,
    /// 3: clear the program (erase its flash).
    Clear,
    /// Any other value (refused by the device with 06090030h).
    Unknown(u8),
}

impl From<u8> for ProgramCommand {
    fn from(raw: u8) -> Self {
        match raw {
            0 => ProgramCommand::Stop,
            1 => ProgramCommand::Start,
            2 => ProgramCommand::Reset,
            3 => ProgramCommand::Clear,
            other => ProgramCommand::Unknown(other),
        }
    }
}

impl From<ProgramCommand> for u8 {
    fn from(c: ProgramCommand) -> Self {
        match c {
            ProgramCommand::Stop => 0,
            ProgramCommand::Start => 1,
            ProgramCommand::Reset => 2,
            ProgramCommand::Clear => 3,
            ProgramCommand::Unknown(raw) => raw,
        }
    }
}

impl ProgramCommand {
    /// The command in words ("stop program", ...).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ProgramCommand::Stop => "stop program",
            ProgramCommand::Start => "start program",
            ProgramCommand::Reset => "reset program",
            ProgramCommand::Clear => "clear program",
            ProgramCommand::Unknown(_) => "unknown program command",
        }
    }
}

/// The 1F51h program state (the value read; CiA 302-3 gives each value a
/// command and a state: 0 stop / stopped, 1 start / started, 3 clear / no
/// program available).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ProgramState {
    /// 0: program stopped.
    Stopped,
    /// 1: program started.
    Started,
    /// 3: no program available (stopped, nothing valid in flash).
    NoProgram,
    /// Any other value (2, the reset command, is no state).
    Unknown(u8),
}

impl From<u8> for ProgramState {
    fn from(raw: u8) -> Self {
        match raw {
            0 => ProgramState::Stopped,
            1 => ProgramState::Started,
            3 => ProgramState::NoProgram,
            other => ProgramState::Unknown(other),
        }
    }
}

impl From<ProgramState> for u8 {
    fn from(s: ProgramState) -> Self {
        match s {
            ProgramState::Stopped => 0,
            ProgramState::Started => 1,
            ProgramState::NoProgram => 3,
            ProgramState::Unknown(raw) => raw,
        }
    }
}

impl ProgramState {
    /// The state in words ("program stopped", ...).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ProgramState::Stopped => "program stopped",
            ProgramState::Started => "program started",
            ProgramState::NoProgram => "no program available",
            ProgramState::Unknown(_) => "unknown program state",
        }
    }
}

/// Where a downloaded program goes: the application's flash (or a file,
/// or memory). The device calls it from the SDO transfers on 1F50h and
/// the commands on 1F51h, synchronously; every error is a [`FlashError`],
/// which 1F57h then shows. No allocation is asked of it.
///
/// The write protocol: [`write`](Self::write) with increasing offsets
/// (one call per SDO segment, 7 bytes at most), then
/// [`finish`](Self::finish) with the total length, which checks the image
/// and returns its software identification (1F56h). A transfer aborted
/// half-way calls neither; the image is then not valid until the next
/// complete download.
pub trait ProgramStore {
    /// The largest image it takes (a longer download is refused at its
    /// initiate with 06070012h).
    fn capacity(&self) -> usize;

    /// The software identification of the program already in flash at
    /// power-on, `None` if there is no valid one.
    fn software_id(&self) -> Option<u32>;

    /// Erases the program (1F51h = 3).
    fn clear(&mut self) -> Result<(), FlashError>;

    /// Writes `bytes` at `offset` of the image.
    fn write(&mut self, offset: usize, bytes: &[u8]) -> Result<(), FlashError>;

    /// The image is complete with `len` bytes: checks it and returns its
    /// software identification (e.g. its [`Crc32`]).
    fn finish(&mut self, len: usize) -> Result<u32, FlashError>;

    /// Starts the program (1F51h = 1; called only with a valid program).
    fn start(&mut self) -> Result<(), FlashError>;

    /// Stops the program (1F51h = 0). Default: nothing to do.
    fn stop(&mut self) -> Result<(), FlashError> {
        Ok(())
    }

    /// Resets the program (1F51h = 2). Default: [`stop`](Self::stop),
    /// then [`start`](Self::start).
    fn reset(&mut self) -> Result<(), FlashError> {
        self.stop()?;
        self.start()
    }
}

/// CRC-32 (IEEE 802.3: polynomial 04C11DB7h reflected, initial value and
/// final XOR FFFFFFFFh; the one of zlib and Ethernet), fed in pieces: a
/// [`ProgramStore`]'s natural software identification of an image, which
/// any tool can recompute.
///
/// ```
/// use canopen_codec::program::Crc32;
/// let mut crc = Crc32::new();
/// crc.update(b"1234");
/// crc.update(b"56789");
/// assert_eq!(crc.value(), 0xCBF4_3926);
/// assert_eq!(Crc32::of(b""), 0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Crc32(u32);

impl Default for Crc32 {
    fn default() -> Self {
        Self::new()
    }
}

impl Crc32 {
    /// A CRC over no bytes yet.
    #[must_use]
    pub const fn new() -> Self {
        Crc32(u32::MAX)
    }

    /// Continues over `bytes` (bit by bit: no table in flash).
    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u32::from(b);
            for _ in 0..8 {
                let mask = (self.0 & 1).wrapping_neg();
                self.0 = (self.0 >> 1) ^ (0xEDB8_8320 & mask);
            }
        }
    }

    /// The CRC of the bytes so far.
    #[must_use]
    pub const fn value(&self) -> u32 {
        !self.0
    }

    /// The CRC of `bytes`.
    #[must_use]
    pub fn of(bytes: &[u8]) -> u32 {
        let mut crc = Self::new();
        crc.update(bytes);
        crc.value()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flash_error_codes_round_trip() {
        for code in 1..=127u8 {
            let e = FlashError::from_code(code).unwrap();
            assert_eq!(e.code(), code);
        }
        assert_eq!(FlashError::from_code(0), None);
        assert_eq!(FlashError::from_code(5), Some(FlashError::FlashWriteError));
        assert_eq!(FlashError::from_code(64), Some(FlashError::Other(64)));
    }

    #[test]
    fn flash_status_bits() {
        let s = FlashStatus::new(true, Some(FlashError::DataFormatError));
        assert_eq!(s.raw(), 0b111);
        assert!(s.in_progress() && !s.is_ok());
        assert_eq!(s.error(), Some(FlashError::DataFormatError));
        let m = FlashStatus::from_raw(0x1234_5600);
        assert_eq!(
            (m.manufacturer(), m.error(), m.is_ok()),
            (0x12_3456, None, true)
        );
        assert_eq!(
            FlashStatus::from_raw(0xFE).error(),
            Some(FlashError::Other(127))
        );
    }

    #[test]
    fn commands_and_states_are_lossless() {
        for raw in 0..=255u8 {
            assert_eq!(u8::from(ProgramCommand::from(raw)), raw);
            assert_eq!(u8::from(ProgramState::from(raw)), raw);
        }
        assert_eq!(ProgramCommand::from(3).name(), "clear program");
        assert_eq!(ProgramState::from(1).name(), "program started");
    }

    #[test]
    fn crc32_check_values() {
        assert_eq!(Crc32::of(b"123456789"), 0xCBF4_3926);
        assert_eq!(Crc32::of(&[0u8; 32]), 0x190A_55AD);
        let data: [u8; 1000] = core::array::from_fn(|i| (i % 251) as u8);
        let mut pieces = Crc32::new();
        for chunk in data.chunks(7) {
            pieces.update(chunk);
        }
        assert_eq!(pieces.value(), Crc32::of(&data));
    }
}
