//! LSS frames in words, as the decoder prints them.

use core::fmt;

use super::wire::{Fastscan, LssInquiry, LssMessage, LssMode, LssRequest, LssResponse, LssStatus};

impl fmt::Display for LssMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LssMode::Waiting => f.write_str("waiting"),
            LssMode::Configuration => f.write_str("configuration"),
            LssMode::Unknown(raw) => write!(f, "mode {raw:02X}h"),
        }
    }
}

impl fmt::Display for LssStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use super::wire::LssErrorCode as C;
        match self.code {
            C::Success => f.write_str("ok"),
            C::Refused => f.write_str("error 1 (refused)"),
            C::StorageAccess => f.write_str("error 2 (storage media access error)"),
            C::ImplementationSpecific => {
                write!(f, "error 255 (implementation-specific {})", self.specific)
            }
            C::Reserved(raw) => write!(f, "error {raw} (reserved)"),
        }
    }
}

impl fmt::Display for Fastscan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "fastscan id {:08X} bit {} sub {} next {}",
            self.id_number, self.bit_checked, self.sub, self.next
        )
    }
}

impl fmt::Display for LssRequest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let LssRequest::Fastscan(scan) = self {
            return write!(f, "LSS {scan}");
        }
        f.write_str("LSS master: ")?;
        match self {
            LssRequest::SwitchStateGlobal(mode) => write!(f, "switch state global {mode}"),
            LssRequest::SwitchStateSelective(field, v) => {
                write!(f, "switch state selective {} {v:08X}h", field.name())
            }
            LssRequest::ConfigureNodeId(255) => f.write_str("configure node-ID 255 (unconfigured)"),
            LssRequest::ConfigureNodeId(id) => write!(f, "configure node-ID {id}"),
            LssRequest::ConfigureBitTiming { table, index } => {
                write!(f, "configure bit timing table {table} index {index}")
            }
            LssRequest::ActivateBitTiming { delay_ms } => {
                write!(f, "activate bit timing delay {delay_ms} ms")
            }
            LssRequest::StoreConfiguration => f.write_str("store configuration"),
            LssRequest::Inquire(LssInquiry::Address(field)) => {
                write!(f, "inquire {}", field.name())
            }
            LssRequest::Inquire(LssInquiry::NodeId) => f.write_str("inquire node-ID"),
            LssRequest::IdentifyRemoteSlave(part, v) => {
                write!(f, "identify remote slave {} {v:08X}h", part.name())
            }
            LssRequest::IdentifyNonConfigured => {
                f.write_str("identify non-configured remote slave")
            }
            LssRequest::Fastscan(_) => Ok(()),
            LssRequest::Other(p) => write!(f, "unknown [{p}]"),
        }
    }
}

impl fmt::Display for LssResponse {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("LSS slave: ")?;
        match self {
            LssResponse::SwitchStateSelective => f.write_str("switch state selective response"),
            LssResponse::ConfigureNodeId(s) => write!(f, "configure node-ID {s}"),
            LssResponse::ConfigureBitTiming(s) => write!(f, "configure bit timing {s}"),
            LssResponse::StoreConfiguration(s) => write!(f, "store configuration {s}"),
            LssResponse::Address(field, v) => write!(f, "{} {v:08X}h", field.name()),
            LssResponse::NodeId(id) => write!(f, "node-ID {id}"),
            LssResponse::IdentifySlave => f.write_str("identify slave"),
            LssResponse::IdentifyNonConfigured => f.write_str("identify non-configured slave"),
            LssResponse::Other(p) => write!(f, "unknown [{p}]"),
        }
    }
}

impl fmt::Display for LssMessage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LssMessage::Request(r) => r.fmt(f),
            LssMessage::Response(r) => r.fmt(f),
        }
    }
}
