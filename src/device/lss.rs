//! The device core's LSS slave (CiA 305 "Layer setting services and
//! protocol"; feature `lss`): what it does is in the [device core
//! docs](super).

use super::{Device, DeviceEvent, DeviceSpec, PowerOn, Profile};
use crate::clock::Timestamp;
use crate::lss::{LssSlave, LssSlaveEvent};
use crate::machine::Machine;
use crate::nmt::{NmtSlaveEvent, ResetKind};

impl<S: DeviceSpec, const Q: usize, const T: usize, const R: usize> Device<S, Q, T, R> {
    /// A device that also carries an LSS slave (CiA 305; feature `lss`). When the slave
    /// has a node-ID it replaces `config.node`; when it has none (255),
    /// the device waits for one before it boots up (see the module docs).
    ///
    /// ```
    /// # #[cfg(feature = "alloc")] {
    /// use canopen_codec::device::{Cia301Device, DeviceConfig, ProfiledDevice};
    /// use canopen_codec::lss::{LssAddress, LssSlave, LssSlaveConfig};
    /// use canopen_codec::machine::Machine;
    /// use canopen_codec::od::MemoryDictionary;
    /// use canopen_codec::{CanFrame, NodeId, Timestamp};
    /// let lss = LssSlave::new(LssSlaveConfig::new(LssAddress::default(), None));
    /// let config = DeviceConfig::new(NodeId::MAX);
    /// let mut dev: Cia301Device<MemoryDictionary> =
    ///     ProfiledDevice::plain_with_lss(config, MemoryDictionary::new(), lss);
    /// let t = Timestamp::ZERO;
    /// dev.boot(t);
    /// assert_eq!(dev.poll_transmit(), None, "no boot-up without a node-ID");
    /// for data in [[0x04, 1, 0, 0, 0, 0, 0, 0], [0x11, 5, 0, 0, 0, 0, 0, 0], [0x04, 0, 0, 0, 0, 0, 0, 0]] {
    ///     dev.handle_frame(t, &CanFrame::standard(0x7E5, &data).unwrap());
    /// }
    /// assert_eq!(dev.poll_transmit().unwrap().to_string(), "705#00");
    /// assert_eq!(dev.poll_transmit().unwrap().to_string(), "7E4#1100000000000000");
    /// assert_eq!(dev.node(), NodeId::new(5).unwrap());
    /// # }
    /// ```
    pub fn with_lss(mut config: S::PowerOn, app: S::Objects, lss: LssSlave) -> Self {
        if let Some(node) = lss.node_id() {
            config.set_node(node);
        }
        let mut device = Self::new(config, app);
        device.lss = Some(lss);
        device
    }

    /// The LSS slave, if the device has one.
    #[must_use]
    pub const fn lss(&self) -> Option<&LssSlave> {
        self.lss.as_ref()
    }

    /// The LSS slave, to answer a store request.
    pub fn lss_mut(&mut self) -> Option<&mut LssSlave> {
        self.lss.as_mut()
    }

    /// Hands the LSS slave's events on; a not-configured node that got a
    /// node-ID resets its communication and boots up under it.
    pub(super) fn drain_lss<P: Profile<S, Q, T, R>>(&mut self, now: Timestamp, profile: &mut P) {
        while let Some(event) = self.lss.as_mut().and_then(LssSlave::poll_event) {
            self.emit(now, DeviceEvent::Lss(event), profile);
            #[cfg(feature = "store")]
            if let LssSlaveEvent::StoreRequested {
                node_id,
                bit_timing,
            } = event
            {
                self.store_lss(now, node_id, bit_timing, profile);
            }
            if event == LssSlaveEvent::ResetCommunication {
                let reset = NmtSlaveEvent::Reset(ResetKind::Communication);
                self.nmt_event(now, reset, profile);
            }
        }
    }
}
