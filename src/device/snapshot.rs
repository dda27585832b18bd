//! What NMT reset node restores of the application objects: the
//! [`PowerOnValues`] an application dictionary keeps at [`Device::boot`].
//!
//! CiA 301 7.3.2.2.1 (NMT states, reset node: its "reset application"
//! step) sets the parameters of the manufacturer-specific and of the
//! standardized device profile area to their power-on values; the
//! application's measurements and identity are not parameters. So a dictionary says what its power-on
//! values are: a profile keeps its `rw` objects (what an SDO download or an
//! RPDO can change), a generic dictionary such as
//! `od::MemoryDictionary` a copy of itself.
//!
//! [`Device::boot`]: super::Device::boot

/// The part of an application dictionary that NMT reset node sets back to
/// its value at [`Device::boot`](super::Device::boot): the device core keeps
/// one [`Snapshot`](Self::Snapshot) (taken at boot) and restores it at every
/// reset node. What the snapshot leaves out keeps the value the application
/// last set.
///
/// A profile's dictionary snapshots what the bus can change (its `rw`
/// objects); a dictionary with nothing to leave out snapshots itself:
///
/// ```
/// use canopen_codec::device::PowerOnValues;
///
/// /// A charger setpoint the bus writes, a measurement the application sets.
/// #[derive(Debug, Clone)]
/// struct Objects {
///     setpoint: u16,
///     measured: u16,
/// }
///
/// impl PowerOnValues for Objects {
///     type Snapshot = u16;
///     fn snapshot(&self) -> u16 {
///         self.setpoint
///     }
///     fn restore(&mut self, snapshot: &u16) {
///         self.setpoint = *snapshot;
///     }
/// }
///
/// /// Everything is a parameter: a full copy.
/// #[derive(Debug, Clone, PartialEq)]
/// struct Parameters([u32; 4]);
///
/// impl PowerOnValues for Parameters {
///     type Snapshot = Self;
///     fn snapshot(&self) -> Self {
///         self.clone()
///     }
///     fn restore(&mut self, snapshot: &Self) {
///         self.clone_from(snapshot);
///     }
/// }
///
/// let mut o = Objects { setpoint: 10, measured: 3 };
/// let at_boot = o.snapshot();
/// (o.setpoint, o.measured) = (42, 4); // an SDO write, a new measurement
/// o.restore(&at_boot); // reset node
/// assert_eq!((o.setpoint, o.measured), (10, 4));
/// ```
pub trait PowerOnValues {
    /// What is kept at boot.
    type Snapshot: Clone;

    /// The values reset node will restore, as they are now.
    fn snapshot(&self) -> Self::Snapshot;

    /// Sets the values of `snapshot` back (reset node); whatever the
    /// snapshot does not hold stays as it is.
    fn restore(&mut self, snapshot: &Self::Snapshot);

    /// The snapshot's bytes as 1010h stores them (CiA 301 section
    /// 7.5.2.13, the application parameters; feature `store`); `None`
    /// (the default): the parameters cannot be stored, and 1010h/1011h
    /// sub 3 read 0.
    #[cfg(feature = "store")]
    fn parameter_bytes(snapshot: &Self::Snapshot) -> Option<&[u8]> {
        let _ = snapshot;
        None
    }

    /// The same bytes, to load a stored record into (feature `store`).
    #[cfg(feature = "store")]
    fn parameter_bytes_mut(snapshot: &mut Self::Snapshot) -> Option<&mut [u8]> {
        let _ = snapshot;
        None
    }

    /// A word that tells this dictionary's parameter layout from another's:
    /// a stored record of another layout is ignored (feature `store`).
    #[cfg(feature = "store")]
    fn parameter_layout() -> u32 {
        0
    }
}

/// A fixed-word dictionary (the profiles'): its
/// [`FixedObjects::PARAMETERS`](crate::od::FixedObjects::PARAMETERS) are
/// restored, as they were at boot.
impl<O: crate::od::FixedObjects> PowerOnValues for crate::od::FixedDictionary<O> {
    type Snapshot = O::Parameters;

    fn snapshot(&self) -> O::Parameters {
        self.parameters()
    }

    fn restore(&mut self, snapshot: &O::Parameters) {
        self.restore_parameters(snapshot);
    }

    #[cfg(feature = "store")]
    fn parameter_bytes(snapshot: &O::Parameters) -> Option<&[u8]> {
        Some(snapshot.as_ref())
    }

    #[cfg(feature = "store")]
    fn parameter_bytes_mut(snapshot: &mut O::Parameters) -> Option<&mut [u8]> {
        Some(snapshot.as_mut())
    }

    /// The CRC-16 of the parameters' index and sub-index bytes, and their
    /// total length above it.
    #[cfg(feature = "store")]
    fn parameter_layout() -> u32 {
        let crc = O::PARAMETERS.iter().fold(0, |crc, &(index, sub)| {
            let [lo, hi] = index.to_le_bytes();
            crate::sdo::crc16_update(crc, &[lo, hi, sub])
        });
        let len = core::mem::size_of::<O::Parameters>() as u32;
        u32::from(crc) | len << 16
    }
}

/// A generic dictionary: every object is restored (a full copy).
#[cfg(feature = "alloc")]
impl PowerOnValues for crate::od::MemoryDictionary {
    type Snapshot = Self;

    fn snapshot(&self) -> Self {
        self.clone()
    }

    fn restore(&mut self, snapshot: &Self) {
        self.clone_from(snapshot);
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::PowerOnValues;
    use crate::od::{Access, MemoryDictionary, ObjectDictionary};

    #[test]
    fn memory_dictionary_restores_every_object() {
        let mut od = MemoryDictionary::new();
        od.insert(0x2000, 0, Access::ReadWrite, &[1]);
        od.insert(0x2001, 0, Access::ReadOnly, &[2, 0]);
        let at_boot = od.snapshot();
        od.write(0x2000, 0, 0, &[9]).unwrap();
        od.finish_write(0x2000, 0, 1).unwrap();
        od.insert(0x2001, 0, Access::ReadOnly, &[7, 7]);
        od.insert(0x2002, 0, Access::ReadOnly, &[5]);
        od.restore(&at_boot);
        assert_eq!(od, at_boot);
    }
}
