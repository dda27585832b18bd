//! Either side's command by its shape (CiA 301 section 7.2.4.3, SDO
//! protocols), for the formatters that name commands (the text of
//! [`Message`](crate::Message)'s `Display`, the decoder's JSON): the client
//! and the server send the same shapes, a data segment, a bare t bit, an
//! initiate with or without the value, an abort, and differ only in which
//! transfer each serves. One match per side gives the shape; each formatter
//! names the shapes once, through a [`Names`] table per side.

use super::{
    BlockDataCommand, ClientBlockUpload, ClientCommand, ServerBlockDownload, ServerCommand,
};
use crate::abort::AbortCode;
use crate::od::Address;
use crate::sdo::data::{InitiatePayload, Segment};

/// An SDO command of either side, by its shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CommandView<'a> {
    /// A data segment: the client's download segment (ccs = 0), the
    /// server's upload segment (scs = 0).
    Segment(&'a Segment),
    /// A segment frame that carries only the t bit: the client's upload
    /// segment request (ccs = 3), the server's download segment
    /// acknowledgement (scs = 1).
    Toggle(bool),
    /// An initiate that carries the value or its size: the client's
    /// download request (ccs = 1), the server's upload response (scs = 2).
    InitiateData(Address, &'a InitiatePayload),
    /// An initiate without data: the client's upload request (ccs = 2),
    /// the server's download response (scs = 3).
    Initiate(Address),
    /// An abort (cs = 4) of the transfer of an object, the same both ways.
    Abort(Address, AbortCode),
    /// A block transfer command (client cs = 5 / 6, server cs = 6 / 5).
    Block(BlockView<'a>),
    /// A specifier CiA 301 does not define (cs = 7): byte 0 as received.
    Unknown(u8),
}

/// A block transfer command: one side's control frames, or the frames
/// around the data, which the sender of the data sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BlockView<'a> {
    /// The client's block upload commands (ccs = 5).
    ClientUpload(&'a ClientBlockUpload),
    /// The client's block download initiate and end (ccs = 6).
    ClientDownload(&'a BlockDataCommand),
    /// The server's block download responses (scs = 5).
    ServerDownload(&'a ServerBlockDownload),
    /// The server's block upload initiate response and end (scs = 6).
    ServerUpload(&'a BlockDataCommand),
}

/// One shape's name: in words (the `Display` of a command) and as the
/// decoder's JSON `command` value.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Name {
    /// In words.
    pub text: &'static str,
    /// In JSON.
    #[cfg_attr(not(feature = "log"), allow(dead_code))]
    pub json: &'static str,
}

/// What one side's commands of each shape are called.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Names {
    /// [`CommandView::Segment`].
    pub segment: Name,
    /// [`CommandView::Toggle`].
    pub toggle: Name,
    /// [`CommandView::InitiateData`], before the object.
    pub initiate_data: Name,
    /// [`CommandView::Initiate`], before the object.
    pub initiate: Name,
    /// [`CommandView::Initiate`] in words, after the object.
    pub initiate_after: &'static str,
}

/// Maps one side's commands to their shapes: which variant is the data
/// segment, the bare t bit, the initiate with data and the one without,
/// and which view each block family takes. The table below has one row
/// per side.
macro_rules! command_shapes {
    ($(
        $(#[$doc:meta])*
        $cmd:ident: $segment:ident, $toggle:ident, $initiate_data:ident, $initiate:ident,
        $upload:ident, $download:ident;
    )*) => {$(
        impl $cmd {
            $(#[$doc])*
            pub(crate) const fn view(&self) -> CommandView<'_> {
                match self {
                    $cmd::$segment(s) => CommandView::Segment(s),
                    $cmd::$toggle { toggle } => CommandView::Toggle(*toggle),
                    $cmd::$initiate_data {
                        index,
                        sub,
                        payload,
                    } => CommandView::InitiateData(Address::new(*index, *sub), payload),
                    $cmd::$initiate { index, sub } => {
                        CommandView::Initiate(Address::new(*index, *sub))
                    }
                    $cmd::Abort { index, sub, code } => {
                        CommandView::Abort(Address::new(*index, *sub), *code)
                    }
                    $cmd::BlockUpload(b) => CommandView::Block(BlockView::$upload(b)),
                    $cmd::BlockDownload(b) => CommandView::Block(BlockView::$download(b)),
                    $cmd::Unknown(b) => CommandView::Unknown(*b),
                }
            }
        }
    )*};
}

command_shapes! {
    /// The request by its shape: ccs 0 download segment, 3 upload segment
    /// request, 1 initiate download, 2 initiate upload.
    ClientCommand: DownloadSegment, UploadSegment, InitiateDownload, InitiateUpload,
        ClientUpload, ClientDownload;
    /// The response by its shape: scs 0 upload segment, 1 download segment
    /// acknowledgement, 2 initiate upload, 3 initiate download.
    ServerCommand: UploadSegment, DownloadSegment, InitiateUpload, InitiateDownload,
        ServerUpload, ServerDownload;
}

/// What the requests are called.
pub(crate) const CLIENT_NAMES: Names = Names {
    segment: Name {
        text: "download segment",
        json: "download_segment",
    },
    toggle: Name {
        text: "upload segment request",
        json: "upload_segment",
    },
    initiate_data: Name {
        text: "initiate download",
        json: "initiate_download",
    },
    initiate: Name {
        text: "initiate upload",
        json: "initiate_upload",
    },
    initiate_after: "",
};

/// What the responses are called.
pub(crate) const SERVER_NAMES: Names = Names {
    segment: Name {
        text: "upload segment",
        json: "upload_segment",
    },
    toggle: Name {
        text: "download segment ack",
        json: "download_segment_ack",
    },
    initiate_data: Name {
        text: "upload",
        json: "initiate_upload_response",
    },
    initiate: Name {
        text: "download",
        json: "initiate_download_response",
    },
    initiate_after: " acknowledged",
};
