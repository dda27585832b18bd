//! The observer's transitions: one open transfer and what each frame of its
//! channel does to it. The rules themselves are the client's and the
//! server's (`crate::sdo::rules`); this file only says which side applies
//! which rule when (see [`super`]).

use super::{
    BreakReason, Direction, Observed, ObserverEvent, SdoChannel, Side, Sink, Transfer, TransferKind,
};
use crate::abort::AbortCode;
use crate::bytes::Payload;
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::sdo::data::{InitiatePayload, Segment, SegmentData};
use crate::sdo::rules::block::{check_block_size, is_abort, Receiver};
use crate::sdo::rules::segmented::{check_toggle, Segments};
use crate::sdo::wire::{
    ClientBlockDownload, ClientBlockUpload, ClientCommand, SdoRequest, SdoResponse,
    ServerBlockDownload, ServerBlockUpload, ServerCommand,
};
use block_phase::{ack, block_segment, end, Blocks};

mod block_phase;

/// Where an open transfer stands: what the next frame may be.
#[derive(Debug, Clone, Copy)]
enum Phase {
    /// Initiate upload sent; the server's answer is due.
    UploadInitiated,
    /// Segmented upload: the client's segment request is due.
    UploadRequestDue(Segments),
    /// Segmented upload: the server's segment is due.
    UploadSegmentDue(Segments),
    /// Initiate download sent (the value in it when `expedited`).
    DownloadInitiated { expedited: bool },
    /// Segmented download: the client's segment is due.
    DownloadSegmentDue(Segments),
    /// Segmented download: the server's acknowledgement of the segment
    /// with `toggle` (the last one when `last`) is due.
    DownloadAckDue {
        rx: Segments,
        toggle: bool,
        last: bool,
    },
    /// Block upload initiate sent with this block size and CRC support.
    BlockUploadInitiated { blksize: u8, crc: bool },
    /// Block upload answered; the client's start command is due.
    BlockUploadStartDue(Receiver),
    /// Block download initiate sent (its frame kept to spot its repeat).
    BlockDownloadInitiated {
        crc: bool,
        size: Option<usize>,
        frame: Payload,
    },
    /// Sub-blocks: the sender of the data sends segments (held in a
    /// [`SubBlock`] of the pool), the receiver's acknowledgement commits
    /// them; after the last segment is acknowledged, the end frame.
    SubBlocks(Blocks),
    /// The end frame was taken; the receiver's confirmation is due (a
    /// repeat of the end frame meanwhile is ignored, as the receiver,
    /// done with the transfer, ignores it).
    EndAckDue { crc_checked: bool, end: Payload },
    /// A segmented upload's last segment broke a size rule: the client's
    /// abort may follow; any other frame (or the end) completes it.
    Accepted,
    /// A frame broke a rule: the abort `by` that side is due. Until it
    /// comes, frames of a block's data sender are still segments.
    Violated {
        code: AbortCode,
        by: Side,
        segments_from: Option<Side>,
    },
}

/// The transfer open on one channel.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Open {
    transfer: Transfer,
    bytes: usize,
    /// Bytes of the sub-block segments seen that no acknowledgement has
    /// confirmed yet (not delivered), and how many segments.
    pending: (usize, u8),
    phase: Phase,
    /// A rule just broken, to report.
    broken: Option<(AbortCode, Side)>,
    /// The first rule broken that the transfer went on past (sizes, CRC).
    flagged: Option<AbortCode>,
    /// When it is broken off for silence.
    pub(super) deadline: Option<Timestamp>,
}

impl Open {
    /// What is known of the transfer.
    pub(super) const fn transfer(&self) -> Transfer {
        self.transfer
    }

    /// The end event when `reason` ends the transfer, or a frame that is not
    /// the abort it waits for: a transfer waiting for the abort a rule
    /// called for ends as that violation, one that a peer accepted past a
    /// rule completes.
    pub(super) fn ended(self, reason: BreakReason) -> ObserverEvent {
        if let Phase::Accepted = self.phase {
            return self.completed(false);
        }
        self.broken_off(reason)
    }

    /// The end event for `reason` (a transfer waiting for the abort a rule
    /// called for ends as that violation whatever the reason).
    fn broken_off(self, reason: BreakReason) -> ObserverEvent {
        let (pending, segments) = self.pending;
        let reason = match (self.phase, reason) {
            (Phase::Violated { code, by, .. }, _) => BreakReason::Violation { code, by },
            (_, BreakReason::EndOfTrace | BreakReason::Timeout) if segments > 0 => {
                BreakReason::AckNotSeen {
                    segments,
                    trace_ended: reason == BreakReason::EndOfTrace,
                }
            }
            _ => reason,
        };
        ObserverEvent::BrokenOff {
            transfer: self.transfer,
            bytes: self.bytes,
            pending,
            reason,
        }
    }

    fn aborted(self, code: AbortCode, by: Side) -> ObserverEvent {
        let expected = match self.phase {
            Phase::Violated { code, .. } => Some(code),
            _ => self.flagged,
        };
        ObserverEvent::Aborted {
            transfer: self.transfer,
            bytes: self.bytes,
            pending: self.pending.0,
            code,
            by,
            expected,
        }
    }

    fn completed(self, crc_checked: bool) -> ObserverEvent {
        ObserverEvent::Completed {
            transfer: self.transfer,
            bytes: self.bytes,
            crc_checked,
        }
    }

    /// A frame that repeats one the receiver of the data recognises as a
    /// repeat: the block upload initiate response before the first segment
    /// (the client's block receiver knows it), the end frame after it was
    /// taken.
    fn is_repeat(&self, from: Side, bytes: &[u8]) -> bool {
        if from != self.data_sender() {
            return false;
        }
        match &self.phase {
            Phase::BlockUploadStartDue(rx) => rx.is_duplicate(bytes),
            Phase::EndAckDue { end, .. } => end.as_slice() == bytes,
            _ => false,
        }
    }

    /// True while the transfer may hold sub-block segments (a buffer of
    /// the pool): in the sub-block phase.
    pub(super) const fn holds_segments(&self) -> bool {
        matches!(self.phase, Phase::SubBlocks(_))
    }

    /// The side that sends the value.
    const fn data_sender(&self) -> Side {
        match self.transfer.direction {
            Direction::Upload => Side::Server,
            Direction::Download => Side::Client,
        }
    }

    fn deliver(&mut self, offset: usize, data: SegmentData, out: &mut Sink) {
        if data.is_empty() {
            return;
        }
        self.bytes = self.bytes.saturating_add(data.len());
        out.push(ObserverEvent::Data {
            channel: self.transfer.channel,
            offset,
            data,
        });
    }

    /// The server's answer to a block initiate, for the object `answered`
    /// and with CRC when both sides announced it (`crc`, CiA 301 section
    /// 7.2.4.3.9): the transfer goes on by block, CRC or not, when it names
    /// the transfer's own object; otherwise the client is due to abort
    /// (06040043h) and `None`.
    fn block_answer(&mut self, answered: (u16, u8), crc: bool) -> Option<bool> {
        if answered != (self.transfer.index, self.transfer.sub) {
            self.violate(AbortCode::GeneralParameterIncompatibility, Side::Client);
            return None;
        }
        self.transfer.kind = Some(TransferKind::Block { crc });
        Some(crc)
    }

    /// The rule the last frame broke, as the event that reports it (once).
    pub(super) fn rule_broken(&mut self) -> Option<ObserverEvent> {
        let (code, by) = self.broken.take()?;
        Some(ObserverEvent::RuleBroken {
            channel: self.transfer.channel,
            code,
            by,
        })
    }

    /// A rule the transfer can be followed past (the indicated size, the
    /// CRC) is broken: `by` should abort with `code`, and if it does not,
    /// the transfer goes on as the peers run it.
    fn flag(&mut self, code: AbortCode, by: Side) {
        self.broken = Some((code, by));
        self.flagged = self.flagged.or(Some(code));
    }

    /// Takes a segment of a segmented transfer as the receiver of the data
    /// (`by`) would: a wrong toggle bit ends the reading of it, a size rule
    /// broken is flagged and the segment taken.
    fn segment(&mut self, rx: &mut Segments, seg: &Segment, by: Side) -> Option<usize> {
        match rx.check(seg) {
            Ok(()) => {}
            Err(AbortCode::ToggleBitNotAlternated) => {
                self.violate(AbortCode::ToggleBitNotAlternated, by);
                return None;
            }
            Err(code) => self.flag(code, by),
        }
        Some(rx.accept(seg).offset)
    }

    /// `code` is due from `by`: the next frame should be its abort.
    fn violate(&mut self, code: AbortCode, by: Side) {
        let segments_from = match self.phase {
            Phase::SubBlocks(_) => Some(self.data_sender()),
            _ => None,
        };
        self.phase = Phase::Violated {
            code,
            by,
            segments_from,
        };
        self.broken = Some((code, by));
    }
}

/// How a frame ended a transfer.
enum End {
    /// Both sides confirmed it (a block transfer's CRC checked or not).
    Completed(bool),
    /// The observer cannot follow it further.
    Broken(BreakReason),
}

/// One command, whoever sent it.
enum Command {
    Client(ClientCommand),
    Server(ServerCommand),
}

/// Takes one frame from `from` on `channel` with the transfer `open` there.
/// A rule it broke stays flagged in the transfer, for
/// [`Open::rule_broken`].
pub(super) fn step(
    open: &mut Option<Open>,
    channel: SdoChannel,
    from: Side,
    frame: &CanFrame,
    out: &mut Sink,
) -> Observed {
    let bytes = frame.data();
    if let Some((seen, end)) = block_segment(open, channel, from, bytes, out) {
        if let Some(reason) = end {
            if let Some(o) = open.take() {
                out.push(o.ended(reason));
            }
        }
        return seen;
    }
    let repeat = open.as_ref().is_some_and(|o| o.is_repeat(from, bytes));
    let decoded = match from {
        Side::Client => SdoRequest::decode_frame(frame).map(|request| {
            (
                Command::Client(request.command),
                Observed::Request { channel, request },
            )
        }),
        Side::Server => SdoResponse::decode_frame(frame).map(|response| {
            (
                Command::Server(response.command),
                Observed::Response { channel, response },
            )
        }),
    };
    let (command, seen) = match decoded {
        Ok(both) => both,
        Err(error) => {
            return Observed::Malformed {
                channel,
                from,
                error,
            }
        }
    };
    if repeat {
        return seen;
    }
    // An abort as the crate's client and server take it: byte 0 80h
    // exactly (CiA 301 section 7.2.4.3); command specifier 4 with the
    // unused bits set is a command that does not fit.
    let abort = match command {
        Command::Client(ClientCommand::Abort { code, .. })
        | Command::Server(ServerCommand::Abort { code, .. })
            if is_abort(bytes) =>
        {
            Some(code)
        }
        _ => None,
    };
    if let Some(code) = abort {
        if let Some(o) = open.take() {
            out.push(o.aborted(code, from));
        }
        return seen;
    }
    if let Some(o) = open.take_if(|o| matches!(o.phase, Phase::Violated { .. } | Phase::Accepted)) {
        out.push(o.ended(BreakReason::NewInitiate));
    }
    if let Command::Client(c) = &command {
        if let Some((transfer, phase)) = initiate(channel, c, bytes) {
            if let Some(o) = open.take() {
                out.push(o.ended(BreakReason::NewInitiate));
            }
            out.push(ObserverEvent::Started(transfer));
            let mut o = Open {
                transfer,
                bytes: 0,
                pending: (0, 0),
                phase,
                broken: None,
                flagged: None,
                deadline: None,
            };
            if let ClientCommand::InitiateDownload {
                payload: InitiatePayload::Expedited { data, .. },
                ..
            } = c
            {
                o.deliver(
                    0,
                    SegmentData::new(data.as_slice()).unwrap_or_default(),
                    out,
                );
            }
            if let ClientCommand::BlockUpload(ClientBlockUpload::Initiate(i)) = c {
                if let Err(code) = check_block_size(i.blksize) {
                    o.violate(code, Side::Server);
                }
            }
            *open = Some(o);
            return seen;
        }
    }
    let Some(o) = open.as_mut() else {
        // No transfer: a stray frame (the trace began in the middle of one,
        // or it follows an abort).
        return seen;
    };
    let done = match command {
        Command::Client(c) => client(o, c, bytes, out),
        Command::Server(s) => server(o, s, bytes, out),
    };
    if let Some(end) = done {
        if let Some(o) = open.take() {
            out.push(match end {
                End::Completed(crc_checked) => o.completed(crc_checked),
                End::Broken(reason) => o.ended(reason),
            });
        }
    }
    seen
}

/// A client frame that begins a transfer: what is known of it and its
/// first phase.
fn initiate(channel: SdoChannel, c: &ClientCommand, bytes: &[u8]) -> Option<(Transfer, Phase)> {
    let transfer = |direction, index, sub, kind, indicated| Transfer {
        channel,
        direction,
        index,
        sub,
        kind,
        indicated,
    };
    // A block transfer, with CRC as the client offered it (the server's
    // answer may still turn it off).
    let block = |direction, index, sub, crc, indicated| {
        transfer(
            direction,
            index,
            sub,
            Some(TransferKind::Block { crc }),
            indicated,
        )
    };
    Some(match *c {
        ClientCommand::InitiateUpload { index, sub } => (
            transfer(Direction::Upload, index, sub, None, None),
            Phase::UploadInitiated,
        ),
        ClientCommand::InitiateDownload {
            index,
            sub,
            payload,
        } => match payload {
            InitiatePayload::Expedited {
                data,
                size_indicated,
            } => (
                transfer(
                    Direction::Download,
                    index,
                    sub,
                    Some(TransferKind::Expedited { size_indicated }),
                    size_indicated
                        .then(|| u32::try_from(data.len()).ok())
                        .flatten(),
                ),
                Phase::DownloadInitiated { expedited: true },
            ),
            InitiatePayload::Segmented { size } => (
                transfer(
                    Direction::Download,
                    index,
                    sub,
                    Some(TransferKind::Segmented),
                    size,
                ),
                Phase::DownloadInitiated { expedited: false },
            ),
        },
        ClientCommand::BlockUpload(ClientBlockUpload::Initiate(i)) => (
            block(Direction::Upload, i.index, i.sub, i.crc, None),
            Phase::BlockUploadInitiated {
                blksize: i.blksize,
                crc: i.crc,
            },
        ),
        ClientCommand::BlockDownload(ClientBlockDownload::Initiate(i)) => (
            block(Direction::Download, i.index, i.sub, i.crc, i.size),
            Phase::BlockDownloadInitiated {
                crc: i.crc,
                size: i.size.map(|s| usize::try_from(s).unwrap_or(usize::MAX)),
                frame: Payload::new(bytes).unwrap_or_default(),
            },
        ),
        _ => return None,
    })
}

/// Takes a client command (not an initiate, not an abort); `Some` when it
/// ended the transfer.
fn client(o: &mut Open, c: ClientCommand, bytes: &[u8], out: &mut Sink) -> Option<End> {
    let upload = o.transfer.direction == Direction::Upload;
    match (c, o.phase) {
        (ClientCommand::UploadSegment { toggle }, Phase::UploadRequestDue(rx)) => {
            match check_toggle(toggle, rx.toggle()) {
                Ok(()) => o.phase = Phase::UploadSegmentDue(rx),
                Err(code) => o.violate(code, Side::Server),
            }
        }
        (ClientCommand::UploadSegment { .. }, Phase::UploadSegmentDue(_)) => {
            o.violate(AbortCode::ToggleBitNotAlternated, Side::Server);
        }
        (ClientCommand::DownloadSegment(seg), Phase::DownloadSegmentDue(mut rx)) => {
            download_segment(o, &mut rx, &seg, out);
        }
        (ClientCommand::BlockUpload(ClientBlockUpload::Start), Phase::BlockUploadStartDue(rx)) => {
            o.phase = Phase::SubBlocks(Blocks::new(rx));
        }
        (ClientCommand::BlockUpload(ClientBlockUpload::Ack { ackseq, blksize }), _) if upload => {
            return ack(o, (ackseq, blksize), bytes, Side::Client, out);
        }
        (
            ClientCommand::BlockUpload(ClientBlockUpload::End),
            Phase::EndAckDue { crc_checked, .. },
        ) if upload => {
            return Some(End::Completed(crc_checked));
        }
        (ClientCommand::BlockDownload(ClientBlockDownload::End { unused, crc }), _) if !upload => {
            return end(o, (unused, crc), bytes, Side::Server, out);
        }
        _ => o.violate(AbortCode::InvalidCommandSpecifier, Side::Server),
    }
    None
}

/// Placed as the server places it; the abort it would send is due when
/// the segment breaks a rule.
fn download_segment(o: &mut Open, rx: &mut Segments, seg: &Segment, out: &mut Sink) {
    if let Some(offset) = o.segment(rx, seg, Side::Server) {
        o.phase = Phase::DownloadAckDue {
            rx: *rx,
            toggle: seg.toggle,
            last: seg.last,
        };
        o.deliver(offset, seg.data, out);
    }
}

/// Takes a server command (not an abort); `Some` when it ended the
/// transfer.
fn server(o: &mut Open, s: ServerCommand, bytes: &[u8], out: &mut Sink) -> Option<End> {
    let upload = o.transfer.direction == Direction::Upload;
    let (index, sub) = (o.transfer.index, o.transfer.sub);
    let names_other = |ri: u16, rs: u8| (ri, rs) != (index, sub);
    match (s, o.phase) {
        (
            ServerCommand::InitiateUpload {
                index: ri,
                sub: rs,
                payload,
            },
            Phase::UploadInitiated | Phase::BlockUploadInitiated { .. },
        ) => {
            if names_other(ri, rs) {
                o.violate(AbortCode::GeneralParameterIncompatibility, Side::Client);
                return None;
            }
            match payload {
                InitiatePayload::Expedited {
                    data,
                    size_indicated,
                } => {
                    o.transfer.kind = Some(TransferKind::Expedited { size_indicated });
                    o.transfer.indicated = size_indicated
                        .then(|| u32::try_from(data.len()).ok())
                        .flatten();
                    o.deliver(
                        0,
                        SegmentData::new(data.as_slice()).unwrap_or_default(),
                        out,
                    );
                    return Some(End::Completed(false));
                }
                InitiatePayload::Segmented { size } => {
                    o.transfer.kind = Some(TransferKind::Segmented);
                    o.transfer.indicated = size;
                    o.phase = Phase::UploadRequestDue(Segments::new(
                        size.map(|s| usize::try_from(s).unwrap_or(usize::MAX)),
                    ));
                }
            }
        }
        (
            ServerCommand::InitiateDownload { index: ri, sub: rs },
            Phase::DownloadInitiated { expedited },
        ) => {
            if names_other(ri, rs) {
                o.violate(AbortCode::GeneralParameterIncompatibility, Side::Client);
                return None;
            }
            if expedited {
                return Some(End::Completed(false));
            }
            let size = o
                .transfer
                .indicated
                .map(|s| usize::try_from(s).unwrap_or(usize::MAX));
            o.phase = Phase::DownloadSegmentDue(Segments::new(size));
        }
        (ServerCommand::UploadSegment(seg), Phase::UploadSegmentDue(mut rx)) => {
            // More bytes than indicated (06070012h for the client) is
            // flagged and followed, as python-canopen's client reads on and
            // keeps the indicated size.
            if let Some(offset) = o.segment(&mut rx, &seg, Side::Client) {
                o.deliver(offset, seg.data, out);
                if seg.last && o.flagged.is_some() {
                    o.phase = Phase::Accepted;
                } else if seg.last {
                    return Some(End::Completed(false));
                } else {
                    o.phase = Phase::UploadRequestDue(rx);
                }
            }
        }
        (
            ServerCommand::DownloadSegment { toggle },
            Phase::DownloadAckDue {
                rx,
                toggle: t,
                last,
            },
        ) => match check_toggle(toggle, t) {
            Ok(()) if last => return Some(End::Completed(false)),
            Ok(()) => o.phase = Phase::DownloadSegmentDue(rx),
            Err(code) => o.violate(code, Side::Client),
        },
        (
            ServerCommand::BlockDownload(ServerBlockDownload::Initiate(a)),
            Phase::BlockDownloadInitiated {
                crc: client_crc,
                size,
                frame,
            },
        ) => {
            let crc = o.block_answer((a.index, a.sub), a.crc && client_crc)?;
            match check_block_size(a.blksize) {
                Ok(b) => {
                    let rx = Receiver::new(b, size, crc).after(frame.as_slice());
                    o.phase = Phase::SubBlocks(Blocks::new(rx));
                }
                Err(code) => o.violate(code, Side::Client),
            }
        }
        (ServerCommand::BlockDownload(ServerBlockDownload::Ack { ackseq, blksize }), _)
            if !upload =>
        {
            return ack(o, (ackseq, blksize), bytes, Side::Server, out);
        }
        (
            ServerCommand::BlockDownload(ServerBlockDownload::End),
            Phase::EndAckDue { crc_checked, .. },
        ) if !upload => {
            return Some(End::Completed(crc_checked));
        }
        (
            ServerCommand::BlockUpload(ServerBlockUpload::Initiate(i)),
            Phase::BlockUploadInitiated {
                blksize,
                crc: client_crc,
            },
        ) => {
            let crc = o.block_answer((i.index, i.sub), i.crc && client_crc)?;
            o.transfer.indicated = i.size;
            let size = i.size.map(|s| usize::try_from(s).unwrap_or(usize::MAX));
            o.phase = Phase::BlockUploadStartDue(Receiver::new(blksize, size, crc).after(bytes));
        }
        (ServerCommand::BlockUpload(ServerBlockUpload::End { unused, crc }), _) if upload => {
            return end(o, (unused, crc), bytes, Side::Client, out);
        }
        _ => o.violate(AbortCode::InvalidCommandSpecifier, Side::Client),
    }
    None
}
