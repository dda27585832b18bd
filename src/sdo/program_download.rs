//! The master's side of program download (CiA 302-3, the program download
//! objects; see [`program`](crate::program)): one
//! sans-IO machine that drives the whole sequence on one SDO client.
//!
//! 1. 1F51h sub n = 0: stop the program;
//! 2. 1F51h sub n = 3: clear it;
//! 3. the image into 1F50h sub n, by block download (CRC per
//!    [`ClientConfig::crc`]) or segmented ([`ProgramDownloadConfig::block`]
//!    off, or without the feature `sdo-block`);
//! 4. read 1F57h sub n: the flash status must be "no error, not in
//!    progress";
//! 5. read 1F56h sub n: the software identification;
//! 6. 1F51h sub n = 1: start the program.
//!
//! Every step that completes is a [`ProgramDownloadEvent::StepDone`]; the
//! sequence ends in exactly one terminal event, [`Finished`] or [`Failed`].
//! **Choice**: when the device aborts the download itself (a store that
//! failed: 08000020h), the machine still reads 1F57h, so the failure is
//! reported with the device's flash error ([`ProgramDownloadError::Flash`]);
//! a flash status without error there reports the abort
//! ([`ProgramDownloadError::Aborted`]). It reads 1F57h
//! [`ProgramDownloadConfig::settle`] after the abort, not at once: the
//! rest of a sub-block the device aborted is still on the bus, and a
//! device may answer those segments as requests of their own (with
//! aborts of other objects) that must not be taken for the answer.
//!
//! [`Finished`]: ProgramDownloadEvent::Finished
//! [`Failed`]: ProgramDownloadEvent::Failed
//!
//! It implements [`Machine`]: after [`ProgramDownload::start`] and every
//! `handle_*` call, drain `poll_transmit` (the SDO client's frames), then
//! `poll_event`. Events go to a queue of 4, oldest dropped and counted.

use super::{AbortCode, AbortOrigin, Client, ClientConfig, ClientError, ClientEvent, TransferEnd};
use crate::clock::{timer_kind, Timers, Timestamp};
use crate::machine::Machine;
use crate::program::{
    FlashStatus, ProgramCommand, FLASH_STATUS_IDENTIFICATION, PROGRAM_CONTROL, PROGRAM_DATA,
    PROGRAM_SOFTWARE_IDENTIFICATION,
};
use crate::queue::EventQueue;

/// The events the machine's queue holds.
const EVENT_CAPACITY: usize = 4;

/// The steps of the sequence, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ProgramStep {
    /// 1F51h = 0.
    Stop,
    /// 1F51h = 3.
    Clear,
    /// The image into 1F50h.
    Download,
    /// 1F57h read.
    FlashStatus,
    /// 1F56h read.
    SoftwareId,
    /// 1F51h = 1.
    Start,
}

impl ProgramStep {
    /// The object the step reads or writes (sub-index: the program number).
    #[must_use]
    pub const fn index(self) -> u16 {
        match self {
            ProgramStep::Stop | ProgramStep::Clear | ProgramStep::Start => PROGRAM_CONTROL,
            ProgramStep::Download => PROGRAM_DATA,
            ProgramStep::FlashStatus => FLASH_STATUS_IDENTIFICATION,
            ProgramStep::SoftwareId => PROGRAM_SOFTWARE_IDENTIFICATION,
        }
    }
}

/// Why a program download failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ProgramDownloadError {
    /// An SDO transfer of `step` was aborted (by the device or here).
    #[error("program download step {step:?}: SDO aborted with {code}")]
    Aborted {
        /// The step.
        step: ProgramStep,
        /// The abort code.
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
    /// 1F57h reports an error or a download still in progress. `code` is
    /// the abort of the download that preceded it, if any.
    #[error("program download: flash status {status:?}")]
    Flash {
        /// The 1F57h word.
        status: FlashStatus,
        /// The device's abort of the download, if it aborted it.
        code: Option<AbortCode>,
    },
    /// The SDO client refused a step's transfer (e.g. an image too long for
    /// SDO).
    #[error("program download step {step:?}: {error}")]
    Refused {
        /// The step.
        step: ProgramStep,
        /// Why.
        error: ClientError,
    },
}

/// What the machine reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ProgramDownloadEvent {
    /// A step completed.
    StepDone(ProgramStep),
    /// The program is downloaded, checked and started.
    Finished {
        /// Bytes downloaded.
        len: usize,
        /// 1F56h.
        software_id: u32,
    },
    /// The sequence stopped.
    Failed(ProgramDownloadError),
}

/// The machine's settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProgramDownloadConfig {
    /// The SDO client (server node, timeout, block size, CRC).
    pub client: ClientConfig,
    /// The program number: the sub-index of 1F50h, 1F51h, 1F56h, 1F57h.
    pub program: u8,
    /// Download the image by block (default); segmented when off.
    pub block: bool,
    /// How long after the device aborted the download 1F57h is read
    /// (default 100 ms).
    pub settle: core::time::Duration,
}

impl ProgramDownloadConfig {
    /// Program 1 of `server` with the default client settings, by block.
    #[must_use]
    pub const fn for_server(server: crate::cob_id::NodeId) -> Self {
        ProgramDownloadConfig {
            client: ClientConfig::for_server(server),
            program: crate::program::PROGRAM_1,
            block: true,
            settle: core::time::Duration::from_millis(100),
        }
    }
}

/// What the client sends: a 1F51h command or the image.
#[derive(Debug)]
enum Payload<D> {
    Command([u8; 1]),
    Image(D),
}

impl<D: AsRef<[u8]>> AsRef<[u8]> for Payload<D> {
    fn as_ref(&self) -> &[u8] {
        match self {
            Payload::Command(c) => c,
            Payload::Image(d) => d.as_ref(),
        }
    }
}

timer_kind! {
    /// The program download's own deadline (the SDO client keeps the
    /// transfers').
    enum DownloadTimer {
        /// 1F57h is read this long ([`ProgramDownloadConfig::settle`])
        /// after the device aborted the download: the rest of the
        /// sub-block passes first.
        ReadStatus,
    }
}

/// The master's program download machine for one device (see the module
/// docs). `D` is the image (a slice, an array, a `Vec`), held until it is
/// sent.
///
/// ```
/// use canopen_codec::machine::Machine;
/// use canopen_codec::sdo::{ProgramDownload, ProgramDownloadConfig};
/// use canopen_codec::{NodeId, Timestamp};
///
/// let mut master = ProgramDownload::new(ProgramDownloadConfig::for_server(NodeId::new(10).unwrap()));
/// master.start(Timestamp::ZERO, &[0xAA; 100][..]).unwrap();
/// // First step: 1F51h sub 1 = 0 (stop program), expedited.
/// assert_eq!(master.poll_transmit().unwrap().to_string(), "60A#2F511F0100000000");
/// ```
#[derive(Debug)]
pub struct ProgramDownload<D> {
    config: ProgramDownloadConfig,
    client: Client<Payload<D>, { super::EVENTS_PER_CALL }>,
    /// The step running, `None` when idle.
    step: Option<ProgramStep>,
    image: Option<D>,
    len: usize,
    /// The value being uploaded (4 bytes at most).
    value: [u8; 4],
    /// The device's abort of the download, explained by 1F57h.
    download_abort: Option<AbortCode>,
    /// 1F56h as read.
    software_id: u32,
    /// Its own deadline ([`DownloadTimer`]); the client keeps its own.
    timers: Timers<DownloadTimer, 1>,
    events: EventQueue<ProgramDownloadEvent, EVENT_CAPACITY>,
}

impl<D: AsRef<[u8]>> ProgramDownload<D> {
    /// An idle machine.
    #[must_use]
    pub fn new(config: ProgramDownloadConfig) -> Self {
        ProgramDownload {
            config,
            client: Client::with_event_capacity(config.client),
            step: None,
            image: None,
            len: 0,
            value: [0; 4],
            download_abort: None,
            software_id: 0,
            timers: Timers::new(),
            events: EventQueue::new(ProgramDownloadEvent::StepDone(ProgramStep::Stop)),
        }
    }

    /// The step running, `None` when idle.
    #[must_use]
    pub const fn step(&self) -> Option<ProgramStep> {
        self.step
    }

    /// True while a sequence runs.
    #[must_use]
    pub const fn is_busy(&self) -> bool {
        self.step.is_some()
    }

    /// Starts the sequence with `image`: the first step's request is
    /// queued. Refused with [`ClientError::Busy`] while a sequence runs.
    pub fn start(&mut self, now: Timestamp, image: D) -> Result<(), ClientError> {
        if self.is_busy() {
            return Err(ClientError::Busy);
        }
        self.len = image.as_ref().len();
        self.image = Some(image);
        self.download_abort = None;
        self.timers.clear();
        self.begin(now, ProgramStep::Stop);
        Ok(())
    }

    /// Gives up: the running transfer is aborted with `code` (one abort
    /// frame) and the sequence fails with it. False when idle.
    pub fn abort(&mut self, now: Timestamp, code: AbortCode) -> bool {
        if !self.is_busy() {
            return false;
        }
        if !self.client.abort(now, code) {
            // Waiting to read 1F57h, no transfer runs: fail without a frame.
            self.timers.clear();
            self.fail_aborted(code, AbortOrigin::Local);
        }
        self.drain(now);
        true
    }

    /// Starts `step`'s transfer.
    fn begin(&mut self, now: Timestamp, step: ProgramStep) {
        self.step = Some(step);
        let (index, sub) = (step.index(), self.config.program);
        let command = |c: ProgramCommand| Payload::Command([u8::from(c)]);
        let started = match step {
            ProgramStep::Stop => {
                self.client
                    .start_download(now, index, sub, command(ProgramCommand::Stop))
            }
            ProgramStep::Clear => {
                self.client
                    .start_download(now, index, sub, command(ProgramCommand::Clear))
            }
            ProgramStep::Start => {
                self.client
                    .start_download(now, index, sub, command(ProgramCommand::Start))
            }
            ProgramStep::Download => match self.image.take() {
                Some(image) if self.config.block && cfg!(feature = "sdo-block") => self
                    .client
                    .start_block_download(now, index, sub, Payload::Image(image)),
                Some(image) => self
                    .client
                    .start_download(now, index, sub, Payload::Image(image)),
                None => Err(ClientError::Busy),
            },
            ProgramStep::FlashStatus | ProgramStep::SoftwareId => {
                self.value = [0; 4];
                self.client.start_upload(now, index, sub)
            }
        };
        if let Err(error) = started {
            self.fail(ProgramDownloadError::Refused { step, error });
        }
    }

    fn fail(&mut self, error: ProgramDownloadError) {
        self.step = None;
        self.image = None;
        self.events.push(ProgramDownloadEvent::Failed(error));
    }

    fn fail_aborted(&mut self, code: AbortCode, origin: AbortOrigin) {
        if let Some(step) = self.step {
            self.fail(ProgramDownloadError::Aborted { step, code, origin });
        }
    }

    /// The client's events move the sequence on.
    fn drain(&mut self, now: Timestamp) {
        while let Some(event) = self.client.poll_event() {
            let Some(step) = self.step else { continue };
            match event {
                ClientEvent::UploadData { offset, data, .. } => {
                    for (i, b) in data.as_slice().iter().enumerate() {
                        if let Some(slot) =
                            offset.checked_add(i).and_then(|at| self.value.get_mut(at))
                        {
                            *slot = *b;
                        }
                    }
                }
                ClientEvent::Ended(TransferEnd::Uploaded { .. })
                | ClientEvent::Ended(TransferEnd::Downloaded { .. }) => {
                    self.step_done(now, step);
                }
                ClientEvent::Ended(TransferEnd::Aborted { code, origin, .. }) => {
                    if step == ProgramStep::Download && origin == AbortOrigin::Peer {
                        // The device refused the image: 1F57h says why,
                        // once the rest of the sub-block has passed.
                        self.download_abort = Some(code);
                        self.step = Some(ProgramStep::FlashStatus);
                        let settle = crate::clock::micros_of(self.config.settle);
                        let at = now.add_micros(settle);
                        self.timers.set(DownloadTimer::ReadStatus, Some(at));
                    } else {
                        self.fail_aborted(code, origin);
                    }
                }
            }
        }
    }

    /// The settle time after the device aborted the download is over:
    /// 1F57h (flash status) is read to explain the abort.
    fn read_status(&mut self, now: Timestamp) {
        self.begin(now, ProgramStep::FlashStatus);
    }

    fn step_done(&mut self, now: Timestamp, step: ProgramStep) {
        let value = u32::from_le_bytes(self.value);
        let next = match step {
            ProgramStep::Stop => ProgramStep::Clear,
            ProgramStep::Clear => ProgramStep::Download,
            ProgramStep::Download => ProgramStep::FlashStatus,
            ProgramStep::FlashStatus => {
                let status = FlashStatus::from_raw(value);
                let code = self.download_abort;
                if !status.is_ok() {
                    return self.fail(ProgramDownloadError::Flash { status, code });
                }
                if let Some(code) = code {
                    self.step = Some(ProgramStep::Download);
                    return self.fail_aborted(code, AbortOrigin::Peer);
                }
                ProgramStep::SoftwareId
            }
            ProgramStep::SoftwareId => ProgramStep::Start,
            ProgramStep::Start => {
                self.step = None;
                self.events.push(ProgramDownloadEvent::StepDone(step));
                let software_id = self.software_id;
                self.events.push(ProgramDownloadEvent::Finished {
                    len: self.len,
                    software_id,
                });
                return;
            }
        };
        if step == ProgramStep::SoftwareId {
            self.software_id = value;
        }
        self.events.push(ProgramDownloadEvent::StepDone(step));
        self.begin(now, next);
    }
}

super::sdo_client_sequence_machine!(
    impl [D: AsRef<[u8]>] Machine for ProgramDownload<D>,
    ProgramDownloadEvent,
    events,
    own timers: DownloadTimer::ReadStatus => read_status
);

// The image (20 bytes) goes by segmented transfer: without the segmented
// client, a program download is refused before its first frame.
#[cfg(all(test, feature = "sdo-client-segmented"))]
mod tests {
    use super::*;
    use crate::cob_id::NodeId;
    use crate::frame::CanFrame;
    use std::string::ToString;

    /// A download to node 10 by segmented transfer (no block transfer),
    /// not started.
    fn segmented_to_node_10() -> ProgramDownload<&'static [u8]> {
        let mut config = ProgramDownloadConfig::for_server(NodeId::new(10).unwrap());
        config.block = false;
        ProgramDownload::new(config)
    }

    /// An answer of node 10's SDO server.
    fn answer(bytes: [u8; 8]) -> CanFrame {
        CanFrame::standard(0x58A, &bytes).unwrap()
    }

    #[test]
    fn reads_the_flash_status_at_its_own_deadline_and_not_before() {
        let t = Timestamp::from_millis;
        let mut m = segmented_to_node_10();
        assert_eq!(m.poll_timeout(), None);
        m.start(t(0), &[0xAA; 20][..]).unwrap();
        // Stop and clear, each acknowledged at once.
        for sent in ["60A#2F511F0100000000", "60A#2F511F0103000000"] {
            assert_eq!(m.poll_transmit().unwrap().to_string(), sent);
            m.handle_frame(t(1), &answer([0x60, 0x51, 0x1F, 1, 0, 0, 0, 0]));
        }
        // The download: the device refuses it (08000020h).
        assert_eq!(
            m.poll_transmit().unwrap().to_string(),
            "60A#21501F0114000000"
        );
        assert_eq!(m.poll_timeout(), Some(t(1 + 2000)));
        m.handle_frame(t(2), &answer([0x80, 0x50, 0x1F, 1, 0x20, 0, 0, 0x08]));
        assert_eq!(m.poll_transmit(), None);
        // No transfer runs: the read of 1F57h, `settle` later, is the only
        // deadline, and nothing is sent before it.
        assert_eq!(m.poll_timeout(), Some(t(102)));
        m.handle_timeout(t(101));
        assert_eq!((m.poll_transmit(), m.poll_timeout()), (None, Some(t(102))));
        m.handle_timeout(t(102));
        assert_eq!(
            m.poll_transmit().unwrap().to_string(),
            "60A#40571F0100000000"
        );
        // Its own timer fired once; the client's transfer deadline is next.
        assert_eq!(m.poll_timeout(), Some(t(102 + 2000)));
        m.handle_timeout(t(103));
        assert_eq!(m.poll_transmit(), None);
    }

    #[test]
    fn an_abort_while_waiting_stops_the_timer() {
        let t = Timestamp::from_millis;
        let mut m = segmented_to_node_10();
        m.start(t(0), &[0xAA; 20][..]).unwrap();
        for _ in 0..2 {
            let _ = m.poll_transmit();
            m.handle_frame(t(1), &answer([0x60, 0x51, 0x1F, 1, 0, 0, 0, 0]));
        }
        let _ = m.poll_transmit();
        m.handle_frame(t(2), &answer([0x80, 0x50, 0x1F, 1, 0x20, 0, 0, 0x08]));
        assert_eq!(m.poll_timeout(), Some(t(102)));
        assert!(m.abort(t(50), AbortCode::GeneralError));
        assert_eq!((m.poll_transmit(), m.poll_timeout()), (None, None));
        m.handle_timeout(t(102));
        assert_eq!(m.poll_transmit(), None);
    }
}
