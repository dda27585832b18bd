//! The plain CiA 301 device ([`Cia301`]: the [`DeviceSpec`] of a device
//! over any dictionary) and a profile with its core as one machine
//! ([`ProfiledDevice`], made from the profile's configuration by
//! [`DeviceSetup`]).

use core::marker::PhantomData;
use core::mem::MaybeUninit;
use core::ops::Deref;

use super::{
    CommObjects, Device, DeviceConfig, DeviceEvent, DeviceSpec, PowerOn, PowerOnValues, Profile,
};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::od::ObjectDictionary;
use crate::pdo::PdoConfig;

/// The spec of a plain CiA 301 device over the dictionary `A`, reporting
/// `E` (default [`DeviceEvent`]), configured by `C` (default
/// [`DeviceConfig`]); its profile adds nothing.
pub struct Cia301<A, E = DeviceEvent, C = DeviceConfig>(PhantomData<SpecOf<A, E, C>>);

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
