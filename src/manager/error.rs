//! The boot process's error status (CiA 302-2 "Network management",
//! section 4.4, the "boot NMT slave" process and its error status letters
//! A to O), and the events the manager reports.

use crate::abort::AbortCode;
use crate::cob_id::NodeId;
use crate::od::index::{
    EXPECTED_APPLICATION_SW_DATE, EXPECTED_APPLICATION_SW_TIME, EXPECTED_SOFTWARE_IDENTIFICATION,
    VERIFY_APPLICATION_SOFTWARE,
};
use crate::program::PROGRAM_SOFTWARE_IDENTIFICATION;
use crate::sdo::{AbortOrigin, ClientError, ProgramDownloadError};

/// One comparison of the software check (1F81h bit 5, CiA 302-2 "Network
/// management", section 4.4, "check and update software version"): what
/// the manager reads of the slave and what it compares it with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SoftwareCheck {
    /// 1F56h sub 1 "program software identification" (CiA 302-3) against
    /// 1F55h "expected software identification".
    Identification,
    /// 1F52h sub 1 "application software date" against 1F53h "expected
    /// application software date".
    Date,
    /// 1F52h sub 2 "application software time" against 1F54h "expected
    /// application software time".
    Time,
}

impl SoftwareCheck {
    /// The object and sub-index the manager reads on the slave.
    #[must_use]
    pub const fn address(self) -> (u16, u8) {
        match self {
            SoftwareCheck::Identification => (PROGRAM_SOFTWARE_IDENTIFICATION, 1),
            SoftwareCheck::Date => (VERIFY_APPLICATION_SOFTWARE, 1),
            SoftwareCheck::Time => (VERIFY_APPLICATION_SOFTWARE, 2),
        }
    }

    /// The manager's object holding the expected value.
    #[must_use]
    pub const fn expected_index(self) -> u16 {
        match self {
            SoftwareCheck::Identification => EXPECTED_SOFTWARE_IDENTIFICATION,
            SoftwareCheck::Date => EXPECTED_APPLICATION_SW_DATE,
            SoftwareCheck::Time => EXPECTED_APPLICATION_SW_TIME,
        }
    }
}

/// Why the software update of a slave failed (error status I).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpdateFailure {
    /// The manager has no program for the slave
    /// ([`NodeConfig::program`](super::NodeConfig::program) is `None`).
    NoProgram,
    /// The program download (stop, clear, 1F50h, 1F57h, 1F56h, start)
    /// failed.
    Download(ProgramDownloadError),
    /// The program was downloaded and started, and the check still finds
    /// this difference.
    StillDiffers {
        /// The comparison that failed.
        check: SoftwareCheck,
        /// The expected value.
        expected: u32,
        /// The value read.
        read: u32,
    },
}

/// Which check of the slave's identity failed: 1000h or one 1018h sub.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IdentityCheck {
    /// 1000h against 1F84h (error status C).
    DeviceType,
    /// 1018h sub 1 against 1F85h (D).
    VendorId,
    /// 1018h sub 2 against 1F86h (M).
    ProductCode,
    /// 1018h sub 3 against 1F87h (N).
    Revision,
    /// 1018h sub 4 against 1F88h (O).
    Serial,
}

impl IdentityCheck {
    /// The check of 1018h `sub` (1-4); the device type for any other.
    pub(crate) const fn of_identity_sub(sub: u8) -> Self {
        match sub {
            1 => IdentityCheck::VendorId,
            2 => IdentityCheck::ProductCode,
            3 => IdentityCheck::Revision,
            4 => IdentityCheck::Serial,
            _ => IdentityCheck::DeviceType,
        }
    }
}

/// Why a configuration write failed (error status J).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConfigurationFailure {
    /// The transfer ended in an abort (the slave's, or the manager's own,
    /// e.g. an SDO timeout 05040000h).
    Aborted {
        /// The abort code.
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
    /// The SDO client could not start the write (e.g. a value above 4
    /// bytes without the segmented client): nothing was sent.
    Refused(ClientError),
}

/// How a slave's boot process failed, or its error control after it: one
/// CiA 302-2 error status letter ([`letter`](Self::letter)) with what the
/// manager saw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BootError {
    /// A: the node sent a boot-up message but is not in the network list
    /// (1F81h bit 0).
    #[error("A: the node is not in the network list (1F81h)")]
    NotListed,
    /// B: no answer to the read of 1000h (after the retries), or the read
    /// was aborted.
    #[error("B: no response to the read of 1000h ({code})")]
    NoResponse {
        /// The abort that ended the last try (05040000h: SDO timeout).
        code: AbortCode,
    },
    /// C, D, M, N, O: 1000h or a 1018h sub differs from its 1F84h-1F88h
    /// value (`read` `None`: the read of 1018h failed).
    #[error("{}: {} differs: expected {expected:#010X}, read {}", check_letter(*.check), check_name(*.check), Hex(*.read))]
    Identity {
        /// The check that failed.
        check: IdentityCheck,
        /// The expected value (1F84h-1F88h).
        expected: u32,
        /// The value read, `None` when it could not be read.
        read: Option<u32>,
    },
    /// E: the slave's heartbeat was lost after its boot, or a keep-alive
    /// slave sent none when its state was checked.
    #[error("E: heartbeat event: no heartbeat received within the consumer time")]
    HeartbeatLost,
    /// F: node guarding found the slave lost.
    #[error("F: node guarding event: no answer to the guarding requests")]
    GuardingLost,
    /// G: 1F81h asks for the software check (bit 5) but neither 1F55h,
    /// the expected software identification, nor 1F53h, the expected
    /// application software date, is configured: "objects for the program
    /// check not configured".
    #[error("G: the software check is asked for (1F81h bit 5) but neither 1F55h nor 1F53h is configured")]
    SoftwareNotConfigured,
    /// G: the slave's 1F56h sub 1 or 1F52h could not be read (the objects
    /// for the program check are inconsistent: lely-core ends the boot
    /// with G there too).
    #[error("G: the read of {:04X}h:{:02X} for the software check failed ({code})", check.address().0, check.address().1)]
    SoftwareUnreadable {
        /// The comparison whose read failed.
        check: SoftwareCheck,
        /// The abort that ended the read (05040000h: SDO timeout).
        code: AbortCode,
    },
    /// H: the slave's software differs from what the manager expects and
    /// an update is not allowed (1F81h bit 6 clear, or a keep-alive slave).
    #[error("H: {:04X}h:{:02X} differs from {:04X}h: expected {expected:#010X}, read {read:#010X}", check.address().0, check.address().1, check.expected_index())]
    SoftwareDiffers {
        /// The comparison that failed.
        check: SoftwareCheck,
        /// The expected value (1F55h, 1F53h or 1F54h).
        expected: u32,
        /// The value read (1F56h sub 1, 1F52h sub 1 or 2).
        read: u32,
    },
    /// I: the software differs, an update is allowed (1F81h bit 6), and it
    /// failed.
    #[error("I: software update failed: {failure:?}")]
    SoftwareUpdate {
        /// How it failed.
        failure: UpdateFailure,
    },
    /// J: the configuration download failed at `index`, `sub`.
    #[error("J: configuration download failed at {index:04X}h:{sub:02X} ({failure:?})")]
    Configuration {
        /// The object written.
        index: u16,
        /// Its sub-index.
        sub: u8,
        /// How the write failed.
        failure: ConfigurationFailure,
    },
    /// K: no heartbeat within the consumer time when error control was
    /// started during the boot.
    #[error("K: no heartbeat received when error control was started")]
    ErrorControlStart,
}

/// The letter of an identity check.
const fn check_letter(check: IdentityCheck) -> char {
    match check {
        IdentityCheck::DeviceType => 'C',
        IdentityCheck::VendorId => 'D',
        IdentityCheck::ProductCode => 'M',
        IdentityCheck::Revision => 'N',
        IdentityCheck::Serial => 'O',
    }
}

/// The object an identity check reads, in words.
const fn check_name(check: IdentityCheck) -> &'static str {
    match check {
        IdentityCheck::DeviceType => "device type 1000h",
        IdentityCheck::VendorId => "vendor-ID 1018h:01",
        IdentityCheck::ProductCode => "product code 1018h:02",
        IdentityCheck::Revision => "revision number 1018h:03",
        IdentityCheck::Serial => "serial number 1018h:04",
    }
}

/// A value read, or "nothing" (for the error text).
struct Hex(Option<u32>);

impl core::fmt::Display for Hex {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.0 {
            Some(v) => write!(f, "{v:#010X}"),
            None => f.write_str("nothing (the read failed)"),
        }
    }
}

impl BootError {
    /// The CiA 302-2 error status letter (section 4.4; the letters as
    /// lely-core's `co_nmt_es2str` spells them out).
    ///
    /// ```
    /// use canopen_codec::manager::{BootError, IdentityCheck};
    /// let e = BootError::Identity { check: IdentityCheck::ProductCode, expected: 7, read: Some(8) };
    /// assert_eq!(e.letter(), 'M');
    /// assert_eq!(e.reason(), "value of 1018h sub-index 02 differs from 1F86h (product code)");
    /// ```
    #[must_use]
    pub const fn letter(&self) -> char {
        match self {
            BootError::NotListed => 'A',
            BootError::NoResponse { .. } => 'B',
            BootError::Identity { check, .. } => check_letter(*check),
            BootError::HeartbeatLost => 'E',
            BootError::GuardingLost => 'F',
            BootError::SoftwareNotConfigured | BootError::SoftwareUnreadable { .. } => 'G',
            BootError::SoftwareDiffers { .. } => 'H',
            BootError::SoftwareUpdate { .. } => 'I',
            BootError::Configuration { .. } => 'J',
            BootError::ErrorControlStart => 'K',
        }
    }

    /// What the letter means, in CiA 302-2's words.
    #[must_use]
    pub const fn reason(&self) -> &'static str {
        match self {
            BootError::NotListed => "the node is not listed in 1F81h",
            BootError::NoResponse { .. } => "no response received for the upload of 1000h",
            BootError::Identity { check, .. } => match check {
                IdentityCheck::DeviceType => "value of 1000h differs from 1F84h (device type)",
                IdentityCheck::VendorId => {
                    "value of 1018h sub-index 01 differs from 1F85h (vendor-ID)"
                }
                IdentityCheck::ProductCode => {
                    "value of 1018h sub-index 02 differs from 1F86h (product code)"
                }
                IdentityCheck::Revision => {
                    "value of 1018h sub-index 03 differs from 1F87h (revision number)"
                }
                IdentityCheck::Serial => {
                    "value of 1018h sub-index 04 differs from 1F88h (serial number)"
                }
            },
            BootError::HeartbeatLost => "heartbeat event: no heartbeat received from the node",
            BootError::GuardingLost => {
                "node guarding event: no confirmation for guarding requests received"
            }
            BootError::SoftwareNotConfigured | BootError::SoftwareUnreadable { .. } => {
                "the objects for the program check are not configured or inconsistent"
            }
            BootError::SoftwareDiffers { .. } => {
                "the software version check failed and a software update is not allowed"
            }
            BootError::SoftwareUpdate { .. } => {
                "a software update is required, but the program download failed"
            }
            BootError::Configuration { .. } => "the configuration download failed",
            BootError::ErrorControlStart => "heartbeat failure during the start of error control",
        }
    }
}

/// What the manager reports, in the order it happens.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum BootEvent {
    /// The slave sent its boot-up message: its boot process starts (again).
    BootUp {
        /// The slave.
        node: NodeId,
    },
    /// 1000h and the 1018h subs the manager checks matched.
    Identified {
        /// The slave.
        node: NodeId,
        /// Its 1000h.
        device_type: u32,
    },
    /// One comparison of the software check matched (1F81h bit 5): the
    /// slave's 1F56h sub 1 equals 1F55h, or its 1F52h sub 1 or 2 equals
    /// 1F53h or 1F54h.
    SoftwareVerified {
        /// The slave.
        node: NodeId,
        /// The comparison.
        check: SoftwareCheck,
        /// The value read.
        value: u32,
    },
    /// The software check found a difference and the manager downloaded
    /// [`NodeConfig::program`](super::NodeConfig::program) into the slave
    /// and started it (1F81h bit 6): its boot starts again from 1000h.
    SoftwareUpdated {
        /// The slave.
        node: NodeId,
        /// Bytes downloaded.
        len: usize,
        /// The slave's 1F56h sub 1 after the download.
        identification: u32,
    },
    /// A keep-alive slave (1F81h bit 4) was operational at its state
    /// check: CiA 302-2's error status **L**, "the slave was initially
    /// operational" (the manager may go on with the others: lely-core
    /// reports it with the boot's success). It is not configured, and not
    /// started again; [`Booted`](Self::Booted) follows.
    InitiallyOperational {
        /// The slave.
        node: NodeId,
    },
    /// Every entry of the slave's concise DCF was written.
    ConfigurationWritten {
        /// The slave.
        node: NodeId,
        /// How many entries.
        entries: u32,
    },
    /// The boot process ended well: checked, configured, under error
    /// control; the slave waits for its start.
    Booted {
        /// The slave.
        node: NodeId,
    },
    /// The NMT "start remote node" that starts the slave was sent (to it,
    /// or to all nodes).
    Operational {
        /// The slave.
        node: NodeId,
    },
    /// The network was started: every mandatory slave has booted and every
    /// slave's first boot process has ended.
    NetworkStarted,
    /// A mandatory slave failed before the network was started: the start
    /// waits for it to boot.
    StartHeld {
        /// The slave.
        node: NodeId,
    },
    /// 1F89h, the boot time, passed with the network not started, and this
    /// mandatory slave has not booted (reported once per
    /// [`start`](super::BootManager::start)).
    BootTimeElapsed {
        /// The slave.
        node: NodeId,
    },
    /// The slave's boot process ended in `error`.
    Error {
        /// The slave.
        node: NodeId,
        /// The error status.
        error: BootError,
    },
    /// Error control lost the slave after its boot: `error` is
    /// [`BootError::HeartbeatLost`] (E) or [`BootError::GuardingLost`] (F).
    Lost {
        /// The slave.
        node: NodeId,
        /// The error status.
        error: BootError,
    },
    /// Error control hears the slave again after [`Lost`](Self::Lost).
    Restored {
        /// The slave.
        node: NodeId,
    },
}
