//! The LSS wire layer: the one place where the bytes of LSS frames (7E5h,
//! 7E4h) are read and written; see the [module docs](crate::lss) for the
//! frames. [`LssFrame`] is the checked view, [`LssRequest`] and
//! [`LssResponse`] the representations (the crate's
//! [`Codec`](crate::wire::Codec) shape).

use crate::bytes::Payload;
use crate::cob_id::{LssDirection, LSS_MASTER_TO_SLAVE, LSS_SLAVE_TO_MASTER};
use crate::error::DecodeError;
use crate::frame::{CanFrame, CanId};
use crate::wire::Codec;

/// The checked view of an LSS frame's data: 0..=8 bytes (CiA 305 section
/// 4 "LSS protocol descriptions": a service frame is 8 bytes, byte 0 the
/// command specifier; any other length is kept as an `Other` frame).
///
/// ```
/// use canopen_codec::lss::LssFrame;
/// let f = LssFrame::new_checked(&[0x5E, 0, 0, 0, 0, 0, 0, 0]).unwrap();
/// assert_eq!(f.service(), Some((0x5E, [0; 7])));
/// assert_eq!(LssFrame::new_checked(&[0x5E]).unwrap().service(), None);
/// assert!(LssFrame::new_checked(&[0; 9]).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LssFrame {
    payload: Payload,
}

impl LssFrame {
    /// The view of `data`: [`DecodeError::TooLong`] above 8 bytes.
    #[inline]
    pub fn new_checked(data: &[u8]) -> Result<Self, DecodeError> {
        Payload::new(data)
            .map(|payload| LssFrame { payload })
            .ok_or(DecodeError::TooLong {
                max: 8,
                got: data.len(),
            })
    }

    /// The data bytes.
    #[must_use]
    #[inline]
    pub fn as_bytes(&self) -> &[u8] {
        self.payload.as_slice()
    }

    /// An 8-byte frame's command specifier (byte 0) and service data
    /// (bytes 1..=7); `None` for any other length.
    #[must_use]
    #[inline]
    pub fn service(&self) -> Option<(u8, [u8; 7])> {
        match *self.as_bytes() {
            [cs, a, b, c, d, e, f, g] => Some((cs, [a, b, c, d, e, f, g])),
            _ => None,
        }
    }
}

/// One of the four parts of the 128-bit LSS address (object 1018h
/// sub-indexes 1..=4, CiA 301 section 7.5.2.23 "Object 1018h: Identity
/// object"; CiA 305 section 3.2 "LSS address").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LssField {
    /// 1018h:01 vendor-ID.
    Vendor,
    /// 1018h:02 product code.
    Product,
    /// 1018h:03 revision number.
    Revision,
    /// 1018h:04 serial number.
    Serial,
}

impl LssField {
    /// The four fields in address order (fastscan's LSSSub 0..=3).
    pub const ALL: [LssField; 4] = [Self::Vendor, Self::Product, Self::Revision, Self::Serial];

    /// The position in the address (fastscan's LSSSub): 0..=3.
    #[must_use]
    pub const fn index(self) -> u8 {
        match self {
            Self::Vendor => 0,
            Self::Product => 1,
            Self::Revision => 2,
            Self::Serial => 3,
        }
    }

    /// The field at position `index` (0..=3), if any.
    #[must_use]
    pub const fn from_index(index: u8) -> Option<Self> {
        match index {
            0 => Some(Self::Vendor),
            1 => Some(Self::Product),
            2 => Some(Self::Revision),
            3 => Some(Self::Serial),
            _ => None,
        }
    }

    /// The field's name in words.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Vendor => "vendor",
            Self::Product => "product",
            Self::Revision => "revision",
            Self::Serial => "serial",
        }
    }
}

/// The 128-bit LSS address of a slave: its 1018h identity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct LssAddress {
    /// 1018h:01.
    pub vendor: u32,
    /// 1018h:02.
    pub product: u32,
    /// 1018h:03.
    pub revision: u32,
    /// 1018h:04.
    pub serial: u32,
}

impl LssAddress {
    /// The part named by `field`.
    #[must_use]
    pub const fn get(&self, field: LssField) -> u32 {
        match field {
            LssField::Vendor => self.vendor,
            LssField::Product => self.product,
            LssField::Revision => self.revision,
            LssField::Serial => self.serial,
        }
    }

    /// Sets the part named by `field`.
    pub fn set(&mut self, field: LssField, value: u32) {
        match field {
            LssField::Vendor => self.vendor = value,
            LssField::Product => self.product = value,
            LssField::Revision => self.revision = value,
            LssField::Serial => self.serial = value,
        }
    }
}

/// The LSS mode switch state global asks for (byte 1 of cs 04h).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssMode {
    /// 0: LSS waiting state.
    Waiting,
    /// 1: LSS configuration state.
    Configuration,
    /// Any other byte, kept.
    Unknown(u8),
}

impl From<u8> for LssMode {
    fn from(raw: u8) -> Self {
        match raw {
            0 => Self::Waiting,
            1 => Self::Configuration,
            other => Self::Unknown(other),
        }
    }
}

impl From<LssMode> for u8 {
    fn from(mode: LssMode) -> u8 {
        match mode {
            LssMode::Waiting => 0,
            LssMode::Configuration => 1,
            LssMode::Unknown(raw) => raw,
        }
    }
}

/// What inquire identity / node-ID asks for (cs 5Ah..=5Eh).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssInquiry {
    /// 5Ah..=5Dh: one part of the LSS address.
    Address(LssField),
    /// 5Eh: the active node-ID.
    NodeId,
}

/// The part of the identify remote slave range a frame carries (cs
/// 46h..=4Bh, CiA 305 "LSS identify remote slave").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IdentifyPart {
    /// 46h: vendor-ID (exact).
    Vendor,
    /// 47h: product code (exact).
    Product,
    /// 48h: lowest revision number.
    RevisionLow,
    /// 49h: highest revision number.
    RevisionHigh,
    /// 4Ah: lowest serial number.
    SerialLow,
    /// 4Bh: highest serial number (the slave answers after this one).
    SerialHigh,
}

impl IdentifyPart {
    /// The six parts in the order the master sends them.
    pub const ALL: [IdentifyPart; 6] = [
        Self::Vendor,
        Self::Product,
        Self::RevisionLow,
        Self::RevisionHigh,
        Self::SerialLow,
        Self::SerialHigh,
    ];

    const fn cs(self) -> u8 {
        match self {
            Self::Vendor => 0x46,
            Self::Product => 0x47,
            Self::RevisionLow => 0x48,
            Self::RevisionHigh => 0x49,
            Self::SerialLow => 0x4A,
            Self::SerialHigh => 0x4B,
        }
    }

    /// The part in words.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Vendor => "vendor",
            Self::Product => "product",
            Self::RevisionLow => "revision low",
            Self::RevisionHigh => "revision high",
            Self::SerialLow => "serial low",
            Self::SerialHigh => "serial high",
        }
    }
}

/// One fastscan step (cs 51h), values as sent (the slave checks ranges).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fastscan {
    /// IDNumber: the candidate value of the address part `sub`.
    pub id_number: u32,
    /// BitChecked: the lowest bit compared (0..=31), or 80h to reset the
    /// search ([`Fastscan::RESET`]).
    pub bit_checked: u8,
    /// LSSSub: the address part compared (0..=3).
    pub sub: u8,
    /// LSSNext: the part the slave compares next on a match (0..=3).
    pub next: u8,
}

impl Fastscan {
    /// BitChecked 80h: every non-configured slave in waiting state resets
    /// its search position and answers.
    pub const RESET: u8 = 0x80;
}

/// A status byte pair of configure node-ID, configure bit timing and store
/// configuration responses (CiA 305 sections "Configure node-ID",
/// "Configure bit timing parameters", "Store configuration").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LssStatus {
    /// Byte 1: the error code.
    pub code: LssErrorCode,
    /// Byte 2: the implementation-specific error (meaningful with
    /// [`LssErrorCode::ImplementationSpecific`], kept as received).
    pub specific: u8,
}

impl LssStatus {
    /// Success (0, 0).
    pub const OK: Self = Self {
        code: LssErrorCode::Success,
        specific: 0,
    };

    /// A status with `code` and specific byte 0.
    #[must_use]
    pub const fn new(code: LssErrorCode) -> Self {
        Self { code, specific: 0 }
    }

    /// True for error code 0.
    #[must_use]
    pub const fn is_ok(&self) -> bool {
        matches!(self.code, LssErrorCode::Success)
    }
}

/// The error code of an LSS configuration response.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssErrorCode {
    /// 0: protocol successfully completed.
    Success,
    /// 1: node-ID out of range (11h), bit timing not supported (13h), store
    /// configuration not supported (17h).
    Refused,
    /// 2: storage media access error (17h).
    StorageAccess,
    /// 255: implementation-specific error, byte 2 tells which.
    ImplementationSpecific,
    /// 3..=254: reserved, kept.
    Reserved(u8),
}

impl From<u8> for LssErrorCode {
    fn from(raw: u8) -> Self {
        match raw {
            0 => Self::Success,
            1 => Self::Refused,
            2 => Self::StorageAccess,
            255 => Self::ImplementationSpecific,
            other => Self::Reserved(other),
        }
    }
}

impl From<LssErrorCode> for u8 {
    fn from(code: LssErrorCode) -> u8 {
        match code {
            LssErrorCode::Success => 0,
            LssErrorCode::Refused => 1,
            LssErrorCode::StorageAccess => 2,
            LssErrorCode::ImplementationSpecific => 255,
            LssErrorCode::Reserved(raw) => raw,
        }
    }
}

/// An LSS master's request (identifier 7E5h).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LssRequest {
    /// 04h: switch state global.
    SwitchStateGlobal(LssMode),
    /// 40h..=43h: switch state selective, one address part.
    SwitchStateSelective(LssField, u32),
    /// 11h: configure node-ID (1..=127, or 255 to unconfigure; raw).
    ConfigureNodeId(u8),
    /// 13h: configure bit timing parameters.
    ConfigureBitTiming {
        /// Table selector (0: the CiA 305 standard table).
        table: u8,
        /// Table index (standard table: 0 = 1000 kbit/s ... 8 = 10 kbit/s).
        index: u8,
    },
    /// 15h: activate bit timing parameters after `delay_ms` (twice).
    ActivateBitTiming {
        /// Switch delay in milliseconds.
        delay_ms: u16,
    },
    /// 17h: store configuration.
    StoreConfiguration,
    /// 5Ah..=5Eh: inquire an address part or the node-ID.
    Inquire(LssInquiry),
    /// 46h..=4Bh: identify remote slave, one part of the range.
    IdentifyRemoteSlave(IdentifyPart, u32),
    /// 4Ch: identify non-configured remote slave.
    IdentifyNonConfigured,
    /// 51h: fastscan.
    Fastscan(Fastscan),
    /// Any other frame (unlisted cs, length other than 8, a reserved byte
    /// not zero): the payload, kept.
    Other(Payload),
}

/// An LSS slave's response (identifier 7E4h).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LssResponse {
    /// 44h: switch state selective response.
    SwitchStateSelective,
    /// 11h: configure node-ID response.
    ConfigureNodeId(LssStatus),
    /// 13h: configure bit timing response.
    ConfigureBitTiming(LssStatus),
    /// 17h: store configuration response.
    StoreConfiguration(LssStatus),
    /// 5Ah..=5Dh: an address part.
    Address(LssField, u32),
    /// 5Eh: the active node-ID (FFh: not configured).
    NodeId(u8),
    /// 4Fh: identify slave (answer to identify remote slave and fastscan).
    IdentifySlave,
    /// 50h: identify non-configured slave.
    IdentifyNonConfigured,
    /// Any other frame, kept.
    Other(Payload),
}

/// An LSS frame of either direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LssMessage {
    /// Master to slave (7E5h).
    Request(LssRequest),
    /// Slave to master (7E4h).
    Response(LssResponse),
}

const fn field_cs(base: u8, field: LssField) -> u8 {
    base + field.index()
}

/// The data bytes `from..` are all zero.
fn zero_from(rest: &[u8; 7], from: usize) -> bool {
    rest.get(from..).is_some_and(|r| r.iter().all(|b| *b == 0))
}

fn u32_at(rest: &[u8; 7]) -> u32 {
    let [a, b, c, d, ..] = *rest;
    u32::from_le_bytes([a, b, c, d])
}

impl LssRequest {
    /// The request command specifier `cs` and the service data `rest`
    /// describe; `None` for a combination no service has.
    fn from_service(cs: u8, rest: [u8; 7]) -> Option<Self> {
        let [b1, b2, _, _, b5, b6, b7] = rest;
        Some(match cs {
            0x04 if zero_from(&rest, 1) => Self::SwitchStateGlobal(b1.into()),
            0x40..=0x43 if zero_from(&rest, 4) => {
                Self::SwitchStateSelective(LssField::from_index(cs - 0x40)?, u32_at(&rest))
            }
            0x11 if zero_from(&rest, 1) => Self::ConfigureNodeId(b1),
            0x13 if zero_from(&rest, 2) => Self::ConfigureBitTiming {
                table: b1,
                index: b2,
            },
            0x15 if zero_from(&rest, 2) => Self::ActivateBitTiming {
                delay_ms: u16::from_le_bytes([b1, b2]),
            },
            0x17 if zero_from(&rest, 0) => Self::StoreConfiguration,
            0x5A..=0x5D if zero_from(&rest, 0) => {
                Self::Inquire(LssInquiry::Address(LssField::from_index(cs - 0x5A)?))
            }
            0x5E if zero_from(&rest, 0) => Self::Inquire(LssInquiry::NodeId),
            0x46..=0x4B if zero_from(&rest, 4) => {
                let part = IdentifyPart::ALL.into_iter().find(|p| p.cs() == cs)?;
                Self::IdentifyRemoteSlave(part, u32_at(&rest))
            }
            0x4C if zero_from(&rest, 0) => Self::IdentifyNonConfigured,
            0x51 => Self::Fastscan(Fastscan {
                id_number: u32_at(&rest),
                bit_checked: b5,
                sub: b6,
                next: b7,
            }),
            _ => return None,
        })
    }

    /// Writes the frame into `buf`, returning the length (8, or the kept
    /// length of `Other`). Reserved bytes are 0.
    fn write(&self, buf: &mut [u8; 8]) -> usize {
        *buf = [0; 8];
        let (cs, data): (u8, [u8; 7]) = match *self {
            Self::SwitchStateGlobal(mode) => (0x04, [mode.into(), 0, 0, 0, 0, 0, 0]),
            Self::SwitchStateSelective(field, v) => (field_cs(0x40, field), u32_data(v)),
            Self::ConfigureNodeId(id) => (0x11, [id, 0, 0, 0, 0, 0, 0]),
            Self::ConfigureBitTiming { table, index } => (0x13, [table, index, 0, 0, 0, 0, 0]),
            Self::ActivateBitTiming { delay_ms } => {
                let [a, b] = delay_ms.to_le_bytes();
                (0x15, [a, b, 0, 0, 0, 0, 0])
            }
            Self::StoreConfiguration => (0x17, [0; 7]),
            Self::Inquire(LssInquiry::Address(field)) => (field_cs(0x5A, field), [0; 7]),
            Self::Inquire(LssInquiry::NodeId) => (0x5E, [0; 7]),
            Self::IdentifyRemoteSlave(part, v) => (part.cs(), u32_data(v)),
            Self::IdentifyNonConfigured => (0x4C, [0; 7]),
            Self::Fastscan(f) => {
                let [a, b, c, d] = f.id_number.to_le_bytes();
                (0x51, [a, b, c, d, f.bit_checked, f.sub, f.next])
            }
            Self::Other(p) => return put_other(buf, &p),
        };
        put(buf, cs, data)
    }

    /// The command specifier (byte 0), if the frame has one.
    #[must_use]
    pub fn cs(&self) -> Option<u8> {
        let mut buf = [0; 8];
        let n = self.emit(&mut buf);
        buf.first().copied().filter(|_| n > 0)
    }

    /// The bytes [`emit`](Codec::emit) writes: 8, or the kept length of
    /// `Other`.
    fn len(&self) -> usize {
        match self {
            Self::Other(p) => p.len(),
            _ => 8,
        }
    }
}

/// The frame methods of an LSS message type: the message a frame on its
/// identifier carries, and the frame that carries a message.
macro_rules! lss_frames {
    ($(#[$from_view:meta])* $ty:ident, $id:ident, $name:literal) => {
        impl $ty {
            #[doc = concat!("The ", $name, " a checked frame carries: every frame is one, a")]
            #[doc = "payload no service describes (or not 8 bytes long) is `Other`."]
            $(#[$from_view])*
            #[must_use]
            pub fn from_view(frame: &LssFrame) -> Self {
                let known = frame.service().and_then(|(cs, rest)| Self::from_service(cs, rest));
                known.unwrap_or(Self::Other(frame.payload))
            }

            #[doc = concat!("The ", $name, " a frame carries: a data frame on ")]
            #[doc = concat!("its identifier whose payload decodes; `None` for any other frame.")]
            #[must_use]
            pub fn of_frame(frame: &CanFrame) -> Option<Self> {
                let on_id = frame.id() == CanId::Standard($id);
                on_id.then(|| Self::parse_frame(frame).ok()).flatten()
            }

            #[doc = concat!("The frame that carries the ", $name, ": its identifier, its bytes.")]
            #[must_use]
            pub fn to_frame(&self) -> CanFrame {
                self.to_frame_on(CanId::Standard($id))
            }
        }

        impl Codec for $ty {
            /// Reads a payload of 0..=8 bytes (never fails for those: a
            /// frame no service describes is `Other`).
            #[inline]
            fn parse(data: &[u8]) -> Result<Self, DecodeError> {
                LssFrame::new_checked(data).map(|f| Self::from_view(&f))
            }

            #[inline]
            fn emit(&self, buf: &mut [u8; 8]) -> usize {
                self.write(buf)
            }

            #[inline]
            fn buffer_len(&self) -> usize {
                self.len()
            }
        }
    };
}

lss_frames!(
    /// See the [module docs](crate::lss).
    ///
    /// ```
    /// use canopen_codec::lss::{LssField, LssRequest};
    /// use canopen_codec::wire::Codec;
    /// let r = LssRequest::parse(&[0x40, 0x9A, 0x02, 0, 0, 0, 0, 0]).unwrap();
    /// assert_eq!(r, LssRequest::SwitchStateSelective(LssField::Vendor, 0x29A));
    /// let mut buf = [0; 8];
    /// assert_eq!(r.emit(&mut buf), 8);
    /// assert_eq!(buf, [0x40, 0x9A, 0x02, 0, 0, 0, 0, 0]);
    /// ```
    LssRequest,
    LSS_MASTER_TO_SLAVE,
    "request (7E5h, master to slave)"
);
lss_frames!(
    /// ```
    /// use canopen_codec::lss::{LssResponse, LssStatus};
    /// use canopen_codec::wire::Codec;
    /// let r = LssResponse::parse(&[0x11, 0, 0, 0, 0, 0, 0, 0]).unwrap();
    /// assert_eq!(r, LssResponse::ConfigureNodeId(LssStatus::OK));
    /// ```
    LssResponse,
    LSS_SLAVE_TO_MASTER,
    "response (7E4h, slave to master)"
);

impl LssResponse {
    /// The response command specifier `cs` and the service data `rest`
    /// describe; `None` for a combination no service has.
    fn from_service(cs: u8, rest: [u8; 7]) -> Option<Self> {
        let [b1, b2, ..] = rest;
        let status = LssStatus {
            code: b1.into(),
            specific: b2,
        };
        Some(match cs {
            0x44 if zero_from(&rest, 0) => Self::SwitchStateSelective,
            0x11 if zero_from(&rest, 2) => Self::ConfigureNodeId(status),
            0x13 if zero_from(&rest, 2) => Self::ConfigureBitTiming(status),
            0x17 if zero_from(&rest, 2) => Self::StoreConfiguration(status),
            0x5A..=0x5D if zero_from(&rest, 4) => {
                Self::Address(LssField::from_index(cs - 0x5A)?, u32_at(&rest))
            }
            0x5E if zero_from(&rest, 1) => Self::NodeId(b1),
            0x4F if zero_from(&rest, 0) => Self::IdentifySlave,
            0x50 if zero_from(&rest, 0) => Self::IdentifyNonConfigured,
            _ => return None,
        })
    }

    /// The bytes [`emit`](Codec::emit) writes: 8, or the kept length of
    /// `Other`.
    fn len(&self) -> usize {
        match self {
            Self::Other(p) => p.len(),
            _ => 8,
        }
    }

    /// Writes the frame into `buf`, returning the length.
    fn write(&self, buf: &mut [u8; 8]) -> usize {
        *buf = [0; 8];
        let st = |s: LssStatus| [s.code.into(), s.specific, 0, 0, 0, 0, 0];
        let (cs, data): (u8, [u8; 7]) = match *self {
            Self::SwitchStateSelective => (0x44, [0; 7]),
            Self::ConfigureNodeId(s) => (0x11, st(s)),
            Self::ConfigureBitTiming(s) => (0x13, st(s)),
            Self::StoreConfiguration(s) => (0x17, st(s)),
            Self::Address(field, v) => (field_cs(0x5A, field), u32_data(v)),
            Self::NodeId(id) => (0x5E, [id, 0, 0, 0, 0, 0, 0]),
            Self::IdentifySlave => (0x4F, [0; 7]),
            Self::IdentifyNonConfigured => (0x50, [0; 7]),
            Self::Other(p) => return put_other(buf, &p),
        };
        put(buf, cs, data)
    }
}

impl LssMessage {
    /// Parses the payload of a frame travelling `direction`
    /// ([`LssRequest`] or [`LssResponse`]'s [`Codec::parse`]).
    pub fn parse(direction: LssDirection, data: &[u8]) -> Result<Self, DecodeError> {
        Ok(match direction {
            LssDirection::MasterToSlave => Self::Request(LssRequest::parse(data)?),
            LssDirection::SlaveToMaster => Self::Response(LssResponse::parse(data)?),
        })
    }

    /// Writes the frame's bytes into `buf`, returning the length
    /// ([`Codec::emit`] of the request or response).
    pub fn emit(&self, buf: &mut [u8; 8]) -> usize {
        match self {
            Self::Request(r) => r.emit(buf),
            Self::Response(r) => r.emit(buf),
        }
    }

    /// The bytes [`emit`](Self::emit) writes.
    #[must_use]
    pub fn buffer_len(&self) -> usize {
        match self {
            Self::Request(r) => r.buffer_len(),
            Self::Response(r) => r.buffer_len(),
        }
    }

    /// Which way the frame travels.
    #[must_use]
    pub const fn direction(&self) -> LssDirection {
        match self {
            Self::Request(_) => LssDirection::MasterToSlave,
            Self::Response(_) => LssDirection::SlaveToMaster,
        }
    }
}

fn u32_data(v: u32) -> [u8; 7] {
    let [a, b, c, d] = v.to_le_bytes();
    [a, b, c, d, 0, 0, 0]
}

fn put(buf: &mut [u8; 8], cs: u8, data: [u8; 7]) -> usize {
    let [a, b, c, d, e, f, g] = data;
    *buf = [cs, a, b, c, d, e, f, g];
    8
}

fn put_other(buf: &mut [u8; 8], p: &Payload) -> usize {
    crate::bytes::copy_payload(buf, p.as_slice());
    p.as_slice().len()
}
