//! The in-memory SDO client/server pair of the `sdo` bench and the
//! `sdo_count` profiling harness: one 1000-byte domain at 2000h:00 in a
//! fixed buffer (no allocation anywhere in the loop); the `sdo` bench's
//! 64 KiB domain is the same dictionary over a `Vec`.

use std::hint::black_box;

use canopen_codec::machine::Machine;
use canopen_codec::od::{Access, ObjectDictionary, ObjectInfo, SizeRule};
use canopen_codec::sdo::{AbortCode, Client, ClientConfig, ClientEvent, Server, ServerConfig};
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

/// A client and the server it talks to (node 1).
pub type Pair = (Client<&'static [u8]>, Server<FixedOd>);

/// A fresh pair; the server holds a 1000-byte value.
pub fn pair() -> Pair {
    let node = NodeId::new(1).expect("node 1");
    (
        Client::new(ClientConfig::for_server(node)),
        Server::new(
            ServerConfig::for_node(node),
            DomainOd::new([0x5A; LEN], LEN),
        ),
    )
}

/// Runs the started transfer to its end; returns the bytes uploaded.
pub fn run((client, server): &mut Pair) -> usize {
    let now = Timestamp::ZERO;
    let mut got = 0;
    while let Some(req) = client.poll_transmit() {
        server.handle_frame(now, &req);
        while server.poll_event().is_some() {}
        if let Some(resp) = server.poll_transmit() {
            client.handle_frame(now, &resp);
        }
        while let Some(e) = client.poll_event() {
            if let ClientEvent::UploadData { data, .. } = e {
                got += black_box(data.as_slice()).len();
            }
        }
    }
    got
}

/// One whole 1000-byte upload (initiate included).
#[inline(never)]
pub fn upload(p: &mut Pair) {
    p.0.start_upload(Timestamp::ZERO, 0x2000, 0)
        .expect("client idle");
    assert_eq!(run(p), LEN);
}

/// One whole 1000-byte download (initiate included).
#[inline(never)]
pub fn download(p: &mut Pair) {
    p.0.start_download(Timestamp::ZERO, 0x2000, 0, &DATA[..])
        .expect("client idle");
    run(p);
    assert_eq!(p.1.od().len, LEN);
}
