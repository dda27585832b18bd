//! Proves the decode/encode paths never touch the heap.
//!
//! The binary's counting `#[global_allocator]` (`counting`) wraps `System`
//! and counts, per thread, every `alloc`, `alloc_zeroed` and `realloc`. Each case in [`CASES`] runs
//! between two readings of the calling thread's counter, after its inputs
//! (the parsed captures, the hand-made frames) are built, so only the codec
//! calls themselves are measured. The counter is thread-local, so the test
//! harness's other threads cannot disturb it.
//!
//! To cover another codec, add one line to [`CASES`]:
//!
//! ```text
//! ("cia418 packed string", |fx| { black_box(PackedString::decode(black_box(&fx.bytes))); }),
//! ```

use crate::common;
use crate::counting::allocations;

use std::hint::black_box;
use std::path::Path;

use canopen_codec::cob_id::{classify, classify_standard};
use canopen_codec::emcy::{Emergency, ErrorCode, ErrorFieldEntry};
use canopen_codec::machine::Machine;
use canopen_codec::nmt::{Heartbeat, NmtCommand};
use canopen_codec::od::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use canopen_codec::sdo::{
    AbortCode, ClientCommand, InitiatePayload, SdoRequest, SdoResponse, ServerCommand,
    ALL_ABORT_CODES,
};
use canopen_codec::sdo::{Client, ClientConfig, ClientError, Server, ServerConfig};
use canopen_codec::sync::SyncMessage;
use canopen_codec::time::TimeOfDay;
use canopen_codec::{cia418, deltaq};
use canopen_codec::{CanFrame, CanId, Codec, Message, NodeId, Timestamp};
use core::fmt::Write as _;

/// A `fmt::Write` that discards: formats without a `String`.
struct Sink;
impl core::fmt::Write for Sink {
    fn write_str(&mut self, _: &str) -> core::fmt::Result {
        Ok(())
    }
}

/// One 100-byte domain at 2000h:00 in a fixed buffer: an object dictionary
/// that does not allocate, so the SDO state machines can be measured alone.
struct FixedOd {
    value: [u8; 100],
    len: usize,
}

impl ObjectDictionary for FixedOd {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        if (index, sub) != (0x2000, 0) {
            return Err(AbortCode::ObjectDoesNotExist);
        }
        Ok(ObjectInfo {
            access: Access::ReadWrite,
            len: self.len,
            size: SizeRule::Variable { max: 100 },
            pdo_mappable: false,
        })
    }
    fn read(&mut self, _: u16, _: u8, offset: usize, buf: &mut [u8]) -> Result<usize, AbortCode> {
        let src = self.value.get(offset..self.len).unwrap_or(&[]);
        let n = src.len().min(buf.len());
        buf[..n].copy_from_slice(&src[..n]);
        Ok(n)
    }
    fn write(&mut self, _: u16, _: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let dst = self
            .value
            .get_mut(offset..offset + data.len())
            .ok_or(AbortCode::DataTypeLengthTooHigh)?;
        dst.copy_from_slice(data);
        Ok(())
    }
    fn finish_write(&mut self, _: u16, _: u8, len: usize) -> Result<(), AbortCode> {
        self.len = len;
        Ok(())
    }
}

static SDO_VALUE: [u8; 100] = [0x5A; 100];

/// Runs one started transfer between `client` and `server` to its end,
/// including a timeout of a second, stalled transfer.
fn sdo_round(client: &mut Client<&'static [u8]>, server: &mut Server<FixedOd>) {
    let now = Timestamp::from_millis(1);
    while let Some(req) = client.poll_transmit() {
        server.handle_frame(now, &req);
        while black_box(server.poll_event()).is_some() {}
        while let Some(resp) = server.poll_transmit() {
            client.handle_frame(now, &resp);
        }
        while black_box(client.poll_event()).is_some() {}
    }
}

/// How many allocations `f` made on this thread.
fn count(f: impl FnOnce()) -> u64 {
    let before = allocations();
    f();
    allocations() - before
}

// ---------------------------------------------------------------------------
// Inputs, built before any measurement.

struct Fixtures {
    /// Every frame of our own logs and of both real captures (when present).
    captures: Vec<CanFrame>,
    /// Hand-made frames covering every other decoder path, good and bad.
    crafted: Vec<CanFrame>,
    /// Every frame that decodes, decoded.
    messages: Vec<Message>,
    /// Raw SDO payloads (0..=8 bytes), requests and responses alike.
    sdo_payloads: Vec<Vec<u8>>,
    /// Typed SDO commands built with `new`.
    client_commands: Vec<ClientCommand>,
    server_commands: Vec<ServerCommand>,
}

fn parse_candump_line(line: &str) -> Option<CanFrame> {
    let (id, data) = line.split_whitespace().nth(2)?.split_once('#')?;
    let raw = u32::from_str_radix(id, 16).ok()?;
    let id = match id.len() {
        3 => CanId::standard(u16::try_from(raw).ok()?)?,
        8 => CanId::extended(raw)?,
        _ => return None,
    };
    if let Some(dlc) = data.strip_prefix('R') {
        return CanFrame::remote(id, if dlc.is_empty() { 0 } else { dlc.parse().ok()? }).ok();
    }
    let bytes = (0..data.len() / 2)
        .map(|i| u8::from_str_radix(data.get(2 * i..2 * i + 2)?, 16).ok())
        .collect::<Option<Vec<u8>>>()?;
    CanFrame::new(id, &bytes).ok()
}

fn fixtures() -> Fixtures {
    // Our own logs always; the real captures too when the shared data
    // folder is beside the checkout.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data");
    let mut logs = vec![
        root.join("virtual-session.log"),
        root.join("sdo-sample.log"),
    ];
    logs.extend(
        [common::captures::STARTUP, common::captures::CHARGING]
            .into_iter()
            .filter_map(common::captures::path),
    );
    let mut captures = Vec::new();
    for path in logs {
        let text = std::fs::read_to_string(&path).expect("log file");
        let before = captures.len();
        captures.extend(text.lines().filter_map(parse_candump_line));
        assert!(captures.len() > before, "no frames in {}", path.display());
    }

    let std = |id: u16, data: &[u8]| CanFrame::standard(id, data).unwrap();
    let sdo_payloads: Vec<Vec<u8>> = vec![
        vec![0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0], // initiate upload 1018h/1
        vec![0x43, 0x18, 0x10, 0x01, 1, 2, 3, 4], // expedited, 4 bytes
        vec![0x4F, 0x00, 0x14, 0x02, 0xFE],       // python-canopen's DLC 5
        vec![0x42, 0x00, 0x10, 0x00, 1, 2, 3, 4], // expedited, size not indicated
        vec![0x41, 0x08, 0x10, 0x00, 0x20, 0, 0, 0], // segmented, size 32
        vec![0x23, 0x17, 0x10, 0x00, 0xE8, 0x03, 0, 0], // download 1017h
        vec![0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0], // download response
        vec![0x00, b'I', b'C', b'L', b'1', b'5', b'0', b'0'], // segment
        vec![0x1B, b'0', b'0', 0, 0, 0, 0, 0],    // last segment, toggle
        vec![0x60, 0, 0, 0, 0, 0, 0, 0],          // upload segment request
        vec![0x80, 0x00, 0x20, 0x00, 0x00, 0x00, 0x02, 0x06], // abort
        vec![0xA4, 0x00, 0x20, 0x00, 0x7F, 0x00, 0, 0], // block upload initiate
        vec![0xA3, 0, 0, 0, 0, 0, 0, 0],          // block start / unknown
        vec![0xA2, 0x7F, 0x7F, 0, 0, 0, 0, 0],    // block ack
        vec![0xA1, 0, 0, 0, 0, 0, 0, 0],          // block end
        vec![0xC6, 0x00, 0x20, 0x00, 0x00, 0x01, 0, 0], // block download initiate
        vec![0xC9, 0x34, 0x12, 0, 0, 0, 0, 0],    // block end with CRC
        vec![0xE5, 1, 2, 3, 4, 5, 6, 7],          // unknown specifier
        vec![],                                   // truncated
        vec![0x40, 0x00],                         // truncated multiplexer
        vec![0x80, 0x00, 0x20, 0x00],             // truncated abort
    ];
    let mut crafted = vec![
        std(0x000, &[0x01, 0x0A]),
        std(0x000, &[0x82, 0x00]),
        std(0x000, &[0x01]), // truncated NMT
        std(0x080, &[]),
        std(0x080, &[7]),
        std(0x080, &[1, 2]), // too long SYNC
        std(0x100, &[0x00, 0x2E, 0x93, 0x02, 0x02, 0x00]),
        std(0x100, &[0xFF; 5]), // truncated TIME
        std(0x08A, &[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]),
        std(0x081, &[0x00, 0x00, 0x00, 0, 0, 0, 0, 0]),
        std(0x081, &[0x10, 0x90]), // truncated EMCY
        std(0x701, &[0x00]),
        std(0x701, &[0x85]),
        std(0x701, &[]), // truncated heartbeat
        std(0x7E5, &[0x04, 0x01, 0, 0, 0, 0, 0, 0]),
        std(0x7E4, &[0x44, 0x01]),
        std(0x48A, &[1, 2, 3]),
        std(0x50A, &[]),
        std(0x7FF, &[1, 2, 3, 4, 5, 6, 7, 8]), // unknown
        CanFrame::remote(CanId::Standard(0x70A), 1).unwrap(),
        CanFrame::remote(CanId::Standard(0x28A), 8).unwrap(),
        CanFrame::remote(CanId::Standard(0x123), 0).unwrap(),
        CanFrame::remote(CanId::Standard(0x601), 8).unwrap(), // unexpected remote
        CanFrame::new(CanId::Extended(0x18FF_0001), &[1, 2, 3]).unwrap(),
        CanFrame::remote(CanId::Extended(0x1FFF_FFFF), 4).unwrap(),
    ];
    for payload in &sdo_payloads {
        crafted.push(std(0x60A, payload));
        crafted.push(std(0x58A, payload));
    }
    let messages = captures
        .iter()
        .chain(&crafted)
        .filter_map(|f| Message::decode(f).ok())
        .collect();

    let client_commands = vec![
        ClientCommand::InitiateUpload {
            index: 0x1018,
            sub: 1,
        },
        ClientCommand::InitiateDownload {
            index: 0x1017,
            sub: 0,
            payload: InitiatePayload::expedited(&[0xE8, 0x03]).unwrap(),
        },
        ClientCommand::UploadSegment { toggle: true },
        ClientCommand::Abort {
            index: 0x2000,
            sub: 0,
            code: AbortCode::SdoProtocolTimedOut,
        },
    ];
    let server_commands = vec![
        ServerCommand::InitiateDownload {
            index: 0x1017,
            sub: 0,
        },
        ServerCommand::InitiateUpload {
            index: 0x1018,
            sub: 1,
            payload: InitiatePayload::Segmented { size: Some(40) },
        },
        ServerCommand::DownloadSegment { toggle: false },
        ServerCommand::Unknown(0xFF),
    ];

    Fixtures {
        captures,
        crafted,
        messages,
        sdo_payloads,
        client_commands,
        server_commands,
    }
}

// ---------------------------------------------------------------------------
// The cases: one line (or one short block) per codec.

type Case = (&'static str, fn(&Fixtures));

const CASES: &[Case] = &[
    ("Message::decode (captures)", |fx| {
        for f in &fx.captures {
            let _ = black_box(Message::decode(black_box(f)));
        }
    }),
    ("Message::decode (crafted, incl. errors)", |fx| {
        for f in &fx.crafted {
            let _ = black_box(Message::decode(black_box(f)));
        }
    }),
    ("Message::encode / kind / node", |fx| {
        for m in &fx.messages {
            black_box(black_box(m).encode());
            black_box(m.kind());
            black_box(m.node());
        }
    }),
    ("Emergency::parse / emit", |fx| {
        for f in fx.captures.iter().chain(&fx.crafted) {
            if let Ok(e) = Emergency::parse(black_box(f.data())) {
                black_box(e.emit(&mut [0; 8]));
                black_box((e.is_reset(), e.code.class(), e.code.name()));
            }
        }
    }),
    ("ErrorFieldEntry", |_| {
        for raw in [0u32, 0x0180_9000, 0x2080_8130, u32::MAX] {
            let e = ErrorFieldEntry::from_u32(black_box(raw));
            black_box(e.to_u32());
            let bytes = e.to_le_bytes();
            let _ = black_box(ErrorFieldEntry::decode(black_box(&bytes)).map(|e| e.code));
            black_box(ErrorFieldEntry::decode(black_box(&bytes[..3])).is_err());
        }
    }),
    ("NmtCommand::parse / emit", |_| {
        for cs in 0..=255u8 {
            for node in [0u8, 1, 127, 128, 255] {
                let c = NmtCommand::parse(black_box(&[cs, node]));
                let _ = black_box(c.map(|c| (c.emit(&mut [0; 8]), c.to_frame())));
            }
        }
        let _ = black_box(NmtCommand::parse(black_box(&[1])));
    }),
    ("Heartbeat::parse / emit", |_| {
        for b in 0..=255u8 {
            let _ = black_box(Heartbeat::parse(black_box(&[b])).map(|h| h.emit(&mut [0; 8])));
        }
        let _ = black_box(Heartbeat::parse(black_box(&[])));
    }),
    ("SyncMessage::parse / emit", |_| {
        for data in [&[][..], &[1], &[240], &[1, 2]] {
            let _ = black_box(SyncMessage::parse(black_box(data)).map(|s| s.emit(&mut [0; 8])));
        }
    }),
    ("TimeOfDay::parse / emit / unix", |_| {
        for data in [[0u8; 6], [0xFF; 6], [0x00, 0x2E, 0x93, 0x02, 0x02, 0x00]] {
            let t = TimeOfDay::parse(black_box(&data));
            let _ = black_box(t.map(|t| (t.emit(&mut [0; 8]), t.unix_millis())));
        }
        black_box(TimeOfDay::from_unix_millis(black_box(1_795_305_600_001)));
        let _ = black_box(TimeOfDay::parse(black_box(&[0; 5])));
    }),
    ("SdoRequest / SdoResponse decode / encode / bytes", |fx| {
        for p in &fx.sdo_payloads {
            if let Ok(r) = SdoRequest::parse(black_box(p)) {
                black_box((r.encode(), r.bytes().len()));
            }
            if let Ok(r) = SdoResponse::parse(black_box(p)) {
                black_box((r.encode(), r.bytes().len()));
            }
            black_box(canopen_codec::sdo::abort_code_of(black_box(p)));
        }
    }),
    ("SdoRequest::new / SdoResponse::new encode", |fx| {
        for c in &fx.client_commands {
            black_box(SdoRequest::new(*black_box(c)).encode());
        }
        for c in &fx.server_commands {
            black_box(SdoResponse::new(*black_box(c)).encode());
        }
    }),
    ("AbortCode conversions", |_| {
        for code in ALL_ABORT_CODES {
            let raw = u32::from(black_box(code));
            black_box(AbortCode::from(black_box(raw)));
            black_box(code.description());
        }
        black_box(AbortCode::from(black_box(0x1234_5678)).to_u32());
    }),
    ("ErrorCode class / name", |_| {
        for raw in [0u16, 0x1000, 0x5010, 0x8130, 0xFF00, 0xFFFF] {
            let c = ErrorCode::from(black_box(raw));
            black_box((c.class(), c.name(), c.named().is_some()));
        }
    }),
    (
        "SDO client and server: segmented and expedited, both ways, timeouts",
        |_| {
            let node = NodeId::new(1).unwrap();
            let mut client: Client<&'static [u8]> = Client::new(ClientConfig::for_server(node));
            let mut server = Server::new(
                ServerConfig::for_node(node),
                FixedOd {
                    value: [0; 100],
                    len: 0,
                },
            );
            let t = Timestamp::ZERO;
            let started = client.start_download(t, 0x2000, 0, &SDO_VALUE[..]);
            if cfg!(feature = "sdo-client-segmented") {
                started.unwrap();
                sdo_round(&mut client, &mut server);
                client.start_upload(t, 0x2000, 0).unwrap();
                sdo_round(&mut client, &mut server);
            } else {
                // Without feature `sdo-client-segmented`: expedited only.
                assert_eq!(started, Err(ClientError::SegmentedUnsupported { len: 100 }));
                assert_eq!(client.poll_transmit(), None);
            }
            client
                .start_download(t, 0x2000, 0, &SDO_VALUE[..3])
                .unwrap();
            sdo_round(&mut client, &mut server);
            client.start_upload(t, 0x3000, 0).unwrap();
            sdo_round(&mut client, &mut server);
            client.start_upload(t, 0x2000, 0).unwrap();
            let _ = client.poll_transmit();
            client.handle_timeout(Timestamp::from_millis(5000));
            while black_box(client.poll_transmit()).is_some() {}
            while black_box(client.poll_event()).is_some() {}
        },
    ),
    (
        "SDO client and server: block download and upload, CRC, timeout",
        |_| {
            let node = NodeId::new(1).unwrap();
            let mut client: Client<&'static [u8]> = Client::new(ClientConfig {
                block_size: 5,
                ..ClientConfig::for_server(node)
            });
            let mut server = Server::new(
                ServerConfig {
                    block_size: 3,
                    ..ServerConfig::for_node(node)
                },
                FixedOd {
                    value: [0; 100],
                    len: 0,
                },
            );
            let t = Timestamp::ZERO;
            let started = client.start_block_download(t, 0x2000, 0, &SDO_VALUE[..]);
            if !cfg!(feature = "sdo-block") {
                // Without feature `sdo-block` the client refuses to start.
                assert_eq!(started, Err(ClientError::BlockUnsupported));
                let started = client.start_block_upload(t, 0x2000, 0);
                assert_eq!(started, Err(ClientError::BlockUnsupported));
                assert_eq!(client.poll_transmit(), None);
                return;
            }
            started.unwrap();
            sdo_round(&mut client, &mut server);
            assert_eq!(server.od().len, 100);
            client.start_block_upload(t, 0x2000, 0).unwrap();
            sdo_round(&mut client, &mut server);
            client.start_block_upload(t, 0x3000, 0).unwrap();
            sdo_round(&mut client, &mut server);
            client.start_block_upload(t, 0x2000, 0).unwrap();
            let _ = client.poll_transmit();
            client.handle_timeout(Timestamp::from_millis(5000));
            while black_box(client.poll_transmit()).is_some() {}
            while black_box(client.poll_event()).is_some() {}
        },
    ),
    (
        "Display of messages, SDO commands, codes (into a sink)",
        |fx| {
            for m in &fx.messages {
                let _ = write!(Sink, "{m}");
            }
            for c in &fx.client_commands {
                let _ = write!(Sink, "{c}");
            }
            let _ = write!(Sink, "{} {}", ErrorCode(0x8130), AbortCode::CrcError);
        },
    ),
    ("candump::parse_line", |_| {
        for line in [
            "(1756955653.603308) can1 000#010A",
            "701#R1",
            "bad",
            "18A#7413454E70000000",
        ] {
            let _ = black_box(
                canopen_codec::trace::candump::parse_line(black_box(line)).map(|l| l.frame),
            );
        }
    }),
    (
        "cia418 packed strings, battery type, device type, date",
        |_| {
            use cia418::{
                BatteryType, CalendarDateTime, DeviceType, EqualizationDate, PackedString,
                PackedStringObject,
            };
            let p = PackedString::encode(
                PackedStringObject::BatterySerialNumber,
                black_box("BATTERY"),
            )
            .unwrap();
            let back = PackedString::decode(
                PackedStringObject::BatterySerialNumber,
                p.count(),
                p.words(),
            )
            .unwrap();
            black_box(back.text().len());
            let _ = black_box(PackedString::encode(
                PackedStringObject::BatteryId,
                black_box("caf\u{e9}"),
            ));
            for raw in 0..=255u8 {
                black_box(BatteryType::from_u8(black_box(raw)).to_u8());
            }
            let d = DeviceType::from_raw(black_box(0x000F_01A2));
            black_box((d.rpdos().len(), d.tpdos().len(), d.encode()));
            let _ = black_box(
                CalendarDateTime::new(2026, 11, 22, 10, 30)
                    .map(|c| EqualizationDate::from(c).to_calendar()),
            );
        },
    ),
    ("deltaq codes, objects, policy", |fx| {
        use deltaq::{emcy_reaction, DeltaQCode, ExtendedChargeStatus, OperatingMode};
        for f in &fx.captures {
            if let Ok(e) = Emergency::parse(f.data()) {
                let code = DeltaQCode::from_emergency(&e);
                let _ = write!(Sink, "{code}");
                black_box((code.entry(), code.to_error_field(e.code)));
                black_box(emcy_reaction(OperatingMode::Local, e.code));
            }
        }
        for raw in [0u32, 0x0180_9000, 0x06C0_5000, 0x5000_06C0] {
            black_box(DeltaQCode::from_error_field(black_box(raw)));
        }
        for raw in [0u16, 0x0070, 0xFFFF] {
            black_box(ExtendedChargeStatus::from_u16(black_box(raw)).to_u16());
        }
    }),
    #[cfg(feature = "heartbeat-consumer")]
    (
        "charger and battery module: boot, configuration, NMT start, PDOs, loss",
        |_| {
            use canopen_codec::cia418::{BatteryModule, BatteryModuleConfig};
            use canopen_codec::deltaq::{Charger, ChargerConfig};
            use canopen_codec::machine::Machine;
            let (c_node, b_node) = (NodeId::new(10).unwrap(), NodeId::new(1).unwrap());
            let mut charger = Charger::new(ChargerConfig::new(c_node, b_node));
            let mut battery = BatteryModule::new(BatteryModuleConfig::new(b_node));
            charger.boot(Timestamp::ZERO);
            battery.boot(Timestamp::ZERO);
            let start = CanFrame::standard(0x000, &[0x01, 0x00]).unwrap();
            let mut now = Timestamp::ZERO;
            for step in 0..4_500u64 {
                now = Timestamp::from_millis(step);
                if step == 100 {
                    charger.handle_frame(now, &start);
                    battery.handle_frame(now, &start);
                }
                if step < 2_000 {
                    while let Some(f) = battery.poll_transmit() {
                        charger.handle_frame(now, &f);
                    }
                }
                while let Some(f) = charger.poll_transmit() {
                    if step < 2_000 {
                        battery.handle_frame(now, &f);
                    }
                }
                charger.handle_timeout(now);
                battery.handle_timeout(now);
                while black_box(charger.poll_event()).is_some() {}
                while black_box(battery.poll_event()).is_some() {}
                if step == 1_000 {
                    assert!(charger.is_configured());
                }
            }
            assert!(
                !charger.is_configured(),
                "the module was lost at 2 s: {now}"
            );
        },
    ),
    ("cob_id::classify (every 11-bit id, some 29-bit)", |_| {
        for raw in 0..=0x7FFu16 {
            let kind = classify_standard(black_box(raw));
            black_box((kind.cob_id(), kind.node()));
            black_box(classify(CanId::Standard(raw)));
        }
        for raw in [0u32, 0x181, 0x1FFF_FFFF] {
            black_box(classify(CanId::Extended(black_box(raw))));
        }
    }),
    (
        "pdo pack / unpack (Delta-Q TPDO 3 typed, P2, errors)",
        |_| {
            use canopen_codec::pdo::{FieldKind, MappingEntry as E, PdoMapping, Value};
            use deltaq::{BatteryVoltageLegacy, ChargingCurrent, ExtendedChargeStatus};
            let m = PdoMapping::new(&[
                E::new(0x2002, 0, 16),
                E::new(0x2100, 0, 16),
                E::new(0x2006, 0, 16),
            ])
            .unwrap();
            for data in [
                &[0x74, 0x13, 0x45, 0x4E, 0x70, 0x00][..],
                &[0x74; 8],
                &[0x74; 5],
            ] {
                if let Ok(u) = m.unpack(black_box(data)) {
                    let raw16 = |i| u.raw(i).and_then(|r| u16::try_from(r).ok()).unwrap_or(0);
                    black_box((
                        ChargingCurrent::from_raw(raw16(0)),
                        BatteryVoltageLegacy::from_raw(raw16(1)),
                    ));
                    let _ = black_box((
                        ExtendedChargeStatus::from_u16(raw16(2)),
                        u.emcy_code(),
                        m.pack_raw(u.raws()),
                    ));
                }
            }
            let p2 = PdoMapping::new(&[4, 8, 24, 12, 3, 13].map(|b| E::new(0x2000, 1, b))).unwrap();
            let v = [
                Value::Unsigned(3),
                Value::Signed(-2),
                Value::Unsigned(0x98_7654),
                Value::Unsigned(0x321),
                Value::Signed(-1),
                Value::Signed(-1071),
            ];
            let packed = p2.pack(black_box(&v)).unwrap();
            let u = p2.unpack(packed.as_slice()).unwrap();
            let _ = black_box((
                u.signed(5),
                u.value(2, FieldKind::Unsigned),
                u.value(2, FieldKind::Real32),
            ));
            let _ = black_box((
                p2.pack(&v[..2]),
                p2.pack_raw(&[1 << 5; 6]),
                u.iter().count(),
            ));
        },
    ),
];

#[test]
fn codecs_do_not_allocate() {
    let fx = fixtures();
    assert!(!fx.captures.is_empty() && !fx.messages.is_empty());

    // The counter must see a real allocation, or a zero below proves nothing.
    let probe = count(|| {
        black_box(Vec::<u8>::with_capacity(black_box(16)));
    });
    assert!(probe >= 1, "the counting allocator did not count a Vec");

    let failures: Vec<String> = CASES
        .iter()
        .filter_map(|(name, case)| {
            let n = count(|| case(&fx));
            (n != 0).then(|| format!("{name}: {n} allocation(s)"))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "allocations on a codec path:\n{}",
        failures.join("\n")
    );
}
