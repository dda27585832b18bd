//! The "check and update software version" step of a slave's boot (CiA
//! 302-2 "Network management", section 4.4; 1F81h bits 5 and 6), after its
//! identity and before its configuration, as lely-core orders it:
//!
//! - the comparisons configured, in order: 1F56h sub 1 "program software
//!   identification" against 1F55h, then 1F52h "verify application
//!   software" sub 1 (date) and sub 2 (time) against 1F53h and 1F54h
//!   (CiA 302-3 "Configuration and program download", section 4); none
//!   configured: **G**; a read that fails: **G**;
//! - a difference: **H** when 1F81h bit 6 does not allow an update (or the
//!   slave is kept alive, bit 4); otherwise the manager downloads the
//!   slave's program (CiA 302-3's program download objects, by
//!   [`ProgramDownload`]) and boots the slave again from 1000h. No
//!   program, a download that fails, or a check that still differs after
//!   the download: **I**, CiA 302-2's "software update required, but
//!   program download failed".
//!
//! **Choice**: the program goes by segmented SDO (every SDO server has it;
//! lely-core tries a block download first), with the manager's SDO
//! timeout.

use super::{BootPhase, BootSlave};
use crate::clock::Timestamp;
use crate::machine::Machine;
use crate::manager::error::{BootError, BootEvent, SoftwareCheck, UpdateFailure};
use crate::queue::EventQueue;
use crate::sdo::{
    ProgramDownload, ProgramDownloadConfig, ProgramDownloadError, ProgramDownloadEvent, ProgramStep,
};

/// The comparisons in the order the manager makes them.
const ORDER: [SoftwareCheck; 3] = [
    SoftwareCheck::Identification,
    SoftwareCheck::Date,
    SoftwareCheck::Time,
];

impl BootSlave<'_> {
    /// The value `check` expects (1F55h, 1F53h or 1F54h).
    fn expected_software(&self, check: SoftwareCheck) -> u32 {
        let e = &self.config.expected;
        match check {
            SoftwareCheck::Identification => e.software,
            SoftwareCheck::Date => e.software_date,
            SoftwareCheck::Time => e.software_time,
        }
    }

    /// Whether `check` is configured: 1F55h not 0, or 1F53h not 0 (for the
    /// date and the time both).
    fn software_configured(&self, check: SoftwareCheck) -> bool {
        let e = &self.config.expected;
        match check {
            SoftwareCheck::Identification => e.software != 0,
            SoftwareCheck::Date | SoftwareCheck::Time => e.software_date != 0,
        }
    }

    /// The next configured comparison after `after` (the first: `None`).
    fn next_software(&self, after: Option<SoftwareCheck>) -> Option<SoftwareCheck> {
        let skip = after.map_or(0, |done| {
            ORDER
                .iter()
                .position(|c| *c == done)
                .map_or(ORDER.len(), |at| at.saturating_add(1))
        });
        ORDER
            .into_iter()
            .skip(skip)
            .find(|c| self.software_configured(*c))
    }

    /// The step's start: without 1F81h bit 5 the configuration follows;
    /// with it, the first comparison configured is read (none: **G**).
    pub(super) fn check_software<const E: usize>(
        &mut self,
        now: Timestamp,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        if !self.config.assignment.verifies_software() {
            return self.configure(now, events);
        }
        match self.next_software(None) {
            Some(check) => self.read(now, BootPhase::Software(check), events),
            None => self.fail(BootError::SoftwareNotConfigured, events),
        }
    }

    /// The value of `check` read: equal, the next comparison (or the
    /// configuration); different, an update or **H** / **I**.
    pub(super) fn software_read<const E: usize>(
        &mut self,
        now: Timestamp,
        check: SoftwareCheck,
        read: u32,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        let expected = self.expected_software(check);
        if read != expected {
            return self.software_differs(now, check, expected, read, events);
        }
        events.push(BootEvent::SoftwareVerified {
            node: self.config.node,
            check,
            value: read,
        });
        match self.next_software(Some(check)) {
            Some(next) => self.read(now, BootPhase::Software(next), events),
            None => self.configure(now, events),
        }
    }

    /// A difference: **H** without 1F81h bit 6 (or kept alive), **I** after
    /// an update or without a program, else the program download starts.
    fn software_differs<const E: usize>(
        &mut self,
        now: Timestamp,
        check: SoftwareCheck,
        expected: u32,
        read: u32,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        let assignment = self.config.assignment;
        if !assignment.allows_software_update() || assignment.keeps_alive() {
            let error = BootError::SoftwareDiffers {
                check,
                expected,
                read,
            };
            return self.fail(error, events);
        }
        if self.updated {
            let failure = UpdateFailure::StillDiffers {
                check,
                expected,
                read,
            };
            return self.fail(BootError::SoftwareUpdate { failure }, events);
        }
        let Some(image) = self.config.program else {
            let failure = UpdateFailure::NoProgram;
            return self.fail(BootError::SoftwareUpdate { failure }, events);
        };
        let mut config = ProgramDownloadConfig::for_server(self.config.node);
        config.client.timeout = self.manager.sdo_timeout;
        config.block = false;
        let mut download = ProgramDownload::new(config);
        if let Err(error) = download.start(now, image) {
            let step = ProgramStep::Stop;
            let failure = UpdateFailure::Download(ProgramDownloadError::Refused { step, error });
            return self.fail(BootError::SoftwareUpdate { failure }, events);
        }
        self.phase = BootPhase::SoftwareUpdate;
        self.update = Some(download);
        self.pump();
    }

    /// The program download's events: finished, the boot starts again
    /// from 1000h (the slave runs its new program); failed, **I**.
    pub(super) fn drain_update<const E: usize>(
        &mut self,
        now: Timestamp,
        events: &mut EventQueue<BootEvent, E>,
    ) {
        self.pump();
        let mut end = None;
        if let Some(update) = self.update.as_mut() {
            while let Some(event) = update.poll_event() {
                match event {
                    ProgramDownloadEvent::Finished { len, software_id } => {
                        end = Some(Ok((len, software_id)));
                    }
                    ProgramDownloadEvent::Failed(error) => end = Some(Err(error)),
                    _ => {}
                }
            }
        }
        match end {
            Some(Ok((len, identification))) => {
                events.push(BootEvent::SoftwareUpdated {
                    node: self.config.node,
                    len,
                    identification,
                });
                self.updated = true;
                self.begin(now, events);
            }
            Some(Err(error)) => {
                let failure = UpdateFailure::Download(error);
                self.fail(BootError::SoftwareUpdate { failure }, events);
            }
            None => {}
        }
    }
}
