//! The charger session: a CiA 419 charger in the Delta-Q IC Series flavour
//! (Delta-Q IC Series CANopen interface specification rev 2.0, section 4)
//! as a profile on the CiA 301 device core ([`crate::device`]).
//!
//! What it adds to the core:
//!
//! - **NMT slave** with heartbeat producer (1017h, 1000 ms) and boot-up
//!   (the core's).
//!   With [`ChargerConfig::self_start`] it enters operational by itself after
//!   boot and after every NMT reset (an NMT "enter pre-operational" from
//!   the master is obeyed); otherwise it waits for an NMT start (in the
//!   real capture the BMS sends `000#010A`).
//! - **Heartbeat consumer** of the battery module (1016h, 2000 ms; the
//!   core's supervision, the charger's reaction).
//! - **PDO COB-ID configuration** (CiA 419 section 7.2; Delta-Q section 4.5.5),
//!   when [`ChargerConfig::configure_cob_ids`] is set: on finding the battery
//!   module (its first heartbeat, boot-up, or a heartbeat after a loss) the
//!   charger reads 1000h by SDO; the profile must be 418 (else
//!   [`ChargerEvent::NotABatteryModule`] and EMCY E-0-4-2). For each PDO the
//!   device type declares it reads the module's COB-ID (communication
//!   parameter sub 1) and sets its own paired PDO to the same identifier:
//!   charger TPDO 0 / RPDO 0 always (module RPDO 0 at 1400h, TPDO 0 at
//!   1800h); TPDO 1 / 2 when bits 16 / 17 say the module has RPDO 1 / 2;
//!   RPDO 1 / 2 when bits 18 / 19 say it has TPDO 1 / 2
//!   ([`crate::cia419::PDO_PAIRS`]); TPDO 3 only when Delta-Q's bit 20
//!   ([`device_type::RPDO_3`](super::device_type::RPDO_3)) asks for it. The settings are volatile. **Choice**
//!   (the documents are silent): a module COB-ID with bit 31 set ("not
//!   valid", CiA 418's TPDO default) is copied by its identifier bits and the
//!   charger's own paired PDO is enabled; enabling the module's TPDOs is the
//!   module's business. The SDO client runs only where CiA 301 allows
//!   SDO (pre-operational and operational): a module found while the
//!   charger is stopped, or a configuration that an NMT stop interrupts
//!   (silently: no abort frame in stopped), is read from 1000h again on
//!   entering pre-operational or operational; a module boot-up during
//!   the configuration restarts it. A request left unanswered (the SDO
//!   timeout: a frame lost on a lossy bus) is asked again, three requests
//!   per finding of the module; the module's abort, or a third timeout,
//!   fails the pairing ([`ChargerEvent::ConfigurationFailed`], E-0-3-0)
//!   until the module is found again. Without `configure_cob_ids` the charger uses its own
//!   default COB-IDs (18Ah, 28Ah, 38Ah, 48Ah; 20Ah, 30Ah, 40Ah), as in the
//!   real capture.
//! - **The module's battery** (6020h, CiA 418 section 7.2.1; the Delta-Q
//!   document is silent, this is ours): in local and local override mode
//!   with no permanent algorithm, once the pairing is done, the charger's
//!   SDO client reads 6020h sub 1, 2 and 4 and the charge control charges
//!   with the algorithm for that battery (the rules: docs/CHARGING.md,
//!   [`ChargerEvent::BatteryIdentified`] /
//!   [`ChargerEvent::IdentificationFailed`] the outcome).
//! - **TPDOs** are sent only while configured, NMT operational and the
//!   battery module present, at 200 ms (TPDO 0-2) and 1000 ms (TPDO 3).
//! - **Battery lost** (no heartbeat for the consumer time): EMCY 8130h with
//!   Delta-Q alarm E-0-3-2, error register 01h, as the real capture shows
//!   (`08A#3081012080000000`); the entry goes to 1003h in the Delta-Q byte
//!   order (high word = the Delta-Q code byte-swapped); TPDOs stop and the
//!   configuration is forgotten.
//! - **Battery gone** (no heartbeat for 2000 ms since the last one, the time
//!   after which Delta-Q section 4 says the charger takes the module as
//!   gone; never before the consumer time): EMCY E-0-3-0 "battery module
//!   communication error" (the capture's `08A#3081011E80000000`, 2014 ms
//!   after the last battery heartbeat where E-0-3-2 came at 342 ms) and
//!   the charger leaves operational for pre-operational, as the real
//!   charger does in the capture and as CiA 301's default error behaviour
//!   (1029h sub 1 = 0) does on a communication error
//!   ([`ChargerEvent::BatteryGone`]). A charger with
//!   [`ChargerConfig::self_start`] starts itself again when the module is
//!   back (unless the NMT master changed its state meanwhile); otherwise
//!   the NMT master does. A failed configuration (the
//!   module's SDO server aborts or does not answer) raises E-0-3-0 too.
//!   When the module is back and configured, an error-reset EMCY (code
//!   0000h) clears the error register.
//! - **EMCY consumer**: the module's EMCYs are decoded and reported with the
//!   reaction of the Delta-Q policy for the operating mode
//!   ([`crate::deltaq::emergency_reaction`]) and given to the charge
//!   control, which acts on it (terminates or shuts down the charge,
//!   derates on a temperature sensor fault).
//! - **SDO server** for the charger's own objects ([`ChargerObjects`]) and
//!   the core's communication objects, including the 1003h error history
//!   (last 10, newest first).
//! - **NMT resets** are the core's: reset node restores the communication
//!   objects and the writable [`ChargerObjects`] (the read-only ones, the
//!   charger's own readings, keep their last value:
//!   [`ChargerPowerOnValues`](super::ChargerPowerOnValues)),
//!   reset communication only the communication objects; both forget the
//!   pairing and are reported as [`DeviceEvent::Reset`].

use super::device_type;
use super::{emergency_reaction, DeltaQCode, OperatingMode, ALARMS_AND_FAULTS};
use crate::abort::AbortCode;
use crate::cia419::{PdoPair, PDO_PAIRS};
use crate::clock::{earliest, timer_kind, Timers, Timestamp};
use crate::cob_id::{NodeId, PdoNumber, EMCY_BASE};
use crate::device::{
    CommObjects, Device, DeviceEvent, DeviceSetup, DeviceSpec, Profile, ProfiledDevice,
    DEFAULT_QUEUE_CAPACITY,
};
use crate::emcy::{Emergency, ErrorCode, ErrorRegister};
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::nmt::heartbeat::HeartbeatEvent;
use crate::nmt::NmtState;
use crate::pdo::{PdoDirection, RpdoError};
use crate::sdo::{Client, ClientConfig, ClientEvent, TransferEnd, EVENTS_PER_CALL};
use crate::wire::Codec;

mod battery;
mod config;
mod control;
mod download;
mod event;
mod pairing;
use super::charge::{BatteryIdentity, ChargeControl, PowerStage, SetPoints};
pub use config::{ChargerConfig, ChargerPowerOn};
use control::ControlLink;
pub use download::ChargerAppDictionary;
pub use event::ChargerEvent;

/// Where the configuration of the PDO pairing stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Link {
    /// Module not heard, or gone.
    Absent,
    /// Heartbeat lost: the module is taken as gone when
    /// [`LinkTimer::ModuleGone`] runs out ([`MODULE_GONE_MS`] after its
    /// last heartbeat) unless it is back.
    Lost,
    /// Gone, and the charger left operational for it: a self-starting one
    /// starts itself again when the module is back, unless the NMT master
    /// has changed its state meanwhile.
    Gone,
    /// Module heard while NMT stopped (no SDO there, CiA 301): the
    /// configuration starts on entering pre-operational or operational.
    Pending,
    /// Reading 1000h.
    DeviceType,
    /// Reading the module's COB-ID of pair `i` (index into [`PAIRS`], of 7), the
    /// module's device type.
    CobId(u8, u32),
    /// Configured: TPDOs may run.
    Ready,
    /// Configuration failed (an abort, or three timeouts); waits for the
    /// module to be found again.
    Failed,
}

timer_kind! {
    /// The charger profile's own deadline (the SDO client and the charge
    /// control keep theirs).
    enum LinkTimer {
        /// The lost module is taken as gone ([`Link::Lost`]).
        ModuleGone,
    }
}

/// Delta-Q section 4: without a battery heartbeat for this long the
/// charger takes the module as gone.
const MODULE_GONE_MS: u64 = 2000;

/// The CiA 419 pairs, then Delta-Q's TPDO 3 (module RPDO 3 at 1403h).
const PAIRS: [PdoPair; 7] = {
    let [a, b, c, d, e, f] = PDO_PAIRS;
    let tpdo3 = PdoPair {
        module_comm_index: 0x1403,
        charger_direction: PdoDirection::Transmit,
        charger_pdo: PdoNumber::P3,
        device_type_bit: device_type::RPDO_3,
    };
    [a, b, c, d, e, f, tpdo3]
};

/// The charger's core: TPDO 0-3 and RPDO 0-2 (`charger_default_pdo`; no RPDO 3 is published).
pub type ChargerDevice<const Q: usize> = Device<ChargerProfile, Q, 4, 3>;

/// A Delta-Q code with the EEC its row of [`ALARMS_AND_FAULTS`] gives
/// (generic, 1000h, for a code without a row).
#[derive(Debug, Clone, Copy)]
struct Alarm(DeltaQCode, ErrorCode);

impl Alarm {
    /// Looks `code` up; meant for `const` contexts, so that firmware
    /// carries the EEC and not the table with its labels and descriptions.
    const fn of(code: DeltaQCode) -> Self {
        let mut i = 0;
        while i < ALARMS_AND_FAULTS.len() {
            let row = &ALARMS_AND_FAULTS[i];
            if row.code.raw() == code.raw() {
                return Alarm(code, row.eec);
            }
            i += 1;
        }
        Alarm(code, ErrorCode::GENERIC)
    }
}

/// SDO (server and client) runs in pre-operational and operational only
/// (CiA 301).
fn sdo_allowed<const Q: usize>(device: &ChargerDevice<Q>) -> bool {
    matches!(
        device.nmt_state(),
        NmtState::PreOperational | NmtState::Operational
    )
}

/// The Delta-Q charger's profile on the device core: its objects
/// ([`ChargerObjects`](super::ChargerObjects)), its events, its configuration and its behaviour
/// on top of the core (see the module docs).
#[derive(Debug)]
pub struct ChargerProfile {
    /// What the profile needs of the [`ChargerConfig`] (the core keeps the
    /// whole of it, [`Device::power_on`]).
    battery: NodeId,
    mode: OperatingMode,
    configure_cob_ids: bool,
    self_start: bool,
    client: Client<&'static [u8], EVENTS_PER_CALL>,
    link: Link,
    /// Its own deadline ([`LinkTimer`]).
    timers: Timers<LinkTimer, 1>,
    /// The value of the upload in progress (1000h, a COB-ID or 6020h: 4
    /// bytes at most).
    upload_value: [u8; 4],
    /// The step of the 6020h read in progress ([`battery`]), and what it
    /// has read.
    reading: Option<u8>,
    /// Reads of 6020h started for this finding of the module
    /// ([`battery::ATTEMPTS`] at most).
    attempts: u8,
    found: BatteryIdentity,
    /// The charge control and what it was last given.
    charge: ControlLink,
}

impl DeviceSpec for ChargerProfile {
    type Objects = ChargerAppDictionary;
    type Event = ChargerEvent;
    type PowerOn = ChargerPowerOn;
}

/// The charger: [`ChargerProfile`] on its device core. See the module
/// docs; it implements [`Machine`](crate::machine::Machine) and
/// dereferences to its [`Device`] core, whose getters give its objects
/// (`objects()`, `comm()` with 1001h and the 1003h history,
/// `pdo_config()`) and `nmt_state()`.
///
/// ```
/// use canopen_codec::deltaq::{Charger, ChargerConfig};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{CanFrame, NodeId, Timestamp};
/// let mut c = Charger::new(ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::new(1).unwrap()));
/// c.boot(Timestamp::ZERO);
/// assert_eq!(c.poll_transmit().unwrap().to_string(), "70A#00");
/// // The battery module's heartbeat: the charger reads its device type.
/// c.handle_frame(Timestamp::from_millis(10), &CanFrame::standard(0x701, &[0x05]).unwrap());
/// assert_eq!(c.poll_transmit().unwrap().to_string(), "601#4000100000000000");
/// ```
///
/// `Q` is the capacity of its event queue and of its queue of frames to
/// send ([`Device`]'s; default [`DEFAULT_QUEUE_CAPACITY`]): e.g.
/// `Charger::<4>::new`; the firmware builds its charger, 2 deep, in place
/// with [`ProfiledDevice::new_in`]:
///
/// ```
/// use core::mem::MaybeUninit;
/// use canopen_codec::deltaq::{Charger, ChargerConfig};
/// use canopen_codec::machine::Machine;
/// use canopen_codec::{NodeId, Timestamp};
/// let mut slot = MaybeUninit::<Charger<4>>::uninit();
/// let config = ChargerConfig::new(NodeId::new(10).unwrap(), NodeId::MIN);
/// let c = Charger::new_in(&mut slot, config);
/// c.boot(Timestamp::ZERO);
/// assert_eq!(c.poll_transmit().unwrap().to_string(), "70A#00");
/// ```
///
/// Feature `heartbeat-consumer` (the battery module's supervision).
pub type Charger<const Q: usize = DEFAULT_QUEUE_CAPACITY> = ProfiledDevice<ChargerProfile, Q, 4, 3>;

/// A charger is made from its configuration: the settings it keeps
/// ([`ChargerPowerOn`]), the Delta-Q power-on objects, its profile, and
/// 1008h written once.
impl DeviceSetup<ChargerProfile> for ChargerConfig {
    fn profile(&self) -> ChargerProfile {
        ChargerProfile::new(*self)
    }

    fn write_constants(&self, comm: &mut CommObjects) {
        comm.device_type = crate::cia419::CHARGER_DEVICE_TYPE;
        comm.device_name = self.device_name;
    }
}

impl<const Q: usize> Charger<Q> {
    /// The configuration (times in the whole milliseconds the charger
    /// keeps, [`ChargerPowerOn`]).
    #[must_use]
    pub fn config(&self) -> ChargerConfig {
        let charge = *self.profile().charge.control.config();
        self.power_on().config(self.comm(), charge)
    }

    /// True once the PDO pairing is done and the module is present.
    #[must_use]
    pub const fn is_configured(&self) -> bool {
        matches!(self.profile().link, Link::Ready)
    }

    /// The charge control: its phase, status, set points and alarms
    /// ([`crate::deltaq::charge`]).
    #[must_use]
    pub const fn charge_control(&self) -> &ChargeControl {
        &self.profile().charge.control
    }

    /// The power stage's orders: what the application sets its output to.
    #[must_use]
    pub const fn set_points(&self) -> SetPoints {
        self.profile().charge.control.set_points()
    }

    /// The power stage measured `stage` (AC, output voltage and current,
    /// temperature): the charge control runs on it, and 2002h, 2100h and
    /// 2101h report it. Call it at the application's measuring rate (the
    /// Ah returned integrate the current between calls).
    pub fn handle_power_stage(&mut self, now: Timestamp, stage: PowerStage) {
        let (device, profile) = self.parts_mut();
        profile.charge.control.handle_power_stage(now, stage);
        let linked = profile.linked();
        profile.charge.publish(device, now, linked);
    }

    /// The CAN controller reports a bus error (error passive or bus off:
    /// `true`) or is back to error active (`false`): Delta-Q E-0-2-9.
    pub fn set_bus_error(&mut self, now: Timestamp, error: bool) {
        let (device, profile) = self.parts_mut();
        profile.charge.bus_error = error;
        profile.sync_charge(device, now, false);
    }
}

impl ChargerProfile {
    fn new(config: ChargerConfig) -> Self {
        ChargerProfile {
            battery: config.battery,
            mode: config.mode,
            configure_cob_ids: config.configure_cob_ids,
            self_start: config.self_start,
            client: Self::client(&config),
            link: Link::Absent,
            timers: Timers::new(),
            upload_value: [0; 4],
            reading: None,
            attempts: 0,
            found: BatteryIdentity {
                battery_type: 0,
                capacity_ah: 0,
                cells: 0,
            },
            charge: ControlLink::new(config.mode, config.charge),
        }
    }

    /// No heartbeat or configuration error of the charger's own is
    /// pending (the error reset may go out when the charge alarms clear).
    fn linked(&self) -> bool {
        matches!(self.link, Link::Ready)
    }

    /// The charge control follows the objects and the supervision.
    fn sync_charge<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        algorithm_written: bool,
    ) {
        let linked = self.linked();
        self.charge
            .sync(device, now, self.battery, algorithm_written, linked);
    }

    fn client(config: &ChargerConfig) -> Client<&'static [u8], EVENTS_PER_CALL> {
        Client::with_event_capacity(ClientConfig {
            timeout: config.sdo_timeout,
            ..ClientConfig::for_server(config.battery)
        })
    }

    /// A fresh client of the same configuration: a transfer in progress
    /// ends silently.
    #[inline(never)]
    fn fresh_client(&mut self) {
        self.client.reset();
    }

    /// Boot or NMT reset: no transfer, no pairing.
    fn restart<const Q: usize>(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp) {
        self.fresh_client();
        self.identification_dropped(device, now);
        self.link = Link::Absent;
        self.timers.clear();
        device.set_tpdos_enabled(now, false);
    }

    /// Raises a Delta-Q alarm: EMCY with the code in the manufacturer
    /// bytes, 1001h generic bit, 1003h entry. `alarm` is an [`Alarm`]
    /// looked up at compile time.
    fn raise<const Q: usize>(device: &mut ChargerDevice<Q>, Alarm(code, eec): Alarm) {
        device.raise_error(
            ErrorRegister::GENERIC,
            code.to_emergency(eec, ErrorRegister::empty()),
        );
    }

    /// Moves the client's frames into the device's queue and handles its events.
    fn drain_client<const Q: usize>(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp) {
        while let Some(e) = self.client.poll_event() {
            match e {
                ClientEvent::UploadData { offset, data, .. } => self.on_upload_data(offset, data),
                ClientEvent::Ended(TransferEnd::Uploaded { .. }) => match self.reading {
                    Some(step) => self.on_parameter(device, now, step),
                    None => self.on_uploaded(device, now),
                },
                ClientEvent::Ended(TransferEnd::Aborted {
                    index, sub, code, ..
                }) => {
                    if self.reading.is_some() {
                        self.read_failed(device, now, sub, code);
                    } else if matches!(self.link, Link::DeviceType | Link::CobId(..)) {
                        self.pairing_aborted(device, now, index, sub, code);
                    }
                }
                _ => {}
            }
        }
    }

    /// The module heard: first heard (the callers check [`Self::absent`]),
    /// booted or back after a loss.
    fn battery_found<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        state: NmtState,
    ) {
        let left_for_it = matches!(self.link, Link::Gone);
        if !matches!(
            self.link,
            Link::Absent | Link::Lost | Link::Gone | Link::Failed
        ) {
            // A boot-up while configured: the module reset its PDOs; redo it.
            self.forget_pairing(device, now);
        }
        self.link = Link::Absent;
        self.timers.clear();
        device.push_event(ChargerEvent::BatteryFound { state });
        self.battery_heard(device, now);
        // A self-starting charger that left operational when the module
        // was gone starts itself again (no NMT master to do it).
        if self.self_start && left_for_it {
            device.set_nmt_state(now, NmtState::Operational, self);
        }
        if !self.configure_cob_ids {
            self.configured(device, now);
        } else if sdo_allowed(device) {
            self.start_configuration(device, now);
        } else {
            self.link = Link::Pending;
        }
    }

    fn battery_lost<const Q: usize>(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp) {
        device.push_event(ChargerEvent::BatteryLost);
        Self::raise(device, const { Alarm::of(DeltaQCode::HEARTBEAT_LOST) });
        let _ = self.client.abort(now, AbortCode::GeneralError);
        while self.client.poll_event().is_some() {}
        self.reading = None;
        self.forget_pairing(device, now);
        // The consumer time has passed since the last heartbeat: the module
        // is gone the rest of the 2000 ms later. It never goes in the same
        // call as the loss (at the earliest a microsecond after it, when the
        // consumer time is 2000 ms or longer), so that a call reports one
        // of the two and its EMCY: the firmware's queues hold the worst call.
        let consumer_ms = device
            .comm()
            .consumers()
            .iter()
            .find(|e| e.node == self.battery.raw())
            .map_or(0, |e| u64::from(e.time_ms));
        let rest_us = MODULE_GONE_MS.saturating_sub(consumer_ms) * 1000;
        self.link = Link::Lost;
        let gone = now.add_micros(rest_us.max(1));
        self.timers.set(LinkTimer::ModuleGone, Some(gone));
    }

    /// No heartbeat for [`MODULE_GONE_MS`]: E-0-3-0 and pre-operational.
    fn battery_gone<const Q: usize>(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp) {
        self.link = Link::Absent;
        device.push_event(ChargerEvent::BatteryGone);
        Self::raise(
            device,
            const { Alarm::of(DeltaQCode::BATTERY_MODULE_COMMUNICATION) },
        );
        if matches!(device.nmt_state(), NmtState::Operational) {
            device.set_nmt_state(now, NmtState::PreOperational, self);
            self.link = Link::Gone;
        }
    }

    /// Not heard, or gone: the module's next heartbeat finds it.
    const fn absent(&self) -> bool {
        matches!(self.link, Link::Absent | Link::Gone)
    }
}

impl<const Q: usize> Profile<ChargerProfile, Q, 4, 3> for ChargerProfile {
    /// Boots: boot-up message, default PDOs, pre-operational (or
    /// operational with `self_start`).
    fn boot(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp) {
        self.restart(device, now);
        // The voltage requests start at the charger's maximum, and reset
        // node restores them there.
        self.charge.power_on_objects(device.objects_mut());
        device.boot(now, self);
        if self.self_start {
            device.set_nmt_state(now, NmtState::Operational, self);
        }
    }

    /// The battery module's heartbeat events are reported as
    /// [`ChargerEvent::BatteryFound`] / [`ChargerEvent::BatteryLost`].
    fn keep_event(&self, event: &DeviceEvent) -> bool {
        let battery = self.battery;
        !matches!(event, DeviceEvent::Heartbeat(
            HeartbeatEvent::BootUp(n) | HeartbeatEvent::Lost(n)
            | HeartbeatEvent::Restored { node: n, .. } | HeartbeatEvent::StateChanged { node: n, .. }
        ) if *n == battery)
    }

    fn on_event(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp, event: &DeviceEvent) {
        self.on_core_event(device, now, event);
        let written = matches!(
            event,
            DeviceEvent::ObjectWritten {
                index: super::index::ALGORITHM_REQUEST,
                ..
            }
        );
        self.sync_charge(device, now, written);
    }

    fn on_frame(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp, frame: &CanFrame) {
        let battery = self.battery;
        // A data frame on the module's EMCY identifier: one compare (a
        // remote frame there carries no EMCY either).
        if frame.identity() == u32::from(EMCY_BASE + u16::from(battery.raw())) {
            if let Ok(emcy) = Emergency::parse_frame(frame) {
                let reaction = emergency_reaction(self.mode, &emcy);
                device.push_event(ChargerEvent::BatteryEmcy { emcy, reaction });
                let linked = self.linked();
                self.charge.battery_emcy(device, now, &emcy, linked);
            }
            return;
        }
        // The first heartbeat starts monitoring without an event.
        if self.absent() {
            let consumer = device.heartbeat_consumer();
            if let Some(state) = consumer.state(battery) {
                if consumer.is_alive(battery) {
                    self.battery_found(device, now, state);
                    self.sync_charge(device, now, false);
                }
            }
        }
        if sdo_allowed(device) {
            self.client.handle_frame(now, frame);
            self.drain_client(device, now);
        }
    }

    fn on_timeout(&mut self, device: &mut ChargerDevice<Q>, now: Timestamp) {
        if self.timers.expire(LinkTimer::ModuleGone, now) && matches!(self.link, Link::Lost) {
            self.battery_gone(device, now);
        }
        self.client.handle_timeout(now);
        self.drain_client(device, now);
        self.charge.control.handle_timeout(now);
        self.sync_charge(device, now, false);
    }

    fn poll_transmit(&mut self) -> Option<CanFrame> {
        self.client.poll_transmit()
    }

    /// The earliest of its own deadline, the SDO client's and the charge
    /// control's.
    fn poll_timeout(&self) -> Option<Timestamp> {
        earliest([
            self.timers.next(),
            self.client.poll_timeout(),
            self.charge.control.poll_timeout(),
        ])
    }

    /// Delta-Q's E-0-4-6 "invalid PDO length" with EEC 8210h (Delta-Q IC
    /// Series CANopen interface specification rev 2.0, section 4.4.1) for a
    /// short RPDO.
    fn rpdo_emergency(&self, register: ErrorRegister, error: &RpdoError) -> Option<Emergency> {
        let code = error.emcy_code()?;
        let register = register | ErrorRegister::GENERIC | ErrorRegister::COMMUNICATION;
        Some(DeltaQCode::INVALID_PDO_LENGTH.to_emergency(code, register))
    }
}

impl ChargerProfile {
    /// The core's events, for the pairing and the supervision.
    fn on_core_event<const Q: usize>(
        &mut self,
        device: &mut ChargerDevice<Q>,
        now: Timestamp,
        event: &DeviceEvent,
    ) {
        let battery = self.battery;
        // The master changed the state of a charger that left operational
        // for a gone module: its word stands when the module is back.
        if matches!(event, DeviceEvent::NmtStateChanged { .. }) && matches!(self.link, Link::Gone) {
            self.link = Link::Absent;
        }
        match *event {
            DeviceEvent::Reset { .. } => {
                self.restart(device, now);
                // The core has restored the device (pre-operational).
                if self.self_start {
                    device.set_nmt_state(now, NmtState::Operational, self);
                }
            }
            DeviceEvent::NmtStateChanged {
                to: NmtState::Stopped,
                ..
            } => {
                // No SDO in stopped: a configuration in progress ends
                // without a frame and is redone when SDO is allowed again.
                if matches!(self.link, Link::DeviceType | Link::CobId(..)) {
                    self.fresh_client();
                    self.link = Link::Pending;
                } else if self.reading.is_some() {
                    self.fresh_client();
                    self.read_interrupted();
                }
            }
            DeviceEvent::NmtStateChanged {
                to: NmtState::PreOperational | NmtState::Operational,
                ..
            } => match self.link {
                Link::Pending => self.start_configuration(device, now),
                // A 6020h question that waited for SDO.
                Link::Ready => self.start_identification(device, now),
                _ => {}
            },
            DeviceEvent::Heartbeat(e) => {
                // The module found: booted, back, or first heard with a
                // state change (the first heartbeat is `on_frame`'s).
                let (node, state) = match e {
                    HeartbeatEvent::Lost(n) => {
                        if n == battery {
                            self.battery_lost(device, now);
                        }
                        return;
                    }
                    HeartbeatEvent::BootUp(n) => (n, NmtState::BootUp),
                    HeartbeatEvent::Restored { node, state } => (node, state),
                    HeartbeatEvent::StateChanged { node, state } if self.absent() => (node, state),
                    HeartbeatEvent::StateChanged { .. } => return,
                };
                if node == battery {
                    self.battery_found(device, now, state);
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
#[path = "battery_tests.rs"]
mod battery_tests;
