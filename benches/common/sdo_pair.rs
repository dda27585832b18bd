//! The in-memory SDO client/server pair of the `sdo` bench and the
//! `sdo_count` profiling harness, on the library's simulated bus
//! (`canopen_codec::sim::bus::Bus`, no latency, no log): one 1000-byte
//! domain at 2000h:00 in a fixed buffer (no allocation in the loop once
//! the bus's queues have grown to a transfer's size); the `sdo` bench's
//! 64 KiB domain is the same dictionary over a `Vec`.

use std::hint::black_box;
use std::time::Duration;

use canopen_codec::od::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use canopen_codec::sdo::{AbortCode, Client, ClientConfig, ClientEvent, Server, ServerConfig};
use canopen_codec::sim::bus::{Bus, Handle};
use canopen_codec::{NodeId, Timestamp};

/// Bytes of the value.
pub const LEN: usize = 1000;
/// Segments of one transfer of it.
pub const SEGMENTS: u64 = LEN.div_ceil(7) as u64;

/// The value the client downloads.
pub static DATA: [u8; LEN] = [0xA5; LEN];

/// One domain at 2000h:00 held in `B` (an array, or a `Vec` allocated
/// once before the loop), as long as its buffer at most.
pub struct DomainOd<B> {
    value: B,
    /// Bytes of the value (set by a completed download).
    pub len: usize,
}

impl<B> DomainOd<B> {
    /// A domain in `value`, `len` bytes of it set.
    pub fn new(value: B, len: usize) -> Self {
        DomainOd { value, len }
    }
}

/// The 1000-byte domain of [`pair`].
pub type FixedOd = DomainOd<[u8; LEN]>;

impl<B: AsRef<[u8]> + AsMut<[u8]>> ObjectDictionary for DomainOd<B> {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        if (index, sub) != (0x2000, 0) {
            return Err(AbortCode::ObjectDoesNotExist);
        }
        Ok(ObjectInfo {
            access: Access::ReadWrite,
            len: self.len,
            size: SizeRule::Variable {
                max: self.value.as_ref().len(),
            },
            pdo_mappable: false,
        })
    }
    fn read(&mut self, _: u16, _: u8, offset: usize, buf: &mut [u8]) -> Result<usize, AbortCode> {
        Ok(canopen_codec::od::read_at(
            self.value.as_ref().get(..self.len).unwrap_or(&[]),
            offset,
            buf,
        ))
    }
    fn write(&mut self, _: u16, _: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let dst = offset
            .checked_add(data.len())
            .and_then(|end| self.value.as_mut().get_mut(offset..end))
            .ok_or(AbortCode::DataTypeLengthTooHigh)?;
        dst.copy_from_slice(data);
        Ok(())
    }
    fn finish_write(&mut self, _: u16, _: u8, len: usize) -> Result<(), AbortCode> {
        self.len = len;
        Ok(())
    }
}

/// A client and the server it talks to (node 1) on a bus of their own.
pub struct Pair<B: 'static = [u8; LEN]> {
    pub bus: Bus,
    pub client: Handle<Client<&'static [u8]>>,
    pub server: Handle<Server<DomainOd<B>>>,
}

impl<B: AsRef<[u8]> + AsMut<[u8]> + 'static> Pair<B> {
    /// A fresh pair whose server holds `od`.
    pub fn new(od: DomainOd<B>) -> Self {
        let node = NodeId::new(1).expect("node 1");
        let mut bus = Bus::new(Duration::ZERO);
        bus.set_logging(false);
        let client = bus.add("client", Client::new(ClientConfig::for_server(node)));
        let server = bus.add("server", Server::new(ServerConfig::for_node(node), od));
        Pair {
            bus,
            client,
            server,
        }
    }

    /// Starts a transfer on the client at the bus's time.
    pub fn start<R>(
        &mut self,
        command: impl FnOnce(&mut Client<&'static [u8]>, Timestamp) -> R,
    ) -> R {
        let c = self.client;
        self.bus.with(c, command).expect("the client is plugged")
    }

    /// Runs the started transfer to its end (every frame delivered as soon
    /// as it is sent); returns the bytes uploaded.
    pub fn run(&mut self) -> usize {
        self.bus
            .drive_bounded(1_000_000)
            .expect("the transfer ends");
        let got = self
            .bus
            .events(self.client)
            .iter()
            .map(|(_, e)| match e {
                ClientEvent::UploadData { data, .. } => black_box(data.as_slice()).len(),
                _ => 0,
            })
            .sum();
        self.bus.clear_events();
        got
    }

    /// The server's dictionary.
    pub fn od(&self) -> &DomainOd<B> {
        self.bus
            .machine(self.server)
            .expect("the server is plugged")
            .od()
    }
}

/// A fresh pair; the server holds a 1000-byte value.
pub fn pair() -> Pair {
    Pair::new(DomainOd::new([0x5A; LEN], LEN))
}

/// One whole 1000-byte upload (initiate included).
#[inline(never)]
pub fn upload(p: &mut Pair) {
    p.start(|c, now| c.start_upload(now, 0x2000, 0))
        .expect("client idle");
    assert_eq!(p.run(), LEN);
}

/// One whole 1000-byte download (initiate included).
#[inline(never)]
pub fn download(p: &mut Pair) {
    p.start(|c, now| c.start_download(now, 0x2000, 0, &DATA[..]))
        .expect("client idle");
    p.run();
    assert_eq!(p.od().len, LEN);
}
