//! The peer bench's streams and adapters: the same frames, once per crate in
//! that crate's own frame type (built before timing), and one adapter per
//! crate that calls its public decoder and nothing more, `#[inline(never)]`
//! so every crate pays one call per frame.
//!
//! Streams:
//!
//! - `mixed`: the real Delta-Q ICL1500 startup capture (1387 frames:
//!   heartbeats, PDOs, EMCY, NMT), read from the shared data folder beside
//!   the checkout (its `spec` / `captures` folder) or `$CANOPEN_SHARED_DIR`;
//!   when absent, our own recorded session (tests/data/virtual-session.log,
//!   frames our code produced), and [`Streams::real`] says so;
//! - `sdo_upload`: every frame of a 1000-byte segmented SDO upload, made by
//!   our own client and server (288 frames: initiate, 143 segment
//!   request/response pairs);
//! - `heartbeats`: the heartbeat frames (0x701..0x77F) of `mixed`.
//!
//! Peers (exact versions, from crates.io): canopen-rs 0.6.1, zencan-common
//! 0.0.5, oze-canopen 0.1.0. canopen-rs has no single decode entry point, so
//! its adapter switches on the COB-ID (and on the SDO command specifier)
//! to call the matching public `decode_*` function; zencan-common decodes
//! through `ZencanMessage::try_from` (it has no EMCY or PDO decoder and
//! answers those with an error, as its own receive path does); oze-canopen
//! classifies with `RxMessageParsed::new` and reads the SDO, EMCY and NMT
//! payloads with its binrw types (it has no heartbeat decoder).

use std::io::Cursor;
use std::path::{Path, PathBuf};
use tokio::time::Instant;

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use canopen_codec::pdo::{MappingEntry, PdoMapping};
use canopen_codec::sdo::{AbortCode, Client, ClientConfig, Server, ServerConfig};
use canopen_codec::{CanFrame, CanId, DecodeError, Message, NodeId, Timestamp};

/// The capture the mixed stream is read from.
pub const CAPTURE: &str = "deltaq-icl1500-startup.log";

/// One stream's frames in every crate's own frame type.
pub struct Stream {
    /// Our frames.
    pub ours: Vec<CanFrame>,
    /// canopen-rs works on a COB-ID and the data bytes.
    pub canopen_rs: Vec<RawFrame>,
    /// zencan-common's `CanMessage`.
    pub zencan: Vec<zencan_common::CanMessage>,
    /// oze-canopen's `RxMessage`.
    pub oze: Vec<oze_canopen::canopen::RxMessage>,
}

impl Stream {
    fn new(frames: Vec<CanFrame>) -> Self {
        let now = Instant::now();
        Stream {
            canopen_rs: frames.iter().map(RawFrame::from).collect(),
            zencan: frames.iter().map(to_zencan).collect(),
            oze: frames.iter().map(|f| to_oze(f, now)).collect(),
            ours: frames,
        }
    }

    /// The number of frames.
    pub fn len(&self) -> usize {
        self.ours.len()
    }

    /// True when the stream has no frames.
    pub fn is_empty(&self) -> bool {
        self.ours.is_empty()
    }
}

/// Every stream of the bench.
pub struct Streams {
    /// True when `mixed` is the real capture (false: our own session).
    pub real: bool,
    /// The capture (or fallback), every frame.
    pub mixed: Stream,
    /// A 1000-byte segmented SDO upload.
    pub sdo_upload: Stream,
    /// The heartbeats of `mixed`.
    pub heartbeats: Stream,
}

impl Streams {
    /// Loads the capture (or the fallback) and builds every stream.
    pub fn load() -> Self {
        let (real, mixed) = mixed_frames();
        let heartbeats = mixed
            .iter()
            .copied()
            .filter(|f| matches!(f.id(), CanId::Standard(0x701..=0x77F)) && !f.is_remote())
            .collect();
        Streams {
            real,
            mixed: Stream::new(mixed),
            sdo_upload: Stream::new(sdo_upload_frames()),
            heartbeats: Stream::new(heartbeats),
        }
    }
}

/// The shared data folder's captures (see the module docs).
pub fn captures_dir() -> PathBuf {
    std::env::var_os("CANOPEN_SHARED_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            // benches/peers -> the checkout's parent, built from parts.
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join("..")
                .join("..")
                .join("shared")
        })
        .join("spec")
        .join("captures")
}

fn parse_log(text: &str) -> Vec<CanFrame> {
    text.lines()
        .filter_map(|l| canopen_codec::trace::candump::parse_line(l).ok())
        .map(|l| l.frame)
        .collect()
}

fn mixed_frames() -> (bool, Vec<CanFrame>) {
    let path = captures_dir().join(CAPTURE);
    if let Ok(text) = std::fs::read_to_string(&path) {
        return (true, parse_log(&text));
    }
    let own = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("..")
        .join("tests")
        .join("data")
        .join("virtual-session.log");
    let text =
        std::fs::read_to_string(&own).unwrap_or_else(|e| panic!("reading {}: {e}", own.display()));
    (false, parse_log(&text))
}

const LEN: usize = 1000;

/// One 1000-byte domain at 2000h:00.
struct FixedOd([u8; LEN]);

impl ObjectDictionary for FixedOd {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        if (index, sub) != (0x2000, 0) {
            return Err(AbortCode::ObjectDoesNotExist);
        }
        Ok(ObjectInfo {
            access: Access::ReadOnly,
            len: LEN,
            size: SizeRule::Variable { max: LEN },
            pdo_mappable: false,
        })
    }
    fn read(&mut self, _: u16, _: u8, offset: usize, buf: &mut [u8]) -> Result<usize, AbortCode> {
        Ok(canopen_codec::od::read_at(&self.0, offset, buf))
    }
    fn write(&mut self, _: u16, _: u8, _: usize, _: &[u8]) -> Result<(), AbortCode> {
        Err(AbortCode::WriteOfReadOnlyObject)
    }
    fn finish_write(&mut self, _: u16, _: u8, _: usize) -> Result<(), AbortCode> {
        Err(AbortCode::WriteOfReadOnlyObject)
    }
}

/// Every frame of a 1000-byte upload between our client and server.
fn sdo_upload_frames() -> Vec<CanFrame> {
    let node = NodeId::new(1).expect("node 1");
    let mut value = [0u8; LEN];
    for (i, b) in value.iter_mut().enumerate() {
        *b = (i % 251) as u8;
    }
    let mut client: Client<&'static [u8]> = Client::new(ClientConfig::for_server(node));
    let mut server = Server::new(ServerConfig::for_node(node), FixedOd(value));
    let now = Timestamp::ZERO;
    client.start_upload(now, 0x2000, 0).expect("client is idle");
    let mut frames = Vec::new();
    while let Some(req) = client.poll_transmit() {
        frames.push(req);
        server.handle_frame(now, &req);
        while server.poll_event().is_some() {}
        while let Some(resp) = server.poll_transmit() {
            frames.push(resp);
            client.handle_frame(now, &resp);
        }
        while client.poll_event().is_some() {}
    }
    frames
}

/// The frame as canopen-rs's decoders take it: COB-ID and data bytes.
#[derive(Debug, Clone, Copy)]
pub struct RawFrame {
    /// The 11-bit identifier (29-bit frames keep their low 16 bits).
    pub cob_id: u16,
    /// The data length.
    pub len: u8,
    /// The data, zero-padded.
    pub data: [u8; 8],
}

impl RawFrame {
    /// The data bytes.
    pub fn data(&self) -> &[u8] {
        self.data.get(..usize::from(self.len)).unwrap_or(&[])
    }
}

impl From<&CanFrame> for RawFrame {
    fn from(f: &CanFrame) -> Self {
        RawFrame {
            cob_id: f.id().raw() as u16,
            len: f.data().len() as u8,
            data: f.padded_data(),
        }
    }
}

fn to_zencan(f: &CanFrame) -> zencan_common::CanMessage {
    let id = match f.id() {
        CanId::Standard(id) => zencan_common::CanId::std(id),
        CanId::Extended(id) => zencan_common::CanId::extended(id),
    };
    if f.is_remote() {
        zencan_common::CanMessage::new_rtr(id)
    } else {
        zencan_common::CanMessage::new(id, f.data())
    }
}

fn to_oze(f: &CanFrame, timestamp: Instant) -> oze_canopen::canopen::RxMessage {
    oze_canopen::canopen::RxMessage {
        timestamp,
        cob_id: f.id().raw() as u16,
        data: f.padded_data(),
        dlc: f.data().len(),
    }
}

/// The copy baseline: the frame itself, through the same kind of call.
#[inline(never)]
pub fn copy(f: &CanFrame) -> CanFrame {
    *f
}

/// canopen-codec: `Message::decode`.
#[inline(never)]
pub fn ours(f: &CanFrame) -> Result<Message, DecodeError> {
    Message::decode(f)
}

/// What canopen-rs's decoders return, one variant per decoder called.
#[derive(Debug)]
pub enum CanopenRs<'a> {
    /// `nmt::decode_command`.
    Nmt(canopen_rs::NmtCommand, canopen_rs::NodeId),
    /// `sync::decode`.
    Sync(Option<u8>),
    /// `EmergencyMessage::decode`.
    Emcy(canopen_rs::EmergencyMessage),
    /// `TimeOfDay::decode`.
    Time(canopen_rs::TimeOfDay),
    /// A PDO (canopen-rs unpacks PDOs into its dictionary only: see `pdo`).
    Pdo(&'a [u8]),
    /// `nmt::decode_heartbeat`.
    Heartbeat(canopen_rs::NmtState),
    /// An SDO address and a size, toggle or abort code.
    Sdo(canopen_rs::Address, u32),
    /// `sdo::decode_data_segment`.
    Segment(canopen_rs::Segment<'a>),
    /// `sdo::decode_upload_expedited_response`.
    Expedited(canopen_rs::Address, canopen_rs::Value),
    /// `sdo::decode_download_segment_response` /
    /// `sdo::decode_upload_segment_request`: the toggle.
    Toggle(bool),
}

fn payload(f: &RawFrame) -> canopen_rs::Result<&canopen_rs::sdo::SdoPayload> {
    if f.len == 8 {
        Ok(&f.data)
    } else {
        Err(canopen_rs::Error::BadLength)
    }
}

/// canopen-rs: a COB-ID switch to its public decoders.
#[inline(never)]
pub fn canopen_rs(f: &RawFrame) -> canopen_rs::Result<CanopenRs<'_>> {
    use canopen_rs::sdo;
    let id = f.cob_id;
    let data = f.data();
    Ok(match id {
        0x000 => {
            let frame: &canopen_rs::nmt::NmtCommandFrame =
                data.try_into().map_err(|_| canopen_rs::Error::BadLength)?;
            let (c, n) = canopen_rs::nmt::decode_command(frame)?;
            CanopenRs::Nmt(c, n)
        }
        0x080 => CanopenRs::Sync(canopen_rs::sync::decode(data)?),
        0x081..=0x0FF => CanopenRs::Emcy(canopen_rs::EmergencyMessage::decode(data)?),
        0x100 => CanopenRs::Time(canopen_rs::TimeOfDay::decode(data)?),
        0x180..=0x57F => CanopenRs::Pdo(data),
        0x581..=0x5FF => {
            let p = payload(f)?;
            match p[0] & 0xE0 {
                0x00 => CanopenRs::Segment(sdo::decode_data_segment(p)?),
                0x20 => CanopenRs::Toggle(sdo::decode_download_segment_response(p)?),
                0x40 if p[0] & 0x02 != 0 => {
                    let ty = match (p[0] >> 2) & 3 {
                        3 => canopen_rs::DataType::Unsigned8,
                        2 => canopen_rs::DataType::Unsigned16,
                        0 => canopen_rs::DataType::Unsigned32,
                        _ => canopen_rs::DataType::OctetString,
                    };
                    let (a, v) = sdo::decode_upload_expedited_response(p, ty)?;
                    CanopenRs::Expedited(a, v)
                }
                0x40 => {
                    let (a, n) = sdo::decode_upload_initiate_segmented_response(p)?;
                    CanopenRs::Sdo(a, n)
                }
                0x60 => CanopenRs::Sdo(sdo::decode_download_response(p)?, 0),
                0x80 => {
                    let (a, c) = sdo::decode_abort(p)?;
                    CanopenRs::Sdo(a, c)
                }
                _ => return Err(canopen_rs::Error::UnexpectedCommand),
            }
        }
        0x601..=0x67F => {
            let p = payload(f)?;
            match p[0] & 0xE0 {
                0x00 => CanopenRs::Segment(sdo::decode_data_segment(p)?),
                0x20 => {
                    let (a, n) = sdo::decode_download_initiate_segmented(p)?;
                    CanopenRs::Sdo(a, n)
                }
                // No public decoder for an upload request: its address.
                0x40 => CanopenRs::Sdo(
                    canopen_rs::Address::new(u16::from_le_bytes([p[1], p[2]]), p[3]),
                    0,
                ),
                0x60 => CanopenRs::Toggle(sdo::decode_upload_segment_request(p)?),
                0x80 => {
                    let (a, c) = sdo::decode_abort(p)?;
                    CanopenRs::Sdo(a, c)
                }
                _ => return Err(canopen_rs::Error::UnexpectedCommand),
            }
        }
        0x701..=0x77F => {
            let frame: &canopen_rs::nmt::HeartbeatFrame =
                data.try_into().map_err(|_| canopen_rs::Error::BadLength)?;
            CanopenRs::Heartbeat(canopen_rs::nmt::decode_heartbeat(frame)?)
        }
        _ => return Err(canopen_rs::Error::UnexpectedCommand),
    })
}

/// zencan-common: `ZencanMessage::try_from`.
#[inline(never)]
pub fn zencan(
    m: &zencan_common::CanMessage,
) -> Result<zencan_common::messages::ZencanMessage, zencan_common::messages::MessageError> {
    zencan_common::messages::ZencanMessage::try_from(*m)
}

/// What oze-canopen's decoders return.
#[derive(Debug)]
pub enum Oze {
    /// Classified only (PDO, SYNC, heartbeat, LSS, unknown).
    Parsed(oze_canopen::canopen::RxMessageParsed),
    /// `SdoResponse::read_le`.
    SdoResponse(
        oze_canopen::canopen::NodeId,
        oze_canopen::proto::sdo::SdoResponse,
    ),
    /// `SdoRequest::read_le`.
    SdoRequest(
        oze_canopen::canopen::NodeId,
        oze_canopen::proto::sdo::SdoRequest,
    ),
    /// `Emcy::read_le`.
    Emcy(oze_canopen::canopen::NodeId, oze_canopen::proto::emcy::Emcy),
    /// `NmtCommand::read_le`.
    Nmt(oze_canopen::proto::nmt::NmtCommand),
}

/// oze-canopen: `RxMessageParsed::new`, then its binrw reader for the
/// payloads it has types for.
#[inline(never)]
pub fn oze(m: &oze_canopen::canopen::RxMessage) -> oze_canopen::BinResult<Oze> {
    use oze_canopen::canopen::{RxMessageParsed, RxMessageType};
    use oze_canopen::BinRead;
    let parsed = RxMessageParsed::new(*m);
    let node = parsed.parsed_node_id.unwrap_or(0);
    let data = m.data.get(..m.dlc).unwrap_or(&[]);
    let mut cursor = Cursor::new(data);
    Ok(match parsed.parsed_type {
        RxMessageType::SdoTx => Oze::SdoResponse(node, BinRead::read_le(&mut cursor)?),
        RxMessageType::SdoRx => Oze::SdoRequest(node, BinRead::read_le(&mut cursor)?),
        RxMessageType::Emcy => Oze::Emcy(node, BinRead::read_le(&mut cursor)?),
        RxMessageType::Nmt => Oze::Nmt(BinRead::read_le(&mut cursor)?),
        _ => Oze::Parsed(parsed),
    })
}

/// One mapping entry: (index, sub-index, bits).
pub type Entry = (u16, u8, u8);

/// The capture's PDO mapping (tests/data/CAPTURES.md; padding as CiA 301
/// dummy entries 0005h UNSIGNED8 / 0006h UNSIGNED16): (COB-ID, entries as
/// (index, sub-index, bits)). 0x28A's layout is not published: it is
/// decoded, not unpacked.
pub const CAPTURE_MAPPING: &[(u16, &[Entry])] = &[
    (
        0x18A,
        &[
            (0x2002, 0, 16),
            (0x2101, 0, 16),
            (0x2006, 0, 16),
            (0x0006, 0, 16),
        ],
    ),
    (
        0x38A,
        &[
            (0x2060, 0, 32),
            (0x2200, 0, 16),
            (0x6080, 0, 8),
            (0x0005, 0, 8),
        ],
    ),
    (
        0x20A,
        &[
            (0x2FFA, 1, 8),
            (0x6081, 0, 8),
            (0x4201, 0, 8),
            (0x2276, 0, 16),
            (0x6070, 0, 16),
            (0x6000, 0, 8),
        ],
    ),
    (
        0x30A,
        &[
            (0x2FFA, 1, 8),
            (0x2FFA, 1, 8),
            (0x2002, 0, 16),
            (0x2101, 0, 16),
            (0x6010, 0, 16),
        ],
    ),
];

/// The capture mapping as our `PdoMapping`s, by COB-ID: see [`our_mapping`].
pub struct OurMappings(Vec<(u16, PdoMapping)>);

impl OurMappings {
    /// The capture mapping as our `PdoMapping`s.
    pub fn new() -> Self {
        OurMappings(
            CAPTURE_MAPPING
                .iter()
                .map(|(id, entries)| {
                    let e: Vec<MappingEntry> = entries
                        .iter()
                        .map(|&(i, s, b)| MappingEntry::new(i, s, b))
                        .collect();
                    (*id, PdoMapping::new(&e).expect("capture mapping"))
                })
                .collect(),
        )
    }
}

impl Default for OurMappings {
    fn default() -> Self {
        Self::new()
    }
}

/// The mapping of a COB-ID, if the capture gives one.
#[inline]
pub fn our_mapping(m: &OurMappings, cob_id: u16) -> Option<&PdoMapping> {
    m.0.iter().find(|(id, _)| *id == cob_id).map(|(_, m)| m)
}

/// canopen-codec: decode, then unpack a PDO with its mapping; returns the
/// sum of the raw field values (so nothing is optimised away).
#[inline(never)]
pub fn ours_pdo(m: &OurMappings, f: &CanFrame) -> u64 {
    match Message::decode(f) {
        Ok(Message::Tpdo { payload, .. } | Message::Rpdo { payload, .. }) => {
            let Some(mapping) = our_mapping(m, f.id().raw() as u16) else {
                return 0;
            };
            match mapping.unpack(payload.as_slice()) {
                Ok(u) => u.raws().iter().sum(),
                Err(_) => 0,
            }
        }
        _ => 0,
    }
}

/// canopen-rs's dictionary for its PDO unpack: every mapped object.
pub type CanopenRsOd = canopen_rs::ObjectDictionary<32>;

/// canopen-rs's mappings and dictionary for the capture.
pub struct CanopenRsPdo {
    mappings: Vec<(u16, canopen_rs::PdoMapping<8>)>,
    /// The dictionary the PDOs are unpacked into.
    pub od: CanopenRsOd,
}

impl CanopenRsPdo {
    /// The capture mapping and a dictionary holding each mapped object.
    pub fn new() -> Self {
        use canopen_rs::{Address, Entry, Value};
        let mut od = CanopenRsOd::new();
        let mut mappings = Vec::new();
        for (id, entries) in CAPTURE_MAPPING {
            let mut m = canopen_rs::PdoMapping::<8>::default();
            for &(i, s, b) in *entries {
                m.push(canopen_rs::MappingEntry::new(i, s, b))
                    .expect("mapping fits");
                let v = match b {
                    8 => Value::Unsigned8(0),
                    16 => Value::Unsigned16(0),
                    _ => Value::Unsigned32(0),
                };
                let addr = Address::new(i, s);
                if od.entry(addr).is_none() {
                    od.insert(addr, Entry::rw(v)).expect("dictionary fits");
                }
            }
            mappings.push((*id, m));
        }
        CanopenRsPdo { mappings, od }
    }
}

impl Default for CanopenRsPdo {
    fn default() -> Self {
        Self::new()
    }
}

/// canopen-rs: the COB-ID switch, then `pdo::unpack` into its dictionary.
#[inline(never)]
pub fn canopen_rs_pdo(p: &mut CanopenRsPdo, f: &RawFrame) -> u64 {
    let Ok(CanopenRs::Pdo(data)) = canopen_rs(f) else {
        return 0;
    };
    let Some((_, m)) = p.mappings.iter().find(|(id, _)| *id == f.cob_id) else {
        return 0;
    };
    u64::from(canopen_rs::pdo::unpack(m, &mut p.od, data).is_ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_have_the_issue_sizes() {
        let s = Streams::load();
        assert_eq!(s.sdo_upload.len(), 288);
        if s.real {
            assert_eq!(s.mixed.len(), 1387);
            assert_eq!(s.heartbeats.len(), 590);
        }
        for f in &s.sdo_upload.ours {
            assert!(ours(f).is_ok(), "{f}");
            assert!(canopen_rs(&RawFrame::from(f)).is_ok(), "{f}");
        }
    }

    #[test]
    fn every_peer_decodes_the_upload_and_the_heartbeats() {
        let s = Streams::load();
        for st in [&s.sdo_upload, &s.heartbeats] {
            for ((z, o), f) in st.zencan.iter().zip(&st.oze).zip(&st.ours) {
                assert!(zencan(z).is_ok(), "zencan {f}");
                assert!(oze(o).is_ok(), "oze {f}");
            }
        }
    }

    #[test]
    fn both_pdo_unpacks_see_the_same_frames() {
        let s = Streams::load();
        let ours_m = OurMappings::new();
        let mut theirs = CanopenRsPdo::new();
        let mut n_ours = 0;
        let mut n_theirs = 0;
        for (f, r) in s.mixed.ours.iter().zip(&s.mixed.canopen_rs) {
            if our_mapping(&ours_m, r.cob_id).is_some() {
                n_ours += u64::from(ours_pdo(&ours_m, f) > 0 || f.data().len() == 8);
                n_theirs += canopen_rs_pdo(&mut theirs, r);
            }
        }
        assert!(n_ours > 0);
        assert_eq!(n_ours, n_theirs);
    }
}
