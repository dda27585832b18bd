//! A device configuration file (DCF, CiA 306 "Electronic data sheet
//! specification for CANopen", section 4 "EDS structure": an EDS whose
//! objects carry the values of one configured node) written from an EDS
//! plus values, and turned into the concise DCF a configuration manager
//! downloads (CiA 302-3 "Configuration and program download", section 4;
//! the value of 1F22h).
//!
//! **What the concise DCF holds.** Each writable value (`AccessType` `rw`,
//! `wo`, `rwr` or `rww`) whose `ParameterValue` the DCF gives, encoded by
//! its `DataType` (see [`encode_value`]), with `$NODEID` read as the
//! `NodeID` of `[DeviceComissioning]`. Never a `ro` or `const` value: the
//! node refuses the write (CiA 301 section 7.2.4.3.17, abort 06010002h),
//! and the identity objects 1000h and 1018h are what a manager checks, not
//! what it writes (CiA 302-2 section 4.4, the boot slave process). A value
//! with only a `DefaultValue` is left out: it is what the device holds
//! after a reset of its application and communication (CiA 301 section
//! 7.3.2.2.1, NMT state initialisation), so writing it again changes
//! nothing; a `ParameterValue` is the DCF's statement that the integrator
//! configured the value. An empty `ParameterValue=` configures nothing (tools write
//! the key for every object), for a string as for a number.
//!
//! **Order.** Index and sub-index order, but a PDO is written by the CiA
//! 301 procedure (section 7.5.2.35 "RPDO mapping parameter", the same as
//! [`crate::pdo::reconfig`] runs): its COB-ID with bit 31 set (disabled)
//! when the DCF configures the COB-ID, the other communication
//! parameters, the mapping count 0, the mapping entries, the mapping
//! count, and last the COB-ID as configured. Each PDO's mapping object
//! (1600h-17FFh, 1A00h-1BFFh) follows its communication object
//! (1400h-15FFh, 1800h-19FFh) directly.

use alloc::string::String;
use alloc::vec::Vec;

use super::dictionary::data_type_of;
use super::{encode_value, AccessType, Commissioning, Eds, UnservedReason};
use crate::od::index::{RPDO_COMMUNICATION, TPDO_COMMUNICATION};
use crate::od::{Address, ConciseDcf, ConciseDcfError, ConciseEntry};
use crate::NodeId;

/// Why a DCF could not be written or turned into a concise DCF.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[non_exhaustive]
pub enum DcfError {
    /// A value for an entry the description does not have.
    #[error("{0}: no such entry in the description")]
    NoEntry(Address),
    /// A value for a `ro` or `const` entry, or one without `AccessType`.
    #[error("{0}: not writable (ro, const or no AccessType)")]
    NotWritable(Address),
    /// A value that does not encode in its entry's data type.
    #[error("{addr}: {reason}")]
    Value {
        /// The entry.
        addr: Address,
        /// Why not.
        reason: UnservedReason,
    },
    /// The concise DCF cannot hold the values (more than `u32::MAX`).
    #[error(transparent)]
    Concise(#[from] ConciseDcfError),
}

/// True for the access types an SDO download may write.
fn writable(access: Option<AccessType>) -> bool {
    access.is_some_and(|a| a.access().is_writable())
}

impl Eds {
    /// The DCF of this description configured as node `node` with `values`
    /// (CiA 306 section 4: what a user gets by configuring a device): a
    /// `[DeviceComissioning]` section with `NodeID` (the other keys an
    /// existing section has are kept), a `ParameterValue` for each given
    /// value, everything else as in the EDS. Write it out with
    /// [`write()`](super::write).
    ///
    /// Values are text as a DCF holds them (`500`, `0x1F4`,
    /// `$NODEID+0x180`); each must name a writable entry and encode in its
    /// data type for `node`, or the whole call fails.
    ///
    /// ```
    /// use canopen_codec::eds::{parse, write};
    /// use canopen_codec::od::Address;
    /// use canopen_codec::NodeId;
    ///
    /// let eds = parse("[1017]\nParameterName=Producer heartbeat time\n\
    ///                  DataType=0x0006\nAccessType=rw\nDefaultValue=0\n").unwrap();
    /// let node = NodeId::new(5).unwrap();
    /// let dcf = eds.to_dcf(node, [(Address::new(0x1017, 0), "500")]).unwrap();
    /// let text = write(&dcf);
    /// assert!(text.contains("ParameterValue=500\n"));
    /// assert!(text.contains("[DeviceComissioning]\nNodeID=5\n"));
    /// assert_eq!(dcf.to_concise_dcf().unwrap(), [1, 0, 0, 0, 0x17, 0x10, 0, 2, 0, 0, 0, 0xF4, 1]);
    /// ```
    pub fn to_dcf<'v>(
        &self,
        node: NodeId,
        values: impl IntoIterator<Item = (Address, &'v str)>,
    ) -> Result<Eds, DcfError> {
        let mut dcf = self.clone();
        let mut c = dcf.commissioning.take().unwrap_or_default();
        set_key(&mut c, "NodeID", alloc::format!("{}", node.raw()));
        c.node_id = Some(node.raw());
        dcf.commissioning = Some(c);
        for (addr, text) in values {
            dcf.set_parameter_value(addr, text)?;
        }
        Ok(dcf)
    }

    /// Sets the `ParameterValue` of `addr` to `text` after checking that
    /// the entry exists, is writable and that `text` encodes in its data
    /// type (with `$NODEID` as the commissioning `NodeID`, 1 when none is
    /// set yet: the check is of the form).
    pub fn set_parameter_value(&mut self, addr: Address, text: &str) -> Result<(), DcfError> {
        let node = self.node_id().map_or(1, NodeId::raw);
        let e = self.entry_mut(addr).ok_or(DcfError::NoEntry(addr))?;
        if !writable(e.access) {
            return Err(DcfError::NotWritable(addr));
        }
        let value = |reason| DcfError::Value { addr, reason };
        let data_type = data_type_of(e)
            .map_err(value)?
            .ok_or(DcfError::NoEntry(addr))?;
        encode_value(data_type, text, Some(node)).map_err(|e| value(UnservedReason::Value(e)))?;
        e.parameter_value = Some(String::from(text));
        Ok(())
    }

    /// The node id of a DCF: `NodeID` of `[DeviceComissioning]`.
    #[must_use]
    pub fn node_id(&self) -> Option<NodeId> {
        self.commissioning
            .as_ref()
            .and_then(|c| c.node_id)
            .and_then(NodeId::new)
    }

    /// The values a DCF configures, in index and sub-index order, encoded:
    /// each writable entry with a non-empty `ParameterValue` (see the
    /// module documentation for why exactly these).
    pub fn configured_values(&self) -> Result<Vec<(Address, Vec<u8>)>, DcfError> {
        let node = self.node_id().map(NodeId::raw);
        let mut out = Vec::new();
        for (index, sub, e) in self.value_entries() {
            let addr = Address::new(index, sub);
            let Some(text) = e
                .parameter_value
                .as_deref()
                .filter(|t| !t.trim().is_empty())
            else {
                continue;
            };
            if !writable(e.access) {
                continue;
            }
            let value = |reason| DcfError::Value { addr, reason };
            let Some(data_type) = data_type_of(e).map_err(value)? else {
                continue;
            };
            let bytes =
                encode_value(data_type, text, node).map_err(|e| value(UnservedReason::Value(e)))?;
            out.push((addr, bytes));
        }
        Ok(out)
    }

    /// The concise DCF of this DCF (CiA 302-3 section 4): the
    /// [`configured_values`](Self::configured_values) in the order the
    /// module documentation gives (a PDO by the CiA 301 procedure).
    pub fn to_concise_dcf(&self) -> Result<Vec<u8>, DcfError> {
        let ordered = pdo_order(self.configured_values()?);
        ConciseDcf::encode_vec(
            ordered
                .iter()
                .map(|(addr, data)| ConciseEntry::new(*addr, data)),
        )
        .map_err(DcfError::Concise)
    }

    /// The entry holding the value at `addr`, for writing.
    fn entry_mut(&mut self, addr: Address) -> Option<&mut super::Entry> {
        let o = self.objects.get_mut(&addr.index)?;
        if o.subs.is_empty() {
            return (addr.sub == 0).then_some(&mut o.entry);
        }
        o.subs.get_mut(&addr.sub)
    }
}

/// Sets `key` in a commissioning section (replacing it in any case).
fn set_key(c: &mut Commissioning, key: &str, value: String) {
    c.keys.0.retain(|(k, _)| !k.eq_ignore_ascii_case(key));
    c.keys.0.push((String::from(key), value));
}

/// The communication index of the PDO `index` belongs to (its own for a
/// communication object, 200h below for a mapping object), and whether it
/// is the mapping: CiA 301 section 7.5.2.35-7.5.2.38 give each direction
/// 512 PDOs (1400h-15FFh / 1600h-17FFh receive, 1800h-19FFh / 1A00h-1BFFh
/// transmit).
fn pdo_of(index: u16) -> Option<(u16, bool)> {
    const PDOS: u16 = 0x200;
    [RPDO_COMMUNICATION, TPDO_COMMUNICATION]
        .into_iter()
        .find_map(|comm| match index.checked_sub(comm)? {
            n if n < PDOS => Some((index, false)),
            n if n < 2 * PDOS => Some((index.wrapping_sub(PDOS), true)),
            _ => None,
        })
}

/// Where a configured value goes in the download order: the object (a
/// PDO's mapping under its communication index), the step of the PDO
/// procedure, the sub-index.
fn order_key(addr: Address) -> (u16, u8, u8) {
    match pdo_of(addr.index) {
        // The COB-ID last (enable), the other parameters first.
        Some((comm, false)) if addr.sub == 1 => (comm, 4, 1),
        Some((comm, false)) => (comm, 0, addr.sub),
        // The count after the entries.
        Some((comm, true)) if addr.sub == 0 => (comm, 3, 0),
        Some((comm, true)) => (comm, 2, addr.sub),
        None => (addr.index, 0, addr.sub),
    }
}

/// Orders `values` for download: index order, each PDO by the CiA 301
/// procedure (disable, parameters, count 0, entries, count, COB-ID).
fn pdo_order(mut values: Vec<(Address, Vec<u8>)>) -> Vec<(Address, Vec<u8>)> {
    values.sort_by_key(|(a, _)| order_key(*a));
    let mut out = Vec::with_capacity(values.len());
    let mut current: Option<u16> = None;
    for (addr, data) in &values {
        if let Some((comm, is_mapping)) = pdo_of(addr.index) {
            if current != Some(comm) {
                current = Some(comm);
                // Disable first, with the configured COB-ID's bit 31 set.
                let cob = values
                    .iter()
                    .find(|(a, _)| *a == Address::new(comm, 1))
                    .and_then(|(_, d)| <[u8; 4]>::try_from(d.as_slice()).ok());
                if let Some(cob) = cob {
                    let disabled = u32::from_le_bytes(cob) | 0x8000_0000;
                    out.push((Address::new(comm, 1), disabled.to_le_bytes().to_vec()));
                }
            }
            // Before the first mapping entry: the count 0.
            let first_entry = is_mapping
                && addr.sub != 0
                && out
                    .last()
                    .is_none_or(|(a, _): &(Address, Vec<u8>)| a.index != addr.index);
            if first_entry
                && values
                    .iter()
                    .any(|(a, _)| *a == Address::new(addr.index, 0))
            {
                out.push((Address::new(addr.index, 0), alloc::vec![0]));
            }
        }
        out.push((*addr, data.clone()));
    }
    out
}

#[cfg(test)]
#[path = "dcf_tests.rs"]
mod tests;
