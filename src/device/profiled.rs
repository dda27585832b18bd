//! The plain CiA 301 device ([`Cia301`]: the [`DeviceSpec`] of a device
//! over any dictionary) and a profile with its core as one machine
//! ([`ProfiledDevice`], made from the profile's configuration by
//! [`DeviceSetup`]).

use core::marker::PhantomData;
use core::mem::MaybeUninit;
use core::ops::{Deref, DerefMut};

use super::{
    CommObjects, Device, DeviceConfig, DeviceEvent, DeviceSpec, PowerOn, PowerOnValues, Profile,
};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::od::ObjectDictionary;
use crate::pdo::PdoConfig;

/// The spec and the profile of a plain CiA 301 device over the dictionary
/// `A`, reporting `E` (default [`DeviceEvent`]), configured by `C`
/// (default [`DeviceConfig`]); as a profile it adds nothing to the core.
/// The device is [`Cia301Device`].
pub struct Cia301<A, E = DeviceEvent, C = DeviceConfig>(PhantomData<SpecOf<A, E, C>>);

impl<A, E, C> Cia301<A, E, C> {
    /// The profile that adds nothing.
    #[must_use]
    pub const fn new() -> Self {
        Cia301(PhantomData)
    }
}

impl<A, E, C> Default for Cia301<A, E, C> {
    fn default() -> Self {
        Self::new()
    }
}

impl<A, E, C> core::fmt::Debug for Cia301<A, E, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Cia301")
    }
}

/// A plain CiA 301 device over the dictionary `A` (its profile
/// [`Cia301`] adds nothing): made by [`ProfiledDevice::plain`], driven as
/// every device is, through [`Machine`].
///
/// ```
/// # #[cfg(feature = "alloc")] {
/// use canopen_codec::device::{Cia301Device, DeviceConfig, ProfiledDevice};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::od::MemoryDictionary;
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// let config = DeviceConfig::new(NodeId::new(3).unwrap());
/// let mut dev: Cia301Device<MemoryDictionary> = ProfiledDevice::plain(config, MemoryDictionary::new());
/// dev.boot(Timestamp::ZERO);
/// assert_eq!(dev.poll_transmit().unwrap().to_string(), "703#00");
/// // An SDO upload of 1017h: 1000 ms.
/// dev.handle_frame(Timestamp::ZERO, &CanFrame::standard(0x603, &[0x40, 0x17, 0x10, 0, 0, 0, 0, 0]).unwrap());
/// assert_eq!(dev.poll_transmit().unwrap().to_string(), "583#4B171000E8030000");
/// # }
/// ```
pub type Cia301Device<
    A,
    const Q: usize = { super::DEFAULT_QUEUE_CAPACITY },
    const T: usize = 4,
    const R: usize = 4,
> = ProfiledDevice<Cia301<A>, Q, T, R>;

impl<A, E, C, const Q: usize, const T: usize, const R: usize> Profile<Cia301<A, E, C>, Q, T, R>
    for Cia301<A, E, C>
where
    A: ObjectDictionary + PowerOnValues + core::fmt::Debug,
    E: Copy + From<DeviceEvent> + core::fmt::Debug,
    C: PowerOn + core::fmt::Debug,
{
}

impl<A, E, C, const Q: usize, const T: usize, const R: usize>
    ProfiledDevice<Cia301<A, E, C>, Q, T, R>
where
    A: ObjectDictionary + PowerOnValues + core::fmt::Debug,
    E: Copy + From<DeviceEvent> + core::fmt::Debug,
    C: PowerOn + core::fmt::Debug,
{
    /// A plain CiA 301 device with `config` over the application objects
    /// `app`, not yet booted (call [`boot`](Self::boot)).
    pub fn plain(config: C, app: A) -> Self {
        ProfiledDevice {
            device: Device::new(config, app),
            profile: Cia301::new(),
        }
    }

    /// [`plain`](Self::plain) built in `slot` (e.g. a firmware's static),
    /// not built elsewhere and moved.
    ///
    /// ```
    /// # #[cfg(feature = "alloc")] {
    /// use core::mem::MaybeUninit;
    /// use canopen_codec::device::{Cia301Device, DeviceConfig, ProfiledDevice};
    /// use canopen_codec::od::MemoryDictionary;
    /// use canopen_codec::NodeId;
    /// let mut slot = MaybeUninit::uninit();
    /// let config = DeviceConfig::new(NodeId::new(3).unwrap());
    /// let dev: &mut Cia301Device<MemoryDictionary> =
    ///     ProfiledDevice::plain_in(&mut slot, config, MemoryDictionary::new());
    /// assert_eq!((dev.node().raw(), dev.comm().heartbeat_ms), (3, 1000));
    /// # }
    /// ```
    pub fn plain_in(slot: &mut MaybeUninit<Self>, config: C, app: A) -> &mut Self {
        let made = slot.write(ProfiledDevice {
            device: Device::blank(config, app),
            profile: Cia301::new(),
        });
        made.device.load_power_on();
        made
    }

    /// [`plain`](Self::plain) with an LSS slave (CiA 305; see
    /// [`Device::with_lss`]). Feature `lss`.
    #[cfg(feature = "lss")]
    pub fn plain_with_lss(config: C, app: A, lss: crate::lss::LssSlave) -> Self {
        ProfiledDevice {
            device: Device::with_lss(config, app, lss),
            profile: Cia301::new(),
        }
    }
}

/// What [`Cia301`] names, without owning any of it.
type SpecOf<A, E, C> = fn() -> (A, E, C);

impl<A, E, C> DeviceSpec for Cia301<A, E, C>
where
    A: ObjectDictionary + PowerOnValues + core::fmt::Debug,
    E: Copy + From<DeviceEvent> + core::fmt::Debug,
    C: PowerOn + core::fmt::Debug,
{
    type Objects = A;
    type Event = E;
    type PowerOn = C;
}

/// How a [`ProfiledDevice`] is made from a profile's configuration (the
/// battery module's, the charger's): what the device keeps of it to
/// rebuild its power-on configuration at boot and at every reset (its
/// `Into` the [`PowerOn`]), its profile, and the constant objects written
/// once; the application objects start at their `Default`, their
/// power-on values.
pub trait DeviceSetup<P: DeviceSpec>: Copy + Into<<P as DeviceSpec>::PowerOn> {
    /// The profile.
    fn profile(&self) -> P;

    /// Writes the `const` / `ro` communication objects nothing on the bus
    /// changes (1000h, 1008h, 1018h) into `comm`, once, when the device is
    /// made: every reset keeps what they hold (default: none).
    fn write_constants(&self, comm: &mut CommObjects) {
        let _ = comm;
    }
}

/// A profile `P` on its device core, as one [`Machine`]: the core's
/// inputs and outputs with the profile's hooks, its events `P::Event`. It
/// dereferences to the core ([`Device`]) for its getters (objects,
/// communication objects, PDO configuration, NMT state, error register).
/// `Q`, `T` and `R` are the core's ([`Device`]).
#[derive(Debug)]
pub struct ProfiledDevice<
    P: DeviceSpec,
    const Q: usize = { super::DEFAULT_QUEUE_CAPACITY },
    const T: usize = 4,
    const R: usize = 4,
> {
    device: Device<P, Q, T, R>,
    profile: P,
}

impl<P, const Q: usize, const T: usize, const R: usize> ProfiledDevice<P, Q, T, R>
where
    P: DeviceSpec + Profile<P, Q, T, R>,
{
    /// The profile on `device` (not yet booted).
    pub fn from_parts(device: Device<P, Q, T, R>, profile: P) -> Self {
        ProfiledDevice { device, profile }
    }

    /// Boots the device (power-on): boot-up message, pre-operational, and
    /// whatever the profile does at boot ([`Profile::boot`]).
    pub fn boot(&mut self, now: Timestamp) {
        self.profile.boot(&mut self.device, now);
    }

    /// The device core.
    #[must_use]
    pub const fn device(&self) -> &Device<P, Q, T, R> {
        &self.device
    }

    /// The device core, mutably (e.g. to answer an LSS store request or
    /// to raise an error).
    pub fn device_mut(&mut self) -> &mut Device<P, Q, T, R> {
        &mut self.device
    }

    /// The profile.
    #[must_use]
    pub const fn profile(&self) -> &P {
        &self.profile
    }

    /// The core and the profile, both mutably (for a profile's own
    /// inputs, e.g. the charger's power stage).
    #[cfg(feature = "heartbeat-consumer")]
    pub(crate) fn parts_mut(&mut self) -> (&mut Device<P, Q, T, R>, &mut P) {
        (&mut self.device, &mut self.profile)
    }

    /// Changes application objects in `f`; mapped values that changed are
    /// events for the event-driven TPDOs.
    pub fn update(&mut self, now: Timestamp, f: impl FnOnce(&mut P::Objects)) {
        self.device.update(now, f);
    }

    /// Changes communication objects in `f` (e.g. 1017h: the heartbeat is
    /// re-armed; no SDO rules applied).
    pub fn update_comm(&mut self, now: Timestamp, f: impl FnOnce(&mut CommObjects)) {
        self.device.update_comm(now, f);
    }

    /// Changes the PDO configuration in `f` (no SDO rules applied).
    pub fn update_pdos(&mut self, now: Timestamp, f: impl FnOnce(&mut PdoConfig<T, R>)) {
        self.device.update_pdos(now, f);
    }
}

impl<P, const Q: usize, const T: usize, const R: usize> ProfiledDevice<P, Q, T, R>
where
    P: DeviceSpec + Profile<P, Q, T, R>,
    P::Objects: Default,
{
    /// The device of `setup` whose queues hold `Q` events and `Q` frames
    /// (e.g. `BatteryModule::<4>::with_queue_capacity`), not yet booted.
    #[must_use]
    pub fn with_queue_capacity(setup: impl DeviceSetup<P>) -> Self {
        let mut made = ProfiledDevice {
            device: Device::blank(setup.into(), P::Objects::default()),
            profile: setup.profile(),
        };
        made.load(&setup);
        made
    }

    /// [`with_queue_capacity`](Self::with_queue_capacity) built in `slot` (e.g. a firmware's static): the
    /// device is written there and its power-on values are loaded in
    /// place, not built elsewhere and moved.
    pub fn new_in(slot: &mut MaybeUninit<Self>, setup: impl DeviceSetup<P>) -> &mut Self {
        let made = slot.write(ProfiledDevice {
            device: Device::blank(setup.into(), P::Objects::default()),
            profile: setup.profile(),
        });
        made.load(&setup);
        made
    }

    /// Writes the constants of `setup` into the communication objects,
    /// then loads the power-on values, which may follow them (the CiA 418
    /// default PDO set follows 1000h).
    #[inline(never)]
    fn load(&mut self, setup: &impl DeviceSetup<P>) {
        setup.write_constants(self.device.comm_before_power_on());
        self.device.load_power_on();
    }
}

impl<P, const T: usize, const R: usize> ProfiledDevice<P, { super::DEFAULT_QUEUE_CAPACITY }, T, R>
where
    P: DeviceSpec + Profile<P, { super::DEFAULT_QUEUE_CAPACITY }, T, R>,
    P::Objects: Default,
{
    /// The device of `setup` (a profile's configuration) with the default
    /// queue capacity, not yet booted (call [`boot`](Self::boot)).
    #[must_use]
    pub fn new(setup: impl DeviceSetup<P>) -> Self {
        Self::with_queue_capacity(setup)
    }

    /// The device of `setup` that also carries an LSS slave (CiA 305):
    /// with a slave that has no node-ID (255) it stays silent after
    /// [`boot`](Self::boot) until an LSS master configures one (see
    /// [`Device::with_lss`]). Its 1018h identity should be the slave's LSS
    /// address. Feature `lss`.
    #[cfg(feature = "lss")]
    #[must_use]
    pub fn with_lss(setup: impl DeviceSetup<P>, lss: crate::lss::LssSlave) -> Self {
        let mut made = ProfiledDevice {
            device: Device::with_lss(setup.into(), P::Objects::default(), lss),
            profile: setup.profile(),
        };
        made.load(&setup);
        made
    }
}

impl<P: DeviceSpec, const Q: usize, const T: usize, const R: usize> Deref
    for ProfiledDevice<P, Q, T, R>
{
    type Target = Device<P, Q, T, R>;

    /// The device core, for its getters.
    fn deref(&self) -> &Self::Target {
        &self.device
    }
}

impl<P: DeviceSpec, const Q: usize, const T: usize, const R: usize> DerefMut
    for ProfiledDevice<P, Q, T, R>
{
    /// The device core, for its commands ([`Device::raise_error`],
    /// [`Device::set_storage`](super::Device::set_storage), ...); the
    /// inputs and outputs are the [`Machine`]'s.
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.device
    }
}

impl<P, const Q: usize, const T: usize, const R: usize> Machine for ProfiledDevice<P, Q, T, R>
where
    P: DeviceSpec + Profile<P, Q, T, R>,
{
    type Event = P::Event;

    fn handle_frame(&mut self, now: Timestamp, frame: &CanFrame) {
        self.device.handle_frame_with(now, frame, &mut self.profile);
    }

    fn handle_timeout(&mut self, now: Timestamp) {
        self.device.handle_timeout_with(now, &mut self.profile);
    }

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.device.poll_transmit_with(&mut self.profile)
    }

    fn poll_timeout(&self) -> Option<Timestamp> {
        self.device.poll_timeout_with(&self.profile)
    }

    fn poll_event(&mut self) -> Option<P::Event> {
        self.device.events.pop()
    }

    fn events_dropped(&self) -> u64 {
        self.device.events.dropped()
    }

    fn frames_dropped(&self) -> u64 {
        self.device.transmit.dropped()
    }
}
