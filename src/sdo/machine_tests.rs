//! The SDO client and server under the back-pressure rule of
//! [`crate::machine`]: undrained events are dropped oldest first and
//! counted, never refusing input; an undrained transmit queue keeps the
//! newest frame and counts the one it drops. No allocation needed.

use super::*;
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::{assert_quiet_until, Machine};
use crate::od::{Access, ObjectDictionary, ObjectInfo};
use crate::NodeId;

const NODE: u8 = 1;

/// Two read-write 2-byte objects, 2000h:00 and 2001h:00.
struct TwoObjects([[u8; 2]; 2]);

impl TwoObjects {
    fn slot(index: u16, sub: u8) -> Result<usize, AbortCode> {
        match (index, sub) {
            (0x2000, 0) => Ok(0),
            (0x2001, 0) => Ok(1),
            _ => Err(AbortCode::ObjectDoesNotExist),
        }
    }
}

impl ObjectDictionary for TwoObjects {
    fn info(&self, index: u16, sub: u8) -> Result<ObjectInfo, AbortCode> {
        Self::slot(index, sub).map(|_| ObjectInfo::fixed(Access::ReadWrite, 2))
    }
    fn read(
        &mut self,
        index: u16,
        sub: u8,
        offset: usize,
        buf: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let value = self
            .0
            .get(Self::slot(index, sub)?)
            .ok_or(AbortCode::GeneralError)?;
        let src = value.get(offset..).unwrap_or(&[]);
        let n = src.len().min(buf.len());
        buf[..n].copy_from_slice(&src[..n]);
        Ok(n)
    }
    fn write(&mut self, index: u16, sub: u8, offset: usize, data: &[u8]) -> Result<(), AbortCode> {
        let slot = Self::slot(index, sub)?;
        let dst = self.0[slot]
            .get_mut(offset..offset + data.len())
            .ok_or(AbortCode::DataTypeLengthTooHigh)?;
        dst.copy_from_slice(data);
        Ok(())
    }
}

fn client() -> Client<[u8; 2]> {
    Client::new(ClientConfig::for_server(NodeId::new(NODE).unwrap()))
}

fn server() -> Server<TwoObjects> {
    Server::new(
        ServerConfig::for_node(NodeId::new(NODE).unwrap()),
        TwoObjects([[0x11, 0x22], [0x33, 0x44]]),
    )
}

fn frame(id: u16, data: [u8; 8]) -> CanFrame {
    CanFrame::standard(id, &data).unwrap()
}

fn upload_request(index: u16) -> CanFrame {
    let [lo, hi] = index.to_le_bytes();
    frame(0x601, [0x40, lo, hi, 0, 0, 0, 0, 0])
}

#[test]
fn client_commands_are_never_refused_for_undrained_events() {
    let mut c = client();
    for i in 0..10u32 {
        c.start_upload(Timestamp::from_millis(u64::from(i)), 0x2000, 0)
            .unwrap();
        assert!(c.poll_transmit().is_some());
        assert!(c.abort(Timestamp::ZERO, AbortCode::Other(i)));
        assert!(c.poll_transmit().is_some());
    }
    c.start_download(Timestamp::ZERO, 0x2000, 0, [1, 2])
        .unwrap();
    assert!(c.poll_transmit().is_some());
    assert_eq!(c.events_dropped(), 6);
    for i in 6..10 {
        assert_eq!(
            c.poll_event(),
            Some(ClientEvent::Ended(TransferEnd::Aborted {
                index: 0x2000,
                sub: 0,
                code: AbortCode::Other(i),
                origin: AbortOrigin::Local
            }))
        );
    }
    assert_eq!(c.poll_event(), None);
    assert_eq!(c.frames_dropped(), 0);
}

#[test]
fn client_keeps_the_newest_frame_when_transmits_are_not_drained() {
    let mut c = client();
    c.start_upload(Timestamp::ZERO, 0x2000, 0).unwrap();
    assert_eq!(c.poll_timeout(), Some(Timestamp::from_millis(2000)));
    // The request is never sent; the timeout's abort replaces it.
    c.handle_timeout(Timestamp::from_millis(2000));
    assert_eq!(c.frames_dropped(), 1);
    assert_eq!(
        c.poll_transmit(),
        Some(frame(0x601, [0x80, 0x00, 0x20, 0, 0x00, 0x00, 0x04, 0x05]))
    );
    assert_eq!(c.poll_transmit(), None);
    assert_eq!(c.poll_timeout(), None);
    assert_eq!(
        c.poll_event(),
        Some(ClientEvent::Ended(TransferEnd::local_abort(
            0x2000,
            0,
            AbortCode::SdoProtocolTimedOut
        )))
    );
}

#[test]
fn server_serves_every_request_with_undrained_events() {
    let mut s = server();
    for _ in 0..10 {
        s.handle_frame(Timestamp::ZERO, &upload_request(0x2000));
        assert_eq!(
            s.poll_transmit(),
            Some(frame(0x581, [0x4B, 0x00, 0x20, 0, 0x11, 0x22, 0, 0]))
        );
    }
    assert_eq!(s.events_dropped(), 6);
    let uploaded = ServerEvent::Uploaded {
        index: 0x2000,
        sub: 0,
        len: 2,
    };
    for _ in 0..4 {
        assert_eq!(s.poll_event(), Some(uploaded));
    }
    assert_eq!(s.poll_event(), None);
    assert_eq!(s.frames_dropped(), 0);
}

#[test]
fn server_answers_the_newest_request_when_transmits_are_not_drained() {
    let mut s = server();
    s.handle_frame(Timestamp::ZERO, &upload_request(0x2000));
    s.handle_frame(Timestamp::ZERO, &upload_request(0x2001));
    assert_eq!(s.frames_dropped(), 1);
    assert_eq!(
        s.poll_transmit(),
        Some(frame(0x581, [0x4B, 0x01, 0x20, 0, 0x33, 0x44, 0, 0]))
    );
    assert_eq!(s.poll_transmit(), None);
    assert_eq!(s.events_dropped(), 0);
    assert_eq!(s.poll_event().map(|e| e.object()), Some((0x2000, 0)));
    assert_eq!(s.poll_event().map(|e| e.object()), Some((0x2001, 0)));
}

#[test]
fn server_timer_runs_with_undrained_events() {
    // A segmented download whose events are never read still times out
    // on its own deadline and sends one abort.
    let mut s = server();
    for _ in 0..5 {
        s.handle_frame(Timestamp::ZERO, &upload_request(0x2000));
        let _ = s.poll_transmit();
    }
    s.handle_frame(
        Timestamp::from_millis(10),
        &frame(0x601, [0x21, 0x01, 0x20, 0, 2, 0, 0, 0]),
    );
    assert_eq!(
        s.poll_transmit(),
        Some(frame(0x581, [0x60, 0x01, 0x20, 0, 0, 0, 0, 0]))
    );
    assert_quiet_until(&mut s, Timestamp::from_millis(2010));
    s.handle_timeout(Timestamp::from_millis(2010));
    assert_eq!(
        s.poll_transmit(),
        Some(frame(0x581, [0x80, 0x01, 0x20, 0, 0x00, 0x00, 0x04, 0x05]))
    );
    assert_eq!((s.poll_timeout(), s.is_busy()), (None, false));
    assert_eq!(s.events_dropped(), 2);
}
