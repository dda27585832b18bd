//! Block download and block upload of [`Client`] (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO block download and upload): the commands,
//! the responses the block states accept, and the lazily made segments of
//! a block download.
//! The sub-block rules themselves are shared with the server
//! (`crate::sdo::rules::block`).

use super::{AbortCode, Client, ClientCommand, ServerCommand, State, TransferEnd};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::sdo::rules::block::{check_block_size, clamp_block_size, Acked, Receiver, Sender};
use crate::sdo::wire::{
    BlockDataInitiate, BlockDownloadAccept, ClientBlockDownload, ClientBlockUpload,
    ServerBlockDownload, ServerBlockUpload,
};

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// A block upload's sub-block segment: handled here (true), or a
    /// command for the normal path (false).
    pub(super) fn block_segment(&mut self, now: Timestamp, frame: &CanFrame) -> bool {
        let State::BlockUploading { index, sub, rx } = &mut self.state else {
            return false;
        };
        let (index, sub) = (*index, *sub);
        let blksize = rx.block_size();
        let Some(result) = rx.take(frame.data()) else {
            return false;
        };
        match result {
            Err(code) => self.abort_object(index, sub, code),
            Ok(step) => {
                if let Some((offset, data)) = step.write {
                    self.deliver(index, sub, offset, data);
                }
                if let Some(ackseq) = step.ack {
                    self.send(ClientCommand::BlockUpload(ClientBlockUpload::Ack {
                        ackseq,
                        blksize,
                    }));
                }
                self.arm(now);
            }
        }
        true
    }

    /// The next segment of the running block download's sub-block, if one
    /// is due (see the module docs: one segment per poll).
    #[inline(never)]
    pub(super) fn next_block_segment(&mut self) -> Option<CanFrame> {
        let State::BlockDownloading { data, tx, .. } = &mut self.state else {
            return None;
        };
        let planned = tx.next()?;
        let bytes = data.as_ref();
        let chunk = bytes
            .get(planned.offset..)
            .and_then(|rest| rest.get(..planned.len))
            .unwrap_or(&[]);
        let frame = tx.emit(chunk);
        CanFrame::new(self.config.request_id, &frame).ok()
    }

    /// Sends the next sub-block of a block download (its segments are made
    /// when polled, see `next_block_segment`) and waits for the server's
    /// acknowledgement of it (CiA 301 section 7.2.4.3.9: after the initiate
    /// confirmation and after every acknowledgement that asks for more).
    fn send_sub_block(&mut self, now: Timestamp, index: u16, sub: u8, data: D, tx: Sender) {
        let state = State::BlockDownloading {
            index,
            sub,
            data,
            tx,
        };
        self.wait(now, state);
    }

    /// True when the server's answer to a block initiate names the
    /// transfer's own object; otherwise the transfer is aborted with
    /// 06040043h (CiA 301 section 7.2.4.3: a response for another object).
    fn answers_object(&mut self, (index, sub): (u16, u8), answered: (u16, u8)) -> bool {
        if answered == (index, sub) {
            return true;
        }
        self.abort_object(index, sub, AbortCode::GeneralParameterIncompatibility);
        false
    }

    /// A response in one of the block states (`state` was taken out of
    /// `self.state`, which is `Idle` meanwhile).
    pub(super) fn on_block_response(
        &mut self,
        now: Timestamp,
        state: State<D>,
        cmd: ServerCommand,
        frame: &[u8],
    ) {
        match state {
            State::BlockDownloadInitiated { index, sub, data } => {
                let ServerCommand::BlockDownload(ServerBlockDownload::Initiate(accept)) = cmd
                else {
                    return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
                };
                let BlockDownloadAccept { crc, blksize, .. } = accept;
                if !self.answers_object((index, sub), (accept.index, accept.sub)) {
                    return;
                }
                let blksize = match check_block_size(blksize) {
                    Ok(b) => b,
                    Err(code) => return self.abort_object(index, sub, code),
                };
                let tx = Sender::new(data.as_ref().len(), blksize, crc && self.config.crc);
                self.send_sub_block(now, index, sub, data, tx);
            }
            State::BlockDownloading {
                index,
                sub,
                data,
                mut tx,
            } => {
                let ServerCommand::BlockDownload(ServerBlockDownload::Ack { ackseq, blksize }) =
                    cmd
                else {
                    return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
                };
                match tx.on_ack(ackseq, blksize) {
                    Err(code) => self.abort_object(index, sub, code),
                    Ok(Acked::More) => self.send_sub_block(now, index, sub, data, tx),
                    Ok(Acked::Done { unused, crc }) => {
                        self.send(ClientCommand::BlockDownload(ClientBlockDownload::End {
                            unused,
                            crc,
                        }));
                        self.wait(
                            now,
                            State::BlockDownloadEnding {
                                index,
                                sub,
                                len: data.as_ref().len(),
                            },
                        );
                    }
                }
            }
            State::BlockDownloadEnding { index, sub, len } => {
                if cmd != ServerCommand::BlockDownload(ServerBlockDownload::End) {
                    return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
                }
                self.finish(TransferEnd::Downloaded { index, sub, len });
            }
            State::BlockUploadInitiated { index, sub } => match cmd {
                ServerCommand::BlockUpload(ServerBlockUpload::Initiate(answer)) => {
                    let BlockDataInitiate { crc, size, .. } = answer;
                    if !self.answers_object((index, sub), (answer.index, answer.sub)) {
                        return;
                    }
                    let size = size.map(|s| usize::try_from(s).unwrap_or(usize::MAX));
                    let blksize = clamp_block_size(self.config.block_size);
                    self.send(ClientCommand::BlockUpload(ClientBlockUpload::Start));
                    self.wait(
                        now,
                        State::BlockUploading {
                            index,
                            sub,
                            rx: Receiver::new(blksize, size, crc && self.config.crc).after(frame),
                        },
                    );
                }
                // The protocol switch: a normal upload answers. Followed
                // whatever threshold was offered (lenient: python-canopen's
                // server answers every block upload so).
                ServerCommand::InitiateUpload { .. } => {
                    self.on_upload_initiated(now, index, sub, cmd);
                }
                _ => self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier),
            },
            State::BlockUploading { index, sub, mut rx } => {
                let ServerCommand::BlockUpload(ServerBlockUpload::End { unused, crc }) = cmd else {
                    return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
                };
                match rx.on_end(unused, crc) {
                    Err(code) => self.abort_object(index, sub, code),
                    Ok(ended) => {
                        if let Some((offset, data)) = ended.write {
                            self.deliver(index, sub, offset, data);
                        }
                        // End acknowledged.
                        self.send(ClientCommand::BlockUpload(ClientBlockUpload::End));
                        self.finish(TransferEnd::Uploaded {
                            index,
                            sub,
                            len: ended.total,
                        });
                    }
                }
            }
            // Not block states: handled by the caller before.
            State::Idle
            | State::UploadInitiated { .. }
            | State::Uploading { .. }
            | State::DownloadInitiated { .. }
            | State::Downloading { .. } => {}
        }
    }
}
