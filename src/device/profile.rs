//! What a device is made of ([`DeviceSpec`]: its application objects, its
//! events, its power-on configuration), what the device core reports
//! ([`DeviceEvent`]) and what a profile adds to it ([`Profile`]).

use super::{Device, PowerOn, PowerOnValues};
use crate::abort::AbortCode;
use crate::clock::Timestamp;
use crate::cob_id::PdoNumber;
use crate::emcy::{Emergency, ErrorRegister};
use crate::frame::CanFrame;
#[cfg(feature = "lss")]
use crate::lss::LssSlaveEvent;
#[cfg(feature = "guarding")]
use crate::nmt::guarding::SlaveGuardingEvent;
#[cfg(feature = "heartbeat-consumer")]
use crate::nmt::heartbeat::HeartbeatEvent;
use crate::nmt::NmtState;
use crate::od::ObjectDictionary;
use crate::pdo::RpdoError;
use crate::sdo::AbortOrigin;
use crate::sync::SyncEvent;
#[cfg(feature = "sync-time")]
use crate::time::TimeEvent;

/// The one type a [`Device`] is named by: what its application objects
/// are, what it reports and where its power-on configuration comes from.
/// A profile is usually its own spec ([`ProfiledDevice`](super::ProfiledDevice)); [`Cia301`](super::Cia301) is
/// the spec of a plain CiA 301 device over any dictionary.
///
/// ```
/// # #[cfg(feature = "alloc")] {
/// use canopen_codec::device::{DeviceConfig, DeviceEvent, DeviceSpec, Profile, ProfiledDevice};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::od::MemoryDictionary;
/// use canopen_codec::{NodeId, Timestamp};
///
/// /// A profile of one's own: the core's behaviour, its own name.
/// #[derive(Debug, Default)]
/// struct Logger;
///
/// impl DeviceSpec for Logger {
///     type Objects = MemoryDictionary;
///     type Event = DeviceEvent;
///     type PowerOn = DeviceConfig;
/// }
/// impl Profile<Logger> for Logger {}
///
/// let config = DeviceConfig::new(NodeId::new(7).unwrap());
/// let mut node: ProfiledDevice<Logger> =
///     ProfiledDevice::from_parts(canopen_codec::device::Device::new(config, MemoryDictionary::new()), Logger);
/// node.boot(Timestamp::ZERO);
/// assert_eq!(node.poll_transmit().unwrap().to_string(), "707#00");
/// assert_eq!(node.node().raw(), 7); // the core's getters, through `Deref`
/// # }
/// ```
pub trait DeviceSpec {
    /// The application's dictionary (what reset node restores of it is its
    /// [`PowerOnValues`]).
    type Objects: ObjectDictionary + PowerOnValues + core::fmt::Debug;
    /// What the device reports: the core's [`DeviceEvent`]s and the
    /// profile's own.
    type Event: Copy + From<DeviceEvent> + core::fmt::Debug;
    /// What the power-on configuration is made from ([`PowerOn`]).
    type PowerOn: PowerOn + core::fmt::Debug;
}

/// What the device core reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DeviceEvent {
    /// The NMT state changed (boot, NMT command or reset).
    NmtStateChanged {
        /// The state before ([`NmtState::BootUp`] before the first boot).
        from: NmtState,
        /// The new state.
        to: NmtState,
    },
    /// An NMT reset was executed: reported once the objects are restored
    /// and the boot-up message is queued, before the state change to
    /// pre-operational.
    Reset {
        /// `true` for reset node (81h: the communication objects and the
        /// application's [`PowerOnValues`](super::PowerOnValues) restored), `false` for
        /// reset communication (82h: the communication objects restored).
        node: bool,
    },
    /// An SDO download to an object completed.
    ObjectWritten {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
    /// An RPDO was written into the objects.
    RpdoReceived {
        /// The RPDO number (from 0).
        pdo: PdoNumber,
    },
    /// An RPDO was not (fully) processed.
    RpdoRefused {
        /// The RPDO number (from 0).
        pdo: PdoNumber,
        /// Why.
        error: RpdoError,
    },
    /// An SDO transfer ended in an abort.
    SdoAborted {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// The abort code.
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
    /// The heartbeat consumer (1016h) reported something. Feature
    /// `heartbeat-consumer`.
    #[cfg(feature = "heartbeat-consumer")]
    Heartbeat(HeartbeatEvent),
    /// The device's LSS slave ([`Device::with_lss`]) reported something
    /// (a store request is answered with
    /// [`LssSlave::answer_store`](crate::lss::LssSlave::answer_store) on
    /// [`Device::lss_mut`]). Feature `lss`.
    #[cfg(feature = "lss")]
    Lss(LssSlaveEvent),
    /// Life guarding (100Ch, 100Dh): the master stopped guarding, or
    /// resumed. Feature `guarding`.
    #[cfg(feature = "guarding")]
    LifeGuarding(SlaveGuardingEvent),
    /// The SYNC consumer: a counter skip (1019h) or a synchronous RPDO
    /// outside the window (1007h). A SYNC itself is not reported.
    Sync(SyncEvent),
    /// TIME received (1012h consume bit). Feature `sync-time`.
    #[cfg(feature = "sync-time")]
    Time(TimeEvent),
    /// Store and restore (1010h, 1011h, the LSS store configuration): a
    /// record stored, erased, loaded or ignored, a storage that failed.
    /// Feature `store`.
    #[cfg(feature = "store")]
    Storage(crate::device::StorageEvent),
}

/// What a profile adds to the device core of spec `S` (usually the
/// profile itself, [`ProfiledDevice`](super::ProfiledDevice)). Every
/// method has a default that does nothing more than the core, so
/// [`Cia301`](super::Cia301) is the profile of a plain CiA 301 device. `Q` is the device's queue
/// capacity, `T` and `R` its TPDO and RPDO counts (see [`Device`]).
pub trait Profile<
    S: DeviceSpec,
    const Q: usize = { super::DEFAULT_QUEUE_CAPACITY },
    const T: usize = 4,
    const R: usize = 4,
>
{
    /// Power-on ([`ProfiledDevice::boot`](super::ProfiledDevice::boot)):
    /// the default boots the core ([`Device::boot`]); a profile that
    /// starts itself does more here.
    fn boot(&mut self, device: &mut Device<S, Q, T, R>, now: Timestamp)
    where
        Self: Sized,
    {
        device.boot(now, self);
    }

    /// Whether a core event goes to the application's queue (default: all;
    /// a profile that reports an event in its own words drops it here).
    fn keep_event(&self, event: &DeviceEvent) -> bool {
        let _ = event;
        true
    }

    /// A core event happened (after it was queued, if kept). The profile
    /// may act on the device here, including
    /// [`Device::set_nmt_state`](super::Device::set_nmt_state), which reports
    /// its state change through this method again: a profile must not
    /// change the state on every state change (that would never end).
    fn on_event(&mut self, device: &mut Device<S, Q, T, R>, now: Timestamp, event: &DeviceEvent) {
        let _ = (device, now, event);
    }

    /// Every received frame while the device runs, after the core.
    fn on_frame(&mut self, device: &mut Device<S, Q, T, R>, now: Timestamp, frame: &CanFrame) {
        let _ = (device, now, frame);
    }

    /// Time has passed (after the core's own timers).
    fn on_timeout(&mut self, device: &mut Device<S, Q, T, R>, now: Timestamp) {
        let _ = (device, now);
    }

    /// The profile's own frames (sent after the SDO server's, before TPDOs).
    fn poll_transmit(&mut self) -> Option<CanFrame> {
        None
    }

    /// The profile's own earliest deadline.
    fn poll_timeout(&self) -> Option<Timestamp> {
        None
    }

    /// The EMCY for a refused RPDO (none: no EMCY). The default is CiA 301's
    /// 8210h "PDO not processed due to length error" for a short payload,
    /// with the error register plus the generic and communication bits (not
    /// latched into 1001h).
    fn rpdo_emergency(&self, register: ErrorRegister, error: &RpdoError) -> Option<Emergency> {
        error.emcy_code().map(|code| Emergency {
            code,
            register: register | ErrorRegister::GENERIC | ErrorRegister::COMMUNICATION,
            manufacturer: [0; 5],
        })
    }
}
