//! Block download and block upload of [`Server`] (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO block download and upload): the requests
//! the block states accept and the lazily read segments of a block upload. The sub-block
//! rules themselves are shared with the client (`crate::sdo::rules::block`).

use super::{AbortCode, ObjectDictionary, Server, ServerCommand, ServerEvent, State};
use crate::clock::Timestamp;
use crate::frame::CanFrame;
use crate::sdo::rules::block::{check_block_size, clamp_block_size, Acked, Receiver, Sender};
use crate::sdo::wire::{
    BlockDataInitiate, BlockDownloadAccept, ClientBlockDownload, ClientBlockUpload,
    ServerBlockDownload, ServerBlockUpload,
};

impl<D: ObjectDictionary, const EVENTS: usize> Server<D, EVENTS> {
    /// A block download's sub-block segment: handled here (true), or a
    /// command for the normal path (false).
    pub(super) fn block_segment(&mut self, now: Timestamp, bytes: &[u8]) -> bool {
        let State::BlockDownloading {
            index,
            sub,
            info,
            mut rx,
        } = self.state
        else {
            return false;
        };
        let Some(result) = rx.take(bytes) else {
            return false;
        };
        self.state = State::BlockDownloading {
            index,
            sub,
            info,
            rx,
        };
        let step = match result {
            Ok(step) => step,
            Err(code) => {
                self.abort_local(code);
                return true;
            }
        };
        if let Some((offset, data)) = step.write {
            let data = data.as_slice();
            let written = info
                .check_download_len(offset + data.len())
                .or_else(|code| match code {
                    // Too short is only known at the end.
                    AbortCode::DataTypeLengthTooLow => Ok(()),
                    code => Err(code),
                })
                .and_then(|()| self.od.write(index, sub, offset, data));
            if let Err(code) = written {
                self.abort_local(code);
                return true;
            }
        }
        if let Some(ackseq) = step.ack {
            self.send(ServerCommand::BlockDownload(ServerBlockDownload::Ack {
                ackseq,
                blksize: rx.block_size(),
            }));
        }
        self.arm(now);
        true
    }

    /// The next segment of the running block upload's sub-block, read from
    /// the dictionary at its offset; a failed or short read ends the
    /// transfer with the dictionary's code (short: 08000000h) instead.
    #[inline(never)]
    pub(super) fn next_block_segment(&mut self) -> Option<CanFrame> {
        let State::BlockUploading { index, sub, tx } = &self.state else {
            return None;
        };
        let (index, sub) = (*index, *sub);
        let planned = tx.next()?;
        let mut buf = [0u8; 7];
        let want = buf.get_mut(..planned.len).unwrap_or(&mut []);
        match self.read_full(index, sub, planned.offset, want) {
            Ok(n) if n == planned.len => {}
            Ok(_) => {
                self.abort_local(AbortCode::GeneralError);
                return self.transmit.pop();
            }
            Err(code) => {
                self.abort_local(code);
                return self.transmit.pop();
            }
        }
        // Updated in place: the state is not copied per segment.
        let State::BlockUploading { tx, .. } = &mut self.state else {
            return None;
        };
        let frame = tx.emit(buf.get(..planned.len).unwrap_or(&[]));
        CanFrame::new(self.config.response_id, &frame).ok()
    }

    pub(super) fn on_block_upload(&mut self, now: Timestamp, cmd: ClientBlockUpload) {
        match (cmd, self.state) {
            (ClientBlockUpload::Initiate(i), _) => {
                self.supersede();
                self.initiate_block_upload(now, (i.index, i.sub), i.crc, i.blksize, i.pst);
            }
            (
                ClientBlockUpload::Start,
                State::BlockUploadInitiated {
                    index,
                    sub,
                    len,
                    crc,
                    blksize,
                },
            ) => {
                self.state = State::BlockUploading {
                    index,
                    sub,
                    tx: Sender::new(len, blksize, crc),
                };
                self.arm(now);
            }
            (
                ClientBlockUpload::Ack { ackseq, blksize },
                State::BlockUploading { index, sub, mut tx },
            ) => match tx.on_ack(ackseq, blksize) {
                Err(code) => self.abort_local(code),
                Ok(Acked::More) => {
                    self.state = State::BlockUploading { index, sub, tx };
                    self.arm(now);
                }
                Ok(Acked::Done { unused, crc }) => {
                    self.send(ServerCommand::BlockUpload(ServerBlockUpload::End {
                        unused,
                        crc,
                    }));
                    let len = tx.len();
                    self.state = State::BlockUploadEnding { index, sub, len };
                    self.arm(now);
                }
            },
            (ClientBlockUpload::End, State::BlockUploadEnding { index, sub, len }) => {
                self.finish(ServerEvent::Uploaded { index, sub, len });
            }
            _ => self.abort_local(AbortCode::InvalidCommandSpecifier),
        }
    }

    fn initiate_block_upload(
        &mut self,
        now: Timestamp,
        (index, sub): (u16, u8),
        crc: bool,
        blksize: u8,
        pst: u8,
    ) {
        let blksize = match check_block_size(blksize) {
            Ok(b) => b,
            Err(code) => return self.abort_object(index, sub, code),
        };
        let info = match self.od.info(index, sub) {
            Ok(info) => info,
            Err(code) => return self.abort_object(index, sub, code),
        };
        if !info.access.is_readable() {
            return self.abort_object(index, sub, AbortCode::ReadOfWriteOnlyObject);
        }
        if pst != 0 && info.len <= usize::from(pst) {
            // The info read above (the protocol switch: a normal upload).
            let result = self.initiate_upload(index, sub, info);
            return self.answer_initiate(now, index, sub, result);
        }
        let Ok(size) = u32::try_from(info.len) else {
            return self.abort_object(index, sub, AbortCode::OutOfMemory);
        };
        self.send(ServerCommand::BlockUpload(ServerBlockUpload::Initiate(
            BlockDataInitiate {
                index,
                sub,
                // CiA 301 section 7.2.4.3.13: sc says the server will send a
                // CRC at the end. Set only when the client asked for one
                // (cc): a client that did not ask may still check a CRC it
                // is told of, and the end frame's CRC is then zero.
                crc: crc && self.config.crc,
                size: Some(size),
            },
        )));
        self.state = State::BlockUploadInitiated {
            index,
            sub,
            len: info.len,
            crc: crc && self.config.crc,
            blksize,
        };
        self.arm(now);
    }

    pub(super) fn on_block_download(
        &mut self,
        now: Timestamp,
        cmd: ClientBlockDownload,
        frame: &[u8],
    ) {
        match (cmd, self.state) {
            (ClientBlockDownload::Initiate(i), _) => {
                self.supersede();
                self.initiate_block_download(now, (i.index, i.sub), i.crc, i.size, frame);
            }
            (
                ClientBlockDownload::End { unused, crc },
                State::BlockDownloading {
                    index,
                    sub,
                    info,
                    mut rx,
                },
            ) if rx.is_done() => {
                let ended = match rx.on_end(unused, crc) {
                    Ok(ended) => ended,
                    Err(code) => return self.abort_local(code),
                };
                let mut result = info.check_download_len(ended.total);
                if let (Ok(()), Some((offset, data))) = (result, ended.write) {
                    result = self.od.write(index, sub, offset, data.as_slice());
                }
                if let Err(code) =
                    result.and_then(|()| self.od.finish_write(index, sub, ended.total))
                {
                    return self.abort_local(code);
                }
                self.send(ServerCommand::BlockDownload(ServerBlockDownload::End));
                self.finish(ServerEvent::Downloaded {
                    index,
                    sub,
                    len: ended.total,
                });
            }
            _ => self.abort_local(AbortCode::InvalidCommandSpecifier),
        }
    }

    fn initiate_block_download(
        &mut self,
        now: Timestamp,
        (index, sub): (u16, u8),
        crc: bool,
        size: Option<u32>,
        frame: &[u8],
    ) {
        let info = match self.od.info(index, sub) {
            Ok(info) => info,
            Err(code) => return self.abort_object(index, sub, code),
        };
        if !info.access.is_writable() {
            return self.abort_object(index, sub, AbortCode::WriteOfReadOnlyObject);
        }
        let size = size.map(|s| usize::try_from(s).unwrap_or(usize::MAX));
        if let Some(size) = size {
            if let Err(code) = info.check_download_len(size) {
                return self.abort_object(index, sub, code);
            }
        }
        let blksize = clamp_block_size(self.config.block_size);
        self.send(ServerCommand::BlockDownload(ServerBlockDownload::Initiate(
            BlockDownloadAccept {
                index,
                sub,
                crc: self.config.crc,
                blksize,
            },
        )));
        self.state = State::BlockDownloading {
            index,
            sub,
            info,
            rx: Receiver::new(blksize, size, crc && self.config.crc).after(frame),
        };
        self.arm(now);
    }
}
