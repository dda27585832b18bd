//! The manager's configuration, mirroring the CiA 302-2 objects an NMT
//! master keeps: 1F80h NMT start-up ([`NmtStartup`]), 1F81h NMT slave
//! assignment ([`SlaveAssignment`]), 1F84h-1F88h the expected identity of
//! each slave ([`ExpectedIdentity`]), and the times the boot process uses
//! ([`ManagerConfig`]).

use core::time::Duration;

use crate::cob_id::NodeId;
use crate::od::{Address, ConciseDcf};

bitflags::bitflags! {
    /// Object 1F80h "NMT start-up" (CiA 302-2 "Network management", section
    /// 4.2, object 1F80h): how the NMT master starts the network. The bits
    /// the manager acts on are [`START_ALL`](Self::START_ALL),
    /// [`NO_SLAVE_START`](Self::NO_SLAVE_START),
    /// [`RESET_ALL`](Self::RESET_ALL) and [`STOP_ALL`](Self::STOP_ALL); the
    /// others are kept so the word round-trips.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub struct NmtStartup: u32 {
        /// Bit 0: the device is the NMT master.
        const MASTER = 1 << 0;
        /// Bit 1: start the slaves with one NMT "start remote node" to all
        /// nodes (node-ID 0) instead of one command per slave.
        const START_ALL = 1 << 1;
        /// Bit 2: the master does not enter operational by itself (the
        /// application switches it).
        const NO_SELF_OPERATIONAL = 1 << 2;
        /// Bit 3: the master does not start the slaves; the application
        /// does.
        const NO_SLAVE_START = 1 << 3;
        /// Bit 4: at start-up, reset the communication of all nodes with
        /// one NMT command (node-ID 0) instead of one per slave.
        const RESET_ALL = 1 << 4;
        /// Bit 5: the master takes part in flying-master negotiation (not
        /// done here).
        const FLYING_MASTER = 1 << 5;
        /// Bit 6: on an error control event of a mandatory slave, stop all
        /// nodes (NMT "stop remote node" to node-ID 0).
        const STOP_ALL = 1 << 6;
        /// Any other bit, kept.
        const _ = !0;
    }
}

impl Default for NmtStartup {
    /// The NMT master that starts every slave individually: bit 0 only.
    fn default() -> Self {
        NmtStartup::MASTER
    }
}

/// One sub-index of object 1F81h "NMT slave assignment" (CiA 302-2
/// "Network management", section 4.2, object 1F81h): bit 0 the node is a
/// slave of this master, bit 2 the master may boot it (check and
/// configure it), bit 3 it is mandatory, bit 4 keep alive (its
/// communication is not reset at start-up), bit 5 verify its application
/// software, bit 6 software update allowed, bits 8-15 the retry factor and
/// bits 16-31 the guard time in ms for node guarding.
///
/// ```
/// use canopen_codec::manager::SlaveAssignment;
/// use core::time::Duration;
///
/// let a = SlaveAssignment::BOOTED.mandatory().with_guarding(Duration::from_millis(100), 3);
/// assert_eq!(a.raw(), 0x0064_030D);
/// assert!(a.is_slave() && a.may_boot() && a.is_mandatory() && !a.keeps_alive());
/// assert_eq!((a.guard_time(), a.retry_factor()), (Duration::from_millis(100), 3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SlaveAssignment(u32);

impl SlaveAssignment {
    /// An optional slave the master boots: bits 0 and 2.
    pub const BOOTED: SlaveAssignment = SlaveAssignment(Self::SLAVE | Self::BOOT);

    /// The 1F81h word as it is.
    #[must_use]
    pub const fn from_raw(raw: u32) -> Self {
        SlaveAssignment(raw)
    }

    /// The 1F81h word.
    #[must_use]
    pub const fn raw(self) -> u32 {
        self.0
    }

    /// The same assignment with node guarding: guard time (whole ms,
    /// saturating at 65 535) and retry factor (the life time factor).
    #[must_use]
    pub fn with_guarding(self, guard_time: Duration, retry_factor: u8) -> Self {
        let guard = u32::from(crate::clock::millis_u16(guard_time));
        SlaveAssignment((self.0 & 0xFF) | u32::from(retry_factor) << 8 | guard << 16)
    }

    /// Bits 8-15: the retry factor (node guarding's life time factor).
    #[must_use]
    pub const fn retry_factor(self) -> u8 {
        (self.0 >> 8) as u8
    }

    /// Bits 16-31: the guard time (0: the node is not guarded).
    #[must_use]
    pub const fn guard_time(self) -> Duration {
        Duration::from_millis((self.0 >> 16) as u64)
    }
}

/// Declares each flag bit of 1F81h once: its mask, its test and, for the
/// bits an application sets on [`SlaveAssignment::BOOTED`], its setter.
macro_rules! assignment_bits {
    ($(
        $(#[$doc:meta])*
        $mask:ident = $bit:literal, $test:ident $(, $set:ident)?;
    )*) => {
        impl SlaveAssignment {
            $(
                #[doc = concat!("Bit ", stringify!($bit), " of 1F81h.")]
                const $mask: u32 = 1 << $bit;

                $(#[$doc])*
                #[must_use]
                pub const fn $test(self) -> bool {
                    self.0 & Self::$mask != 0
                }

                $(
                    #[doc = concat!(
                        "The same assignment with bit ", stringify!($bit),
                        " set ([`", stringify!($test), "`](Self::", stringify!($test), "))."
                    )]
                    #[must_use]
                    pub const fn $set(self) -> Self {
                        SlaveAssignment(self.0 | Self::$mask)
                    }
                )?
            )*
        }
    };
}

assignment_bits! {
    /// Bit 0: the node is a slave of this master (in its network list).
    SLAVE = 0, is_slave;
    /// Bit 2: the master checks and configures the slave; when clear, the
    /// manager skips the identity check and the configuration download
    /// and only starts error control and the node.
    BOOT = 2, may_boot;
    /// Bit 3: the slave is mandatory: the network is not started while
    /// it has not booted.
    MANDATORY = 3, is_mandatory, mandatory;
    /// Bit 4: keep alive: its communication is not reset at start-up; its
    /// boot process begins at once.
    KEEP_ALIVE = 4, keeps_alive, keep_alive;
    /// Bit 5: verify the slave's application software before its
    /// configuration is written (CiA 302-2 "Network management", section
    /// 4.4, "check and update software version"): its 1F56h sub 1
    /// "program software identification" against 1F55h
    /// ([`ExpectedIdentity::software`]) and its 1F52h "verify application
    /// software" date and time against 1F53h and 1F54h
    /// ([`ExpectedIdentity::software_date`],
    /// [`ExpectedIdentity::software_time`]), whichever are configured
    /// (neither: error status G). A difference ends the boot with H, or
    /// downloads the program with bit 6.
    VERIFY_SOFTWARE = 5, verifies_software, verify_software;
    /// Bit 6: software update allowed: when the software check of bit 5
    /// finds a difference, the manager downloads [`NodeConfig::program`]
    /// into the slave's 1F50h sub 1 (CiA 302-3 "Configuration and program
    /// download", the program download objects: stop by 1F51h, clear,
    /// download, check 1F57h and 1F56h, start) and boots it again; no
    /// program, or a download that fails, is error status I. Not acted on
    /// for a keep-alive slave (bit 4), which stays H, as lely-core has it.
    SOFTWARE_UPDATE = 6, allows_software_update, allow_software_update;
}

/// The identity a slave must have: 1F84h "device type identification" and
/// 1F85h-1F88h "vendor identification", "product code", "revision number"
/// and "serial number" (CiA 302-2 "Network management", section 4.2),
/// compared with the slave's 1000h and 1018h sub 1-4 (CiA 301 sections
/// 7.5.2.1 and 7.5.2.30). **0 means "do not check"**, as in CiA 302-2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ExpectedIdentity {
    /// 1F84h: the expected 1000h.
    pub device_type: u32,
    /// 1F85h: the expected 1018h sub 1.
    pub vendor_id: u32,
    /// 1F86h: the expected 1018h sub 2.
    pub product_code: u32,
    /// 1F87h: the expected 1018h sub 3.
    pub revision: u32,
    /// 1F88h: the expected 1018h sub 4.
    pub serial: u32,
    /// 1F55h "expected software identification" (CiA 302-3
    /// "Configuration and program download", section 4): the expected
    /// 1F56h sub 1 "program software identification" of the slave, checked
    /// when its 1F81h has [`SlaveAssignment::verify_software`]; there, 0
    /// means "not configured", as lely-core reads it.
    pub software: u32,
    /// 1F53h "expected application software date" (CiA 302-2 "Network
    /// management", section 4.2; CiA 302-3 section 4): the expected 1F52h
    /// sub 1 "application software date" of the slave (days since 1
    /// January 1984, as CiA 301's TIME_OF_DAY counts them), checked with
    /// [`SlaveAssignment::verify_software`]. 0: not configured (no date
    /// and time check).
    pub software_date: u32,
    /// 1F54h "expected application software time": the expected 1F52h sub
    /// 2 "application software time" (ms after midnight), checked with the
    /// date whenever [`software_date`](Self::software_date) is configured
    /// (here 0 is midnight, not "unconfigured").
    pub software_time: u32,
}

impl ExpectedIdentity {
    /// The expected value of 1018h `sub` (1-4), 0 (no check) for any other.
    #[must_use]
    pub const fn identity(&self, sub: u8) -> u32 {
        match sub {
            1 => self.vendor_id,
            2 => self.product_code,
            3 => self.revision,
            4 => self.serial,
            _ => 0,
        }
    }
}

/// What the manager knows of one slave: its node-ID, its 1F81h
/// assignment, its expected identity, its configuration as a concise DCF
/// (CiA 302-3 section 4.3, the format of object 1F22h: written entry by
/// entry in order) and the heartbeat period it produces once configured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeConfig<'a> {
    /// The slave.
    pub node: NodeId,
    /// Its 1F81h sub-index.
    pub assignment: SlaveAssignment,
    /// Its 1F84h-1F88h sub-indexes.
    pub expected: ExpectedIdentity,
    /// Its configuration, written entry by entry in order (`None`:
    /// nothing written).
    pub configuration: Option<ConciseDcf<'a>>,
    /// The heartbeat producer time (1017h) the slave has once configured:
    /// the manager consumes its heartbeat. `None`: no heartbeat (node
    /// guarding with the 1F81h guard time, if non-zero).
    pub heartbeat: Option<Duration>,
    /// The program image downloaded into the slave's 1F50h sub 1 when its
    /// software check fails and 1F81h bit 6
    /// ([`SlaveAssignment::allow_software_update`]) allows an update (the
    /// manager's 1F58h "program data" of CiA 302-3). `None`: nothing to
    /// download, an update that is required fails with error status I.
    pub program: Option<&'a [u8]>,
}

impl<'a> NodeConfig<'a> {
    /// An optional slave the master boots (1F81h bits 0 and 2), nothing
    /// checked, nothing written, no error control.
    #[must_use]
    pub const fn new(node: NodeId) -> Self {
        NodeConfig {
            node,
            assignment: SlaveAssignment::BOOTED,
            expected: ExpectedIdentity {
                device_type: 0,
                vendor_id: 0,
                product_code: 0,
                revision: 0,
                serial: 0,
                software: 0,
                software_date: 0,
                software_time: 0,
            },
            configuration: None,
            heartbeat: None,
            program: None,
        }
    }

    /// The same slave configured by `dcf`; when `dcf` writes a non-zero
    /// producer heartbeat time (1017h, CiA 301 section 7.5.2.21: UNSIGNED16
    /// ms), that is the heartbeat the manager consumes.
    ///
    /// ```
    /// use canopen_codec::manager::NodeConfig;
    /// use canopen_codec::od::ConciseDcf;
    /// use canopen_codec::NodeId;
    /// use core::time::Duration;
    ///
    /// // One entry: 1017h:00 = 500 ms.
    /// let bytes = [1, 0, 0, 0, 0x17, 0x10, 0, 2, 0, 0, 0, 0xF4, 0x01];
    /// let dcf = ConciseDcf::new_checked(&bytes).unwrap();
    /// let node = NodeConfig::new(NodeId::new(5).unwrap()).with_configuration(dcf);
    /// assert_eq!(node.heartbeat, Some(Duration::from_millis(500)));
    /// ```
    #[must_use]
    pub fn with_configuration(mut self, dcf: ConciseDcf<'a>) -> Self {
        let producer = dcf
            .iter()
            .filter(|e| e.addr == Address::index(PRODUCER_HEARTBEAT_TIME))
            .find_map(|e| <[u8; 2]>::try_from(e.data).ok())
            .map(u16::from_le_bytes);
        if let Some(ms) = producer.filter(|ms| *ms != 0) {
            self.heartbeat = Some(Duration::from_millis(u64::from(ms)));
        }
        self.configuration = Some(dcf);
        self
    }
}

/// Object 1017h "producer heartbeat time" (CiA 301 section 7.5.2.21).
const PRODUCER_HEARTBEAT_TIME: u16 = 0x1017;

/// The manager's times and start-up word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ManagerConfig {
    /// 1F80h.
    pub startup: NmtStartup,
    /// The SDO timeout of every transfer (default 500 ms; restarts on
    /// every segment, as the SDO client's).
    pub sdo_timeout: Duration,
    /// How many times an unanswered read of 1000h is tried again before
    /// the boot ends with error B (default 2: three tries in all).
    pub retries: u8,
    /// How long after the NMT reset communication the boot process waits
    /// for the slave's boot-up message before it reads 1000h anyway
    /// (default 1 s).
    pub boot_up_wait: Duration,
    /// Added to one and a half heartbeat periods to make the consumer
    /// time the manager watches a slave's heartbeat with (default 20 ms).
    pub heartbeat_margin: Duration,
    /// 1F89h "boot time" (CiA 302-2 section 4.2, object 1F89h): how long
    /// after [`BootManager::start`](super::BootManager::start) the
    /// mandatory slaves have to boot; when it has passed with the network
    /// not started, each mandatory slave not booted is reported
    /// ([`BootTimeElapsed`](super::BootEvent::BootTimeElapsed)). Zero
    /// (the default): no limit, as 1F89h = 0.
    pub boot_time: Duration,
    /// How long after an error B (no answer to 1000h) the boot process of
    /// the slave starts again by itself (CiA 302-2 section 4.4: the boot
    /// of a slave that is absent is retried asynchronously). Zero (the
    /// default): not retried; its boot-up message still starts it again.
    pub retry_interval: Duration,
}

impl Default for ManagerConfig {
    fn default() -> Self {
        ManagerConfig {
            startup: NmtStartup::default(),
            sdo_timeout: Duration::from_millis(500),
            retries: 2,
            boot_up_wait: Duration::from_secs(1),
            heartbeat_margin: Duration::from_millis(20),
            boot_time: Duration::ZERO,
            retry_interval: Duration::ZERO,
        }
    }
}

impl ManagerConfig {
    /// The consumer time of a slave producing heartbeats every `period`:
    /// 1.5 x `period` + [`heartbeat_margin`](Self::heartbeat_margin)
    /// (CiA 301 section 7.2.8.3.2.2: the consumer time must exceed the
    /// producer time; the half period covers bus load and jitter).
    #[must_use]
    pub fn consumer_time(&self, period: Duration) -> Duration {
        period
            .saturating_add(period / 2)
            .saturating_add(self.heartbeat_margin)
    }
}
