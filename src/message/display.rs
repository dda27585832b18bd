//! Human-readable forms of decoded messages, for loggers and dissectors.
//! Written with `core::fmt` only: no allocation.

use core::fmt;

use crate::bytes::InlineData;
use crate::message::Message;
use crate::nmt::NmtTarget;
use crate::od::Address;
use crate::sdo::wire::view::{BlockView, CommandView, Names, CLIENT_NAMES, SERVER_NAMES};
use crate::sdo::{
    BlockDataCommand, ClientBlockUpload, ClientCommand, InitiatePayload, Segment,
    ServerBlockDownload, ServerCommand,
};

/// Writes bytes as space-separated hex (`74 13 45`), or `-` when empty.
pub struct Hex<'a>(pub &'a [u8]);

const HEX_DIGITS: &[u8; 16] = b"0123456789ABCDEF";

impl fmt::Display for Hex<'_> {
    /// Up to 8 bytes at a time are spelled into a stack buffer and written
    /// with one `write_str` (this is on the log decoder's hot path).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("-");
        }
        for (c, chunk) in self.0.chunks(8).enumerate() {
            if c > 0 {
                f.write_str(" ")?;
            }
            let mut buf = [b' '; 24];
            let mut n = 0;
            for (i, b) in chunk.iter().enumerate() {
                let at = i * 3;
                if let Some([hi, lo]) = buf.get_mut(at..at + 2) {
                    *hi = HEX_DIGITS[usize::from(b >> 4)];
                    *lo = HEX_DIGITS[usize::from(b & 0x0F)];
                }
                n = at + 2;
            }
            // Only ASCII hex digits and spaces were written.
            f.write_str(core::str::from_utf8(buf.get(..n).unwrap_or(&[])).unwrap_or(""))?;
        }
        Ok(())
    }
}

impl<const N: usize> fmt::Display for InlineData<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        Hex(self.as_slice()).fmt(f)
    }
}

impl fmt::Display for NmtTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NmtTarget::All => f.write_str("all nodes"),
            NmtTarget::Node(n) => write!(f, "node {n}"),
            NmtTarget::Invalid(raw) => write!(f, "invalid node {raw}"),
        }
    }
}

fn payload(f: &mut fmt::Formatter<'_>, p: &InitiatePayload) -> fmt::Result {
    match p {
        InitiatePayload::Expedited {
            data,
            size_indicated: true,
        } => write!(f, "expedited {} bytes: {data}", data.len()),
        InitiatePayload::Expedited {
            data,
            size_indicated: false,
        } => write!(f, "expedited, size not indicated: {data}"),
        InitiatePayload::Segmented { size: Some(n) } => write!(f, "segmented, {n} bytes"),
        InitiatePayload::Segmented { size: None } => f.write_str("segmented, size not indicated"),
    }
}

fn segment(f: &mut fmt::Formatter<'_>, what: &str, s: &Segment) -> fmt::Result {
    write!(
        f,
        "{what} t={}, {} bytes: {}{}",
        u8::from(s.toggle),
        s.data.len(),
        s.data,
        if s.last { ", last" } else { "" }
    )
}

/// How a block initiate's CRC support flag (cc / sc) reads.
const fn yes_no(crc: bool) -> &'static str {
    if crc {
        "yes"
    } else {
        "no"
    }
}

/// The frames around a block's data, the same both ways: `initiate` and
/// `end` name them for the direction.
fn block_data(
    f: &mut fmt::Formatter<'_>,
    b: &BlockDataCommand,
    initiate: &str,
    end: &str,
) -> fmt::Result {
    match b {
        BlockDataCommand::Initiate(i) => {
            write!(f, "{initiate} {:04X}h sub {}", i.index, i.sub)?;
            if let Some(n) = i.size {
                write!(f, ", {n} bytes")?;
            }
            write!(f, ", crc {}", yes_no(i.crc))
        }
        BlockDataCommand::End { unused, crc } => {
            write!(f, "{end}, {unused} unused, crc {crc:04X}h")
        }
    }
}

/// One command of either side in words, `words` naming the side's shapes.
fn command(f: &mut fmt::Formatter<'_>, view: CommandView<'_>, words: &Names) -> fmt::Result {
    match view {
        CommandView::Segment(s) => segment(f, words.segment.text, s),
        CommandView::Toggle(t) => write!(f, "{} t={}", words.toggle.text, u8::from(t)),
        CommandView::InitiateData(at, p) => {
            write!(f, "{} {at}, ", words.initiate_data.text)?;
            payload(f, p)
        }
        CommandView::Initiate(at) => {
            let (before, after) = (words.initiate.text, words.initiate_after);
            write!(f, "{before} {at}{after}")
        }
        CommandView::Abort(at, code) => write!(f, "abort {at}: {code}"),
        CommandView::Block(b) => block(f, b),
        CommandView::Unknown(b) => write!(f, "invalid command specifier {b:02X}h"),
    }
}

/// A block transfer command in words.
fn block(f: &mut fmt::Formatter<'_>, b: BlockView<'_>) -> fmt::Result {
    match b {
        BlockView::ClientUpload(ClientBlockUpload::Initiate(i)) => write!(
            f,
            "initiate block upload {}, blksize {}, pst {}, crc {}",
            Address::new(i.index, i.sub),
            i.blksize,
            i.pst,
            yes_no(i.crc)
        ),
        BlockView::ClientUpload(ClientBlockUpload::Start) => f.write_str("block upload start"),
        BlockView::ClientUpload(ClientBlockUpload::Ack { ackseq, blksize }) => {
            write!(f, "block upload ack seq {ackseq}, blksize {blksize}")
        }
        BlockView::ClientUpload(ClientBlockUpload::End) => f.write_str("block upload end"),
        BlockView::ClientDownload(c) => {
            block_data(f, c, "initiate block download", "block download end")
        }
        BlockView::ServerDownload(ServerBlockDownload::Initiate(a)) => write!(
            f,
            "block download {} accepted, blksize {}, crc {}",
            Address::new(a.index, a.sub),
            a.blksize,
            yes_no(a.crc)
        ),
        BlockView::ServerDownload(ServerBlockDownload::Ack { ackseq, blksize }) => {
            write!(f, "block download ack seq {ackseq}, blksize {blksize}")
        }
        BlockView::ServerDownload(ServerBlockDownload::End) => {
            f.write_str("block download end acknowledged")
        }
        BlockView::ServerUpload(c) => block_data(f, c, "block upload", "block upload end"),
    }
}

impl fmt::Display for ClientCommand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        command(f, self.view(), &CLIENT_NAMES)
    }
}

impl fmt::Display for ServerCommand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        command(f, self.view(), &SERVER_NAMES)
    }
}

impl fmt::Display for Message {
    /// One line in words, e.g. `EMCY node 10: 8130h life guard error or
    /// heartbeat error, reg 01h, mfr 20 80 00 00 00`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Message::Nmt(c) => write!(f, "NMT {}, {}", c.command, c.target),
            Message::Sync(s) => match s.counter {
                Some(c) => write!(f, "SYNC counter {c}"),
                None => f.write_str("SYNC"),
            },
            Message::Emcy { node, emcy } => write!(
                f,
                "EMCY node {node}: {}, reg {:02X}h, mfr {}",
                emcy.code,
                emcy.register.bits(),
                Hex(&emcy.manufacturer)
            ),
            Message::Time(t) => write!(
                f,
                "TIME day {} since 1984-01-01, {} ms after midnight",
                t.days, t.millis
            ),
            Message::Tpdo { pdo, node, payload } => {
                write!(f, "TPDO{pdo} node {node}: {payload}")
            }
            Message::TpdoRequest { pdo, node, dlc } => {
                write!(f, "TPDO{pdo} node {node}: remote request, DLC {dlc}")
            }
            Message::Rpdo { pdo, node, payload } => {
                write!(f, "RPDO{pdo} node {node}: {payload}")
            }
            Message::SdoRequest { node, sdo } => {
                write!(f, "SDO request to node {node}: {}", sdo.command)
            }
            Message::SdoResponse { node, sdo } => {
                write!(f, "SDO response from node {node}: {}", sdo.command)
            }
            Message::Heartbeat { node, heartbeat } => {
                if heartbeat.toggle {
                    write!(
                        f,
                        "node guarding reply node {node}: {}, toggle 1",
                        heartbeat.state
                    )
                } else if heartbeat.is_boot_up() {
                    write!(f, "boot-up node {node}")
                } else {
                    write!(f, "heartbeat node {node}: {}", heartbeat.state)
                }
            }
            Message::NodeGuardRequest { node, dlc } => {
                write!(f, "node guarding request node {node}, DLC {dlc}")
            }
            Message::Lss(lss) => lss.fmt(f),
            Message::Unknown(frame) => write!(f, "unknown {frame}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{CanFrame, Message};

    fn words(id: u16, data: &[u8]) -> std::string::String {
        format!(
            "{}",
            Message::decode(&CanFrame::standard(id, data).unwrap()).unwrap()
        )
    }

    #[test]
    fn lines() {
        assert_eq!(words(0x000, &[1, 10]), "NMT start, node 10");
        assert_eq!(
            words(0x000, &[0x80, 0]),
            "NMT enter pre-operational, all nodes"
        );
        assert_eq!(
            words(0x08A, &[0x30, 0x81, 0x01, 0x20, 0x80, 0, 0, 0]),
            "EMCY node 10: 8130h life guard error or heartbeat error, reg 01h, mfr 20 80 00 00 00"
        );
        assert_eq!(words(0x70A, &[0x7F]), "heartbeat node 10: pre-operational");
        assert_eq!(words(0x701, &[0x00]), "boot-up node 1");
        assert_eq!(
            words(0x701, &[0x85]),
            "node guarding reply node 1: operational, toggle 1"
        );
        assert_eq!(words(0x18A, &[0x74, 0x13]), "TPDO0 node 10: 74 13");
        assert_eq!(words(0x20A, &[]), "RPDO0 node 10: -");
        assert_eq!(
            words(0x602, &[0x2B, 0x17, 0x10, 0, 0xA0, 0x0F, 0, 0]),
            "SDO request to node 2: initiate download 1017h sub 0, expedited 2 bytes: A0 0F"
        );
        assert_eq!(
            words(0x582, &[0x80, 0x18, 0x10, 0x01, 0x11, 0x00, 0x09, 0x06]),
            "SDO response from node 2: abort 1018h sub 1: 06090011h Sub-index does not exist"
        );
        assert_eq!(
            words(0x582, &[0x15, 0x69, 0x6E, 0x73, 0x20, 0x21, 0, 0]),
            "SDO response from node 2: upload segment t=1, 5 bytes: 69 6E 73 20 21, last"
        );
        assert_eq!(words(0x080, &[]), "SYNC");
        assert_eq!(words(0x123, &[1]), "unknown 123#01");
    }
}
