//! The access type of an object description (CiA 306, "Electronic data
//! sheet specification for CANopen", section 4.6 "Object descriptions").
//! The object and data type codes are CiA 301's
//! ([`crate::od::ObjectType`], [`crate::od::DataType`]), re-exported here.

use crate::od::Access;
pub use crate::od::{DataType, ObjectType};

/// `AccessType=` (CiA 306, object descriptions): read any case, written
/// lower case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AccessType {
    /// `ro`: read only.
    ReadOnly,
    /// `wo`: write only.
    WriteOnly,
    /// `rw`: read and write.
    ReadWrite,
    /// `rwr`: read and write, read on process input (mapped into TPDOs).
    ReadWriteRead,
    /// `rww`: read and write, written on process output (mapped into RPDOs).
    ReadWriteWrite,
    /// `const`: read only, never changes.
    Const,
}

impl AccessType {
    /// Reads the keyword, any case, surrounding spaces ignored.
    #[must_use]
    pub fn parse(s: &str) -> Option<Self> {
        let s = s.trim();
        [
            ("ro", AccessType::ReadOnly),
            ("wo", AccessType::WriteOnly),
            ("rw", AccessType::ReadWrite),
            ("rwr", AccessType::ReadWriteRead),
            ("rww", AccessType::ReadWriteWrite),
            ("const", AccessType::Const),
        ]
        .into_iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(s))
        .map(|(_, a)| a)
    }

    /// The keyword as CiA 306 writes it.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            AccessType::ReadOnly => "ro",
            AccessType::WriteOnly => "wo",
            AccessType::ReadWrite => "rw",
            AccessType::ReadWriteRead => "rwr",
            AccessType::ReadWriteWrite => "rww",
            AccessType::Const => "const",
        }
    }

    /// The SDO access rule: `rwr` and `rww` are read-write over SDO.
    #[must_use]
    pub const fn access(self) -> Access {
        match self {
            AccessType::ReadOnly => Access::ReadOnly,
            AccessType::WriteOnly => Access::WriteOnly,
            AccessType::ReadWrite | AccessType::ReadWriteRead | AccessType::ReadWriteWrite => {
                Access::ReadWrite
            }
            AccessType::Const => Access::Const,
        }
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn access_any_case() {
        assert_eq!(AccessType::parse("RW"), Some(AccessType::ReadWrite));
        assert_eq!(AccessType::parse(" Const "), Some(AccessType::Const));
        assert_eq!(AccessType::parse("rWw"), Some(AccessType::ReadWriteWrite));
        assert_eq!(AccessType::parse("rx"), None);
        assert_eq!(AccessType::ReadWriteRead.access(), Access::ReadWrite);
    }
}
