//! The client side of PDO reconfiguration (the CiA 301 mapping procedure,
//! as "Delta-Q IC Series CANopen interface specification rev 2.0", section
//! 4.6.2, lists it: set COB-ID bit 31, write 0 to mapping sub 0, write the
//! entries, write their count, clear bit 31): the exact
//! sequence of SDO downloads that remaps a PDO of another node, and a
//! driver that runs it over an SDO [`Client`].
//!
//! The sequence, for PDO n with communication index C and mapping index M:
//!
//! 1. C sub 1 = COB-ID with bit 31 set (disable),
//! 2. M sub 0 = 0,
//! 3. M sub 1..=k = the entries,
//! 4. M sub 0 = k,
//! 5. C sub 1 = the wanted COB-ID (normally valid: enable).

use super::comm::{PdoCobId, PdoDirection};
use super::mapping::{PdoMapping, MAX_ENTRIES};
use crate::abort::AbortCode;
use crate::bytes::InlineData;
use crate::clock::Timestamp;
use crate::cob_id::PdoNumber;
use crate::machine::Machine;
use crate::queue::EventQueue;
use crate::sdo::{AbortOrigin, Client, ClientConfig, ClientError, ClientEvent, TransferEnd};

/// One SDO download of the procedure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Step {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The value, little-endian (1 or 4 bytes).
    pub value: InlineData<4>,
}

/// The whole procedure: at most 2 + 8 + 2 steps, no allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Plan {
    steps: [Step; MAX_ENTRIES + 4],
    len: usize,
}

impl Plan {
    /// The downloads that set PDO `n` (`dir` as seen from the remote node)
    /// to `cob_id` and `mapping`.
    ///
    /// ```
    /// use canopen_codec::pdo::{MappingEntry, PdoCobId, PdoDirection, PdoMapping, Plan};
    /// use canopen_codec::PdoNumber;
    /// let m = PdoMapping::new(&[MappingEntry::new(0x6010, 0, 16), MappingEntry::new(0x6000, 0, 8)]).unwrap();
    /// let plan = Plan::new(PdoDirection::Transmit, PdoNumber::P0, PdoCobId::standard(0x181), &m);
    /// let steps: Vec<(u16, u8, Vec<u8>)> =
    ///     plan.steps().iter().map(|s| (s.index, s.sub, s.value.as_slice().to_vec())).collect();
    /// assert_eq!(steps, [
    ///     (0x1800, 1, vec![0x81, 0x01, 0x00, 0x80]),
    ///     (0x1A00, 0, vec![0]),
    ///     (0x1A00, 1, vec![0x10, 0x00, 0x10, 0x60]),
    ///     (0x1A00, 2, vec![0x08, 0x00, 0x00, 0x60]),
    ///     (0x1A00, 0, vec![2]),
    ///     (0x1800, 1, vec![0x81, 0x01, 0x00, 0x00]),
    /// ]);
    /// ```
    #[must_use]
    pub fn new(dir: PdoDirection, n: PdoNumber, cob_id: PdoCobId, mapping: &PdoMapping) -> Self {
        let comm = dir.comm_index(n);
        let map = dir.mapping_index(n);
        let step = |index, sub, bytes: &[u8]| Step {
            index,
            sub,
            value: InlineData::new(bytes).unwrap_or_default(),
        };
        let mut steps = [step(0, 0, &[]); MAX_ENTRIES + 4];
        let mut len = 0;
        let mut push = |s: Step| {
            if let Some(slot) = steps.get_mut(len) {
                *slot = s;
                len += 1;
            }
        };
        push(step(
            comm,
            1,
            &cob_id.with_valid(false).to_u32().to_le_bytes(),
        ));
        push(step(map, 0, &[0]));
        for (i, e) in mapping.entries().iter().enumerate() {
            push(step(map, i as u8 + 1, &e.to_u32().to_le_bytes()));
        }
        push(step(map, 0, &[mapping.len() as u8]));
        push(step(comm, 1, &cob_id.to_u32().to_le_bytes()));
        Plan { steps, len }
    }

    /// The downloads, in order.
    #[must_use]
    pub fn steps(&self) -> &[Step] {
        self.steps.get(..self.len).unwrap_or(&[])
    }
}

/// How a reconfiguration ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ReconfigEvent {
    /// Every step was accepted.
    Done,
    /// Step number `step` (0-based, in [`Plan::steps`]) failed.
    Failed {
        /// Which step.
        step: usize,
        /// The download that failed.
        at: Step,
        /// The abort code (the server's, or ours on a timeout).
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
}

/// Runs a [`Plan`] with its own SDO [`Client`]; implements [`Machine`], the
/// crate's state-machine contract. Exactly one [`ReconfigEvent`] ends a run;
/// the queue keeps the outcomes of the last 2 runs and counts older ones it
/// drops.
#[derive(Debug)]
pub struct Reconfigurer {
    client: Client<InlineData<4>>,
    plan: Plan,
    next: usize,
    running: bool,
    outcomes: EventQueue<ReconfigEvent, 2>,
}

impl Reconfigurer {
    /// An idle driver talking to the server described by `config`.
    pub fn new(config: ClientConfig) -> Self {
        Reconfigurer {
            client: Client::new(config),
            plan: Plan {
                steps: [Step {
                    index: 0,
                    sub: 0,
                    value: InlineData::default(),
                }; MAX_ENTRIES + 4],
                len: 0,
            },
            next: 0,
            running: false,
            outcomes: EventQueue::new(ReconfigEvent::Done),
        }
    }

    /// True while a plan runs.
    #[must_use]
    pub const fn is_running(&self) -> bool {
        self.running
    }

    /// Starts `plan`. Fails with [`ClientError::Busy`] while another runs.
    pub fn start(&mut self, now: Timestamp, plan: Plan) -> Result<(), ClientError> {
        if self.running {
            return Err(ClientError::Busy);
        }
        self.plan = plan;
        self.next = 0;
        self.running = true;
        self.advance(now);
        Ok(())
    }

    fn advance(&mut self, now: Timestamp) {
        match self.plan.steps().get(self.next).copied() {
            Some(step) => {
                if self
                    .client
                    .start_download(now, step.index, step.sub, step.value)
                    .is_err()
                {
                    self.finish(ReconfigEvent::Failed {
                        step: self.next,
                        at: step,
                        code: AbortCode::GeneralError,
                        origin: AbortOrigin::Local,
                    });
                }
            }
            None => self.finish(ReconfigEvent::Done),
        }
    }

    fn finish(&mut self, event: ReconfigEvent) {
        self.running = false;
        self.outcomes.push(event);
    }

    fn drain(&mut self, now: Timestamp) {
        while let Some(e) = self.client.poll_event() {
            match e {
                ClientEvent::Ended(TransferEnd::Downloaded { .. }) if self.running => {
                    self.next += 1;
                    self.advance(now);
                }
                ClientEvent::Ended(TransferEnd::Aborted { code, origin, .. }) if self.running => {
                    let at = self.plan.steps().get(self.next).copied();
                    if let Some(at) = at {
                        self.finish(ReconfigEvent::Failed {
                            step: self.next,
                            at,
                            code,
                            origin,
                        });
                    }
                }
                _ => {}
            }
        }
    }
}

crate::sdo::sdo_client_sequence_machine!(impl Machine for Reconfigurer, ReconfigEvent, outcomes);
