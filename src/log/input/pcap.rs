//! pcap and pcapng input: the file read in blocks through
//! [`crate::trace::pcap::PcapReader`], every packet an item like a text
//! trace's line: a classic CAN frame, an unsupported one (CAN FD, CAN XL,
//! error frames, packets of another link type: one item each, never
//! silently nothing) or a malformed packet (a bad item; the read goes on).
//! An error of the file's structure is a bad item after the last packet
//! and ends the read. Memory stays bounded: one input block and the
//! reader's fixed state.

use std::io::{self, Read};
use std::vec;

use crate::trace::pcap::{Flavor, PcapError, PcapEvent, PcapReader};

use super::{read_some, At, Bad, Binary, Counted, Detail, Item, Kind};

/// The input block.
const BLOCK: usize = 64 * 1024;

/// Reads the pcap or pcapng file `input` (either, whatever `asked` says:
/// the magic number tells), handing each item to `each`.
pub(super) fn read<F: FnMut(Item<'_>) -> io::Result<()>>(
    mut input: impl Read,
    asked: Binary,
    each: &mut Counted<'_, F>,
) -> io::Result<Kind> {
    let mut reader = PcapReader::new();
    let mut block = vec![0u8; BLOCK];
    let mut packets = 0u64;
    let mut fatal = false;
    'file: loop {
        let n = read_some(&mut input, &mut block)?;
        if n == 0 {
            break;
        }
        let mut chunk = block.get(..n).unwrap_or(&[]);
        loop {
            let item = match reader.read(&mut chunk) {
                Ok(None) => break,
                Ok(Some(PcapEvent::Frame(f))) => {
                    packets += 1;
                    Item::Frame {
                        at: At::Packet(packets),
                        frame: f.trace_frame(),
                    }
                }
                Ok(Some(PcapEvent::Unsupported {
                    what,
                    link_type,
                    timestamp,
                    on_bus,
                })) => {
                    packets += 1;
                    Item::Unsupported {
                        at: At::Packet(packets),
                        what,
                        detail: Detail::LinkType(link_type),
                        timestamp,
                        on_bus,
                    }
                }
                Err(e) if e.is_fatal() => {
                    fatal = true;
                    each.give(structure(packets, e))?;
                    break 'file;
                }
                Err(e) => {
                    packets += 1;
                    Item::Bad {
                        at: At::Packet(packets),
                        why: Bad::Packet(e),
                    }
                }
            };
            each.give(item)?;
        }
    }
    if !fatal {
        if let Err(e) = reader.finish() {
            each.give(structure(packets, e))?;
        }
    }
    let binary = match reader.flavor() {
        Some(Flavor::PcapNg) => Binary::PcapNg,
        Some(Flavor::Pcap { .. }) => Binary::Pcap,
        None => asked,
    };
    Ok(Kind::Binary {
        binary,
        objects: packets,
        skipped: 0,
    })
}

/// A fatal error, after the last packet read.
fn structure<'a>(packets: u64, e: PcapError) -> Item<'a> {
    Item::Bad {
        at: At::AfterPacket(packets),
        why: Bad::Capture(e),
    }
}
