//! The CANopen manager's boot-up: the NMT master start-up and the "boot NMT
//! slave" process of CiA 302-2 "Network management" (sections 4.3 and 4.4),
//! as one sans-IO [`Machine`](crate::machine::Machine), [`BootManager`].
//!
//! For every slave assigned to it ([`NodeConfig`]: the 1F81h assignment,
//! the 1F84h-1F88h expected identity, its configuration, the heartbeat it
//! produces) the manager
//!
//! 1. resets its communication at [`BootManager::start`] and waits for its
//!    boot-up message (CiA 301 section 7.2.8.3.3);
//! 2. reads 1000h (no answer after [`ManagerConfig::retries`] more tries:
//!    **B**; a value other than 1F84h: **C**) and 1018h sub 1-4 where an
//!    expected value is not 0 (**D**, **M**, **N**, **O**);
//! 3. for a keep-alive slave (1F81h bit 4, not reset at
//!    [`BootManager::start`]), checks its state once by its heartbeat: an
//!    operational slave is **L**
//!    ([`InitiallyOperational`](BootEvent::InitiallyOperational)), keeps
//!    running and skips the steps up to error control; any other state
//!    resets its communication and the boot goes on from its boot-up;
//!    no heartbeat: **E**;
//! 4. with 1F81h bit 5 ([`SlaveAssignment::verify_software`]), checks its
//!    software ([`SoftwareCheck`]): its 1F56h sub 1 "program software
//!    identification" against 1F55h ([`ExpectedIdentity::software`]), its
//!    1F52h "verify application software" date and time against 1F53h and
//!    1F54h ([`ExpectedIdentity::software_date`],
//!    [`ExpectedIdentity::software_time`]), whichever are configured
//!    (none, or a read that fails: **G**). A difference is **H**, unless
//!    1F81h bit 6 ([`SlaveAssignment::allow_software_update`]) lets the
//!    manager download [`NodeConfig::program`] into the slave (CiA 302-3
//!    "Configuration and program download", by
//!    [`ProgramDownload`](crate::sdo::ProgramDownload)) and boot it again
//!    from 1000h; no program, a failed download, or a difference after it
//!    is **I**;
//! 5. writes its configuration, a concise DCF (CiA 302-3 section 4, the
//!    format of 1F22h: [`ConciseDcf`](crate::od::ConciseDcf)), entry by
//!    entry in order by SDO download (an abort or a timeout: **J**, with
//!    the object and the abort code);
//! 6. starts error control: waits for a heartbeat within the consumer time
//!    ([`ManagerConfig::consumer_time`]; none: **K**), or guards the node
//!    with the 1F81h guard time and retry factor (no answer: **F**), or
//!    neither when the slave has no heartbeat and no guard time;
//! 7. is then [`Booted`](BootEvent::Booted), and is started once the
//!    network is: when every mandatory slave (1F81h bit 3) has booted and
//!    every slave's first boot process has ended (a choice: an optional
//!    slave is not started before it is configured), by one NMT "start" to
//!    all nodes (1F80h [`START_ALL`](NmtStartup::START_ALL)) or one per
//!    slave; a slave that boots afterwards is started on its own. A
//!    mandatory slave's failure holds the start
//!    ([`StartHeld`](BootEvent::StartHeld)); an optional slave's does not.
//!
//! With 1F80h [`NO_SLAVE_START`](NmtStartup::NO_SLAVE_START) the
//! application starts the slaves ([`BootManager::start_node`],
//! [`BootManager::start_network`]). [`ManagerConfig::boot_time`] (1F89h)
//! bounds the wait for the mandatory slaves
//! ([`BootTimeElapsed`](BootEvent::BootTimeElapsed));
//! [`ManagerConfig::retry_interval`] boots a slave that ended in **B**
//! again by itself.
//!
//! After its boot, a heartbeat missing for the consumer time is
//! [`Lost`](BootEvent::Lost) with **E** (guarding: **F**), reported once;
//! 1F80h [`STOP_ALL`](NmtStartup::STOP_ALL) then stops all nodes when the
//! slave is mandatory. A boot-up message from a slave at any time starts
//! its boot process again; one from a node that is not a slave is an
//! [`Error`](BootEvent::Error) with **A**. Every failure is one
//! [`BootError`], whose [`letter`](BootError::letter) is the CiA 302-2
//! error status (the letters as lely-core's `co_nmt_es2str` writes them).
//!
//! The manager never allocates and never reads a clock: each slave has an
//! SDO client on the CiA 301 default channel (600h/580h + node-ID, CiA 301
//! section 7.3.3) and its own frame queue, the caller's clock drives every
//! timer. It keeps `E` events, the oldest dropped and counted (the
//! back-pressure rule of [`crate::machine`]).
//!
//! ```
//! use canopen_codec::machine::Machine;
//! use canopen_codec::manager::{BootEvent, BootManager, ManagerConfig, NodeConfig};
//! use canopen_codec::{CanFrame, NodeId, Timestamp};
//!
//! let node = NodeId::new(5).unwrap();
//! let mut slave = NodeConfig::new(node);
//! slave.expected.device_type = 0x0001_0191;
//! let mut manager: BootManager<'_, 4> = BootManager::new(ManagerConfig::default());
//! manager.add_node(slave).unwrap();
//! manager.start(Timestamp::ZERO);
//! // Reset communication of node 5, then its boot-up starts the process.
//! assert_eq!(manager.poll_transmit().unwrap().to_string(), "000#8205");
//! manager.handle_frame(Timestamp::from_millis(10), &CanFrame::standard(0x705, &[0]).unwrap());
//! assert_eq!(manager.poll_transmit().unwrap().to_string(), "605#4000100000000000");
//! let answer = CanFrame::standard(0x585, &[0x43, 0, 0x10, 0, 0x91, 0x01, 0x01, 0]).unwrap();
//! manager.handle_frame(Timestamp::from_millis(12), &answer);
//! // Identified, booted (no error control asked for) and started.
//! assert_eq!(manager.poll_transmit().unwrap().to_string(), "000#0105");
//! let events: Vec<_> = core::iter::from_fn(|| manager.poll_event()).collect();
//! assert_eq!(events, [
//!     BootEvent::BootUp { node },
//!     BootEvent::Identified { node, device_type: 0x0001_0191 },
//!     BootEvent::Booted { node },
//!     BootEvent::NetworkStarted,
//!     BootEvent::Operational { node },
//! ]);
//! ```

mod boot;
mod config;
mod error;
mod slave;

pub use boot::{BootManager, ManagerError};
pub use config::{ExpectedIdentity, ManagerConfig, NmtStartup, NodeConfig, SlaveAssignment};
pub use error::{
    BootError, BootEvent, ConfigurationFailure, IdentityCheck, SoftwareCheck, UpdateFailure,
};
pub use slave::BootPhase;

#[cfg(test)]
mod tests;
