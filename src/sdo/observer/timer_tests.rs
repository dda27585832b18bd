//! The observer's timer: the earliest deadline of the open transfers,
//! each [`ObserverConfig::timeout`] after its last frame.

use super::*;

fn request(node: u16, index: u8) -> CanFrame {
    CanFrame::standard(0x600 + node, &[0x40, index, 0x10, 0, 0, 0, 0, 0]).unwrap()
}

#[test]
fn each_transfer_breaks_off_at_its_own_deadline_and_the_earliest_is_reported() {
    let t = Timestamp::from_millis;
    let mut obs: Observer = Observer::new(ObserverConfig {
        default_channels: true,
        timeout: Some(Duration::from_millis(100)),
    });
    assert_eq!(obs.poll_timeout(), None);
    obs.observe(t(10), &request(5, 0x08));
    obs.observe(t(40), &request(6, 0x09));
    while obs.poll_event().is_some() {}
    assert_eq!(obs.poll_timeout(), Some(t(110)));
    // Not before its time.
    obs.handle_timeout(t(109));
    assert_eq!((obs.poll_event(), obs.open_transfers()), (None, 2));
    // Node 5's at 110 ms; node 6's is then the earliest.
    obs.handle_timeout(t(110));
    let channel = |node| SdoChannel::default_for(NodeId::new(node).unwrap());
    match obs.poll_event() {
        Some(ObserverEvent::BrokenOff {
            transfer,
            reason: BreakReason::Timeout,
            ..
        }) => assert_eq!(transfer.channel, channel(5)),
        other => panic!("{other:?}"),
    }
    assert_eq!((obs.poll_event(), obs.open_transfers()), (None, 1));
    assert_eq!(obs.poll_timeout(), Some(t(140)));
    obs.handle_timeout(t(139));
    assert_eq!(obs.open_transfers(), 1);
    obs.handle_timeout(t(140));
    assert_eq!((obs.open_transfers(), obs.poll_timeout()), (0, None));
    assert!(obs.open_transfer(channel(6)).is_none());
}
