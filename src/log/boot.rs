//! What `canopen-boot` does as the network's manager, as a library: each
//! slave's [`NodeConfig`] from its DCF (the concise DCF of its configured
//! values, the expected identity from its own 1000h and 1018h), the
//! [`BootManager`] run over the caller's frames and clock ([`BootRun`]),
//! and the JSON line of each boot's end and of each later event
//! ([`event_json`]).
//!
//! The expected identity (CiA 302-2 "Network management", objects
//! 1F84h-1F88h) is the DCF's 1000h and 1018h sub 1-4 values; a value of 0
//! or none is not checked, as CiA 302-2 says of 0. What a DCF has no
//! place for, the program's options set per node ([`NodeSetting`]): the
//! 1F81h flags mandatory and keep alive, and the software check's expected
//! values (1F55h, 1F53h, 1F54h).

use std::string::{String, ToString};
use std::vec::Vec;

use crate::clock::Timestamp;
use crate::cob_id::NodeId;
use crate::eds::{self, eval_int, Eds};
use crate::frame::CanFrame;
use crate::machine::Machine;
use crate::manager::{
    BootError, BootEvent, BootManager, ExpectedIdentity, ManagerConfig, ManagerError, NodeConfig,
    SlaveAssignment,
};
use crate::od::{ConciseDcf, ConciseDcfError};

/// The most slaves one run manages: every node-ID.
pub const MAX_SLAVES: usize = 127;

/// The events the run's manager keeps between two steps (the queue's
/// largest size): more than one step makes, even starting 127 nodes at once.
const EVENTS: usize = 255;

/// One slave as its DCF describes it: what the manager writes and what it
/// checks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BootNode {
    /// The slave.
    pub node: NodeId,
    /// Its configuration (the DCF's writable `ParameterValue`s).
    pub concise: Vec<u8>,
    /// 1000h and 1018h sub 1-4 of the DCF (0: not checked).
    pub expected: ExpectedIdentity,
    /// 1F81h bit 3.
    pub mandatory: bool,
    /// 1F81h bit 4.
    pub keep_alive: bool,
}

/// One setting `canopen-boot`'s options give a node beyond its DCF.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeSetting {
    /// 1F81h bit 3: the network starts once it has booted.
    Mandatory,
    /// 1F81h bit 4: not reset at the start; found operational, it is
    /// reported with L and left running.
    KeepAlive,
    /// 1F55h: its expected 1F56h sub 1 "program software identification"
    /// (sets 1F81h bit 5).
    SoftwareId(u32),
    /// 1F53h: its expected 1F52h sub 1 "application software date", days
    /// since 1 January 1984 (sets 1F81h bit 5).
    SoftwareDate(u32),
    /// 1F54h: its expected 1F52h sub 2 "application software time", ms
    /// after midnight, checked with the date (sets 1F81h bit 5).
    SoftwareTime(u32),
}

impl BootNode {
    /// The slave `node` described by the DCF (or EDS) `text`: its
    /// `$NODEID` values are `node`'s.
    ///
    /// ```
    /// use canopen_codec::log::boot::BootNode;
    /// use canopen_codec::NodeId;
    ///
    /// let dcf = "[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\n\
    ///            DefaultValue=0x00010191\n\
    ///            [1017]\nParameterName=Producer heartbeat time\nDataType=0x0006\n\
    ///            AccessType=rw\nDefaultValue=0\nParameterValue=500\n";
    /// let node = BootNode::from_dcf(NodeId::new(5).unwrap(), dcf.as_bytes()).unwrap();
    /// assert_eq!(node.expected.device_type, 0x0001_0191);
    /// assert_eq!(node.concise, [1, 0, 0, 0, 0x17, 0x10, 0, 2, 0, 0, 0, 0xF4, 1]);
    /// ```
    pub fn from_dcf(node: NodeId, text: &[u8]) -> Result<Self, String> {
        let parsed = eds::parse_bytes(text).map_err(|e| e.to_string())?;
        let dcf = parsed.to_dcf(node, []).map_err(|e| e.to_string())?;
        let concise = dcf.to_concise_dcf().map_err(|e| e.to_string())?;
        let value = |index, sub| identity_value(&dcf, node, index, sub);
        let expected = ExpectedIdentity {
            device_type: value(0x1000, 0)?,
            vendor_id: value(0x1018, 1)?,
            product_code: value(0x1018, 2)?,
            revision: value(0x1018, 3)?,
            serial: value(0x1018, 4)?,
            ..ExpectedIdentity::default()
        };
        Ok(BootNode {
            node,
            concise,
            expected,
            mandatory: false,
            keep_alive: false,
        })
    }

    /// Applies one setting of the program's options.
    pub fn apply(&mut self, setting: NodeSetting) {
        match setting {
            NodeSetting::Mandatory => self.mandatory = true,
            NodeSetting::KeepAlive => self.keep_alive = true,
            NodeSetting::SoftwareId(v) => self.expected.software = v,
            NodeSetting::SoftwareDate(v) => self.expected.software_date = v,
            NodeSetting::SoftwareTime(v) => self.expected.software_time = v,
        }
    }

    /// Whether a software check is configured: 1F55h, 1F53h or 1F54h
    /// given (then 1F81h bit 5 is set; 1F54h alone is "objects for the
    /// program check not configured", error status G, as CiA 302-2 has
    /// it).
    #[must_use]
    pub const fn verifies_software(&self) -> bool {
        let e = &self.expected;
        e.software != 0 || e.software_date != 0 || e.software_time != 0
    }

    /// The manager's view of it (its 1017h, if configured, is the heartbeat
    /// consumed).
    pub fn config(&self) -> Result<NodeConfig<'_>, ConciseDcfError> {
        let dcf = ConciseDcf::new_checked(&self.concise)?;
        let mut config = NodeConfig::new(self.node).with_configuration(dcf);
        config.expected = self.expected;
        let mut assignment = SlaveAssignment::BOOTED;
        if self.mandatory {
            assignment = assignment.mandatory();
        }
        if self.keep_alive {
            assignment = assignment.keep_alive();
        }
        if self.verifies_software() {
            assignment = assignment.verify_software();
        }
        config.assignment = assignment;
        Ok(config)
    }
}

/// Applies `settings` (node, setting) to `nodes`; a setting for a node
/// that is not among them is an error.
///
/// ```
/// use canopen_codec::log::boot::{apply_settings, BootNode, NodeSetting};
/// use canopen_codec::NodeId;
///
/// let five = NodeId::new(5).unwrap();
/// let mut nodes = [BootNode::from_dcf(five, b"").unwrap()];
/// apply_settings(&mut nodes, [(five, NodeSetting::SoftwareDate(15_340))]).unwrap();
/// assert!(nodes[0].verifies_software());
/// let six = NodeId::new(6).unwrap();
/// assert!(apply_settings(&mut nodes, [(six, NodeSetting::KeepAlive)]).is_err());
/// ```
pub fn apply_settings(
    nodes: &mut [BootNode],
    settings: impl IntoIterator<Item = (NodeId, NodeSetting)>,
) -> Result<(), String> {
    for (node, setting) in settings {
        let target = nodes.iter_mut().find(|n| n.node == node);
        let Some(target) = target else {
            return Err(std::format!("node {node} is not one of the --node options"));
        };
        target.apply(setting);
    }
    Ok(())
}

/// The DCF's value of `index`:`sub` as a u32 (0: absent, not checked).
fn identity_value(dcf: &Eds, node: NodeId, index: u16, sub: u8) -> Result<u32, String> {
    let Some(text) = dcf.entry(index, sub).and_then(eds::Entry::value) else {
        return Ok(0);
    };
    eval_int(text, Some(node.raw()))
        .ok()
        .and_then(|v| u32::try_from(v).ok())
        .ok_or_else(|| std::format!("{index:04X}h:{sub:02X}: '{text}' is not a UNSIGNED32"))
}

/// The manager of a whole run: the slaves' configurations, borrowed from
/// the [`BootNode`]s, and the manager itself (boxed: 127 places).
#[derive(Debug)]
pub struct BootRun<'a> {
    manager: std::boxed::Box<BootManager<'a, MAX_SLAVES, EVENTS>>,
    failed: bool,
}

impl<'a> BootRun<'a> {
    /// A run managing `nodes` with `config`.
    pub fn new(config: ManagerConfig, nodes: &'a [BootNode]) -> Result<Self, String> {
        let mut manager = std::boxed::Box::new(BootManager::new(config));
        for n in nodes {
            let c = n
                .config()
                .map_err(|e| std::format!("node {}: {e}", n.node))?;
            manager
                .add_node(c)
                .map_err(|e: ManagerError| e.to_string())?;
        }
        Ok(BootRun {
            manager,
            failed: false,
        })
    }

    /// The manager.
    #[must_use]
    pub fn manager(&self) -> &BootManager<'a, MAX_SLAVES, EVENTS> {
        &self.manager
    }

    /// Starts the network at `now`; its frames go to `send`.
    pub fn start(&mut self, now: Timestamp, send: impl FnMut(CanFrame)) {
        self.manager.start(now);
        self.flush(send);
    }

    /// One step at `now`: the frame received, if any, then every timer due;
    /// the frames to send go to `send`, the JSON lines to `report`.
    pub fn step(
        &mut self,
        now: Timestamp,
        frame: Option<&CanFrame>,
        mut send: impl FnMut(CanFrame),
        mut report: impl FnMut(String),
    ) {
        if let Some(f) = frame {
            self.manager.handle_frame(now, f);
            self.flush(&mut send);
        }
        crate::machine::drive_timers(&mut *self.manager, now, |_, f| send(f));
        while let Some(e) = self.manager.poll_event() {
            self.failed |= matches!(e, BootEvent::Error { .. });
            if let Some(line) = event_json(&e) {
                report(line);
            }
        }
    }

    /// Whether a slave's boot has ended in an error (CiA 302-2 "Network
    /// management", the boot slave process's error statuses B to M).
    #[must_use]
    pub fn failed(&self) -> bool {
        self.failed
    }

    /// When [`step`](Self::step) must next be called without a frame.
    #[must_use]
    pub fn deadline(&self) -> Option<Timestamp> {
        self.manager.poll_timeout()
    }

    fn flush(&mut self, mut send: impl FnMut(CanFrame)) {
        while let Some(f) = self.manager.poll_transmit() {
            send(f);
        }
    }
}

/// The JSON line of an event the program reports: the end of a boot
/// (`{"node": 5, "result": "operational"}`, `{"node": 6, "result":
/// "error", "code": "D", "reason": "...", "detail": "..."}`) and the events
/// after it (`{"node": 5, "event": "heartbeat", "code": "E"}`, `"guarding"`
/// with F, `"restored"`, `"start held"` for a mandatory slave that holds
/// the network's start, `"boot time elapsed"` for a mandatory slave not
/// booted when 1F89h has passed, `"initially operational"` with L for a keep-alive
/// slave found running). Other steps have no line.
///
/// ```
/// use canopen_codec::log::boot::event_json;
/// use canopen_codec::manager::{BootError, BootEvent};
/// use canopen_codec::NodeId;
/// let node = NodeId::new(5).unwrap();
/// let lost = BootEvent::Lost { node, error: BootError::HeartbeatLost };
/// assert_eq!(event_json(&lost).unwrap(), r#"{"node": 5, "event": "heartbeat", "code": "E"}"#);
/// ```
#[must_use]
pub fn event_json(event: &BootEvent) -> Option<String> {
    use super::json::{display, string};
    let (node, tail) = match event {
        BootEvent::Operational { node } => (node, String::from(r#""result": "operational""#)),
        BootEvent::Error { node, error } => {
            let mut out = std::format!(
                r#""result": "error", "code": "{}", "reason": "#,
                error.letter()
            );
            string(&mut out, error.reason());
            out.push_str(r#", "detail": "#);
            display(&mut out, error);
            (node, out)
        }
        BootEvent::Lost { node, error } => {
            let what = match error {
                BootError::GuardingLost => "guarding",
                _ => "heartbeat",
            };
            let code = error.letter();
            (node, std::format!(r#""event": "{what}", "code": "{code}""#))
        }
        BootEvent::Restored { node } => (node, String::from(r#""event": "restored""#)),
        BootEvent::StartHeld { node } => (node, String::from(r#""event": "start held""#)),
        BootEvent::BootTimeElapsed { node } => {
            (node, String::from(r#""event": "boot time elapsed""#))
        }
        BootEvent::InitiallyOperational { node } => (
            node,
            String::from(r#""event": "initially operational", "code": "L""#),
        ),
        _ => return None,
    };
    Some(std::format!(r#"{{"node": {}, {tail}}}"#, node.raw()))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::frame::standard_frame as f;
    use crate::manager::NmtStartup;

    #[test]
    fn a_node_that_never_answers_1000h_fails_the_run_with_error_b() {
        let dcf = "[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\n\
                   DefaultValue=0x00010191\n";
        let node = NodeId::new(5).unwrap();
        let nodes = [BootNode::from_dcf(node, dcf.as_bytes()).unwrap()];
        let config = ManagerConfig {
            startup: NmtStartup::MASTER,
            ..ManagerConfig::default()
        };
        let mut run = BootRun::new(config, &nodes).unwrap();
        let (mut sent, mut lines) = (Vec::new(), Vec::new());
        run.start(Timestamp::ZERO, |fr| sent.push(fr));
        // The slave boots up: the manager reads its 1000h.
        let boot_up = f(0x705, &[0]);
        let t = Timestamp::from_micros(1_000);
        run.step(t, Some(&boot_up), |fr| sent.push(fr), |l| lines.push(l));
        assert!(sent.iter().any(|fr| fr.id() == f(0x605, &[]).id()));
        assert!(!run.failed());
        // No answer through the timeout and both retries.
        let mut now = t;
        for _ in 0..100 {
            let Some(d) = run.deadline().filter(|_| !run.failed()) else {
                break;
            };
            now = d.max(now);
            run.step(now, None, |fr| sent.push(fr), |l| lines.push(l));
        }
        assert!(run.failed());
        assert!(lines
            .iter()
            .any(|l| l.starts_with(r#"{"node": 5, "result": "error", "code": "B""#)));
    }
}
