//! A CAN FD frame as a trace gives it (ISO 11898-1:2015 section 10.4.2,
//! the FD base and extended frame formats): the crate does not decode CAN
//! FD, but a bus load counts its bits.

use crate::frame::CanId;

/// The data lengths a CAN FD frame can have, by DLC (ISO 11898-1:2015
/// section 10.4.2.4, table 5: DLC 9 to 15 mean 12, 16, 20, 24, 32, 48 and
/// 64 bytes).
pub const FD_LENGTHS: [u8; 16] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64];

/// A CAN FD frame: its identifier, data (0 to 64 bytes) and the two flags
/// of its control field.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct FdFrame {
    id: CanId,
    dlc: u8,
    data: [u8; 64],
    brs: bool,
    esi: bool,
}

impl FdFrame {
    /// A frame of `data` (at most 64 bytes; a length between the FD lengths
    /// is padded with zero bytes to the next one, as a controller sends
    /// it), with its bit-rate switch (BRS: the data phase at the data bit
    /// rate) and error state indicator (ESI: sent by an error-passive node).
    #[must_use]
    pub fn new(id: CanId, data: &[u8], brs: bool, esi: bool) -> Option<FdFrame> {
        let dlc = FD_LENGTHS
            .iter()
            .position(|&l| usize::from(l) >= data.len())?;
        let mut buf = [0u8; 64];
        buf.get_mut(..data.len())?.copy_from_slice(data);
        Some(FdFrame {
            id,
            dlc: u8::try_from(dlc).ok()?,
            data: buf,
            brs,
            esi,
        })
    }

    /// Its identifier.
    #[must_use]
    pub const fn id(&self) -> CanId {
        self.id
    }

    /// Its DLC (0 to 15).
    #[must_use]
    pub const fn dlc(&self) -> u8 {
        self.dlc
    }

    /// Its data bytes, as many as the DLC says (padding included).
    #[must_use]
    pub fn data(&self) -> &[u8] {
        let len = FD_LENGTHS.get(usize::from(self.dlc)).copied().unwrap_or(0);
        self.data.get(..usize::from(len)).unwrap_or(&[])
    }

    /// Bit-rate switch: the data phase is sent at the data bit rate.
    #[must_use]
    pub const fn brs(&self) -> bool {
        self.brs
    }

    /// Error state indicator: the transmitter is error passive.
    #[must_use]
    pub const fn esi(&self) -> bool {
        self.esi
    }
}

/// `123##1` and the data in hex, as candump writes it.
impl core::fmt::Display for FdFrame {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.id {
            CanId::Standard(id) => write!(f, "{id:03X}##")?,
            CanId::Extended(id) => write!(f, "{id:08X}##")?,
        }
        write!(f, "{:X}", u8::from(self.brs) | u8::from(self.esi) << 1)?;
        self.data().iter().try_for_each(|b| write!(f, "{b:02X}"))
    }
}

impl core::fmt::Debug for FdFrame {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}
