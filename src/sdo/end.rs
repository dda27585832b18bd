//! How an SDO transfer ends, the one type the client and the server report
//! it with (CiA 301 section 7.2.4.3, SDO protocols: a transfer ends
//! confirmed, or aborted by either side with an abort code).

use crate::abort::AbortCode;

/// Who ended a transfer with an abort.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum AbortOrigin {
    /// This side detected the failure and sent the abort frame.
    Local,
    /// The peer sent an abort frame; nothing was sent back.
    Peer,
    /// A new initiate request replaced the transfer (server only; no frame
    /// sent, the code is [`AbortCode::GeneralError`]).
    Superseded,
}

/// How a transfer ended, for the client ([`ClientEvent::Ended`]) and the
/// server (its [`ServerEvent`]) alike: exactly one per transfer.
///
/// [`ClientEvent::Ended`]: super::ClientEvent::Ended
/// [`ServerEvent`]: super::ServerEvent
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum TransferEnd {
    /// An upload completed: `len` bytes were read (for the client, the
    /// total delivered in its `UploadData` events).
    Uploaded {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Bytes transferred.
        len: usize,
    },
    /// A download completed: the server's dictionary accepted `len` bytes.
    Downloaded {
        /// Object index.
        index: u16,
        /// Sub-index.
        sub: u8,
        /// Bytes written.
        len: usize,
    },
    /// The transfer ended in an abort.
    Aborted {
        /// Object index of the transfer.
        index: u16,
        /// Sub-index of the transfer.
        sub: u8,
        /// The abort code sent or received.
        code: AbortCode,
        /// Who aborted.
        origin: AbortOrigin,
    },
}

impl TransferEnd {
    /// The end of a transfer of `index`/`sub` that this side aborted with
    /// `code` (the abort frame it sends carries the same object and code).
    #[must_use]
    pub const fn local_abort(index: u16, sub: u8, code: AbortCode) -> Self {
        TransferEnd::Aborted {
            index,
            sub,
            code,
            origin: AbortOrigin::Local,
        }
    }

    /// The object the transfer was about.
    #[must_use]
    pub const fn object(&self) -> (u16, u8) {
        match *self {
            TransferEnd::Uploaded { index, sub, .. }
            | TransferEnd::Downloaded { index, sub, .. }
            | TransferEnd::Aborted { index, sub, .. } => (index, sub),
        }
    }
}
