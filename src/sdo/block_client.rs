//! Block download and block upload of [`Client`] (CiA 301 section
//! 7.2.4.3, SDO protocols: SDO block download and upload): the commands,
//! the responses the block states accept, and the lazily made segments of
//! a block download.
//! The sub-block rules themselves are shared with the server
//! (`super::super::block`).

use super::super::block::{check_block_size, clamp_block_size, Acked, Receiver, Sender};
use super::super::wire::{ServerBlockDownload, ServerBlockUpload};
use super::super::words;
use super::{AbortCode, Client, ClientError, ClientEvent, ServerCommand, State};
use crate::clock::Timestamp;
use crate::frame::CanFrame;

impl<D: AsRef<[u8]>, const EVENTS: usize> Client<D, EVENTS> {
    /// Starts reading `index`/`sub` from the server by block upload (CiA
    /// 301 section 7.2.4.3, SDO block upload), asking for sub-blocks of
    /// [`ClientConfig::block_size`](super::ClientConfig::block_size)
    /// segments, with CRC if [`ClientConfig::crc`](super::ClientConfig::crc)
    /// and the protocol switch threshold
    /// [`ClientConfig::block_threshold`](super::ClientConfig::block_threshold).
    /// The value arrives as [`ClientEvent::UploadData`] pieces, as in a
    /// segmented upload, then [`ClientEvent::Uploaded`].
    pub fn start_block_upload(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
    ) -> Result<(), ClientError> {
        self.check_idle()?;
        // Initiate (cs = 0): CRC support, block size, threshold.
        let b0 = 0xA0 | u8::from(self.config.crc) << 2;
        let blksize = clamp_block_size(self.config.block_size);
        let tail = u32::from_le_bytes([blksize, self.config.block_threshold, 0, 0]);
        self.send(words::mux(b0, index, sub, tail));
        self.state = State::BlockUploadInitiated { index, sub };
        self.arm(now);
        Ok(())
    }

    /// Starts writing `data` to `index`/`sub` by block download (CiA 301
    /// section 7.2.4.3, SDO block download), with the size indicated and CRC if
    /// [`ClientConfig::crc`](super::ClientConfig::crc); the server chooses
    /// the block size. Values of any length, 0 included, go by block.
    pub fn start_block_download(
        &mut self,
        now: Timestamp,
        index: u16,
        sub: u8,
        data: D,
    ) -> Result<(), ClientError> {
        self.check_idle()?;
        let len = data.as_ref().len();
        let Ok(size) = u32::try_from(len) else {
            return Err(ClientError::TooLong { len });
        };
        // Initiate (cs = 0) with CRC support and the size indicated.
        let b0 = 0xC2 | u8::from(self.config.crc) << 2;
        self.send(words::mux(b0, index, sub, size));
        self.state = State::BlockDownloadInitiated { index, sub, data };
        self.arm(now);
        Ok(())
    }

    /// A block upload's sub-block segment: handled here (true), or a
    /// command for the normal path (false).
    pub(super) fn block_segment(&mut self, now: Timestamp, bytes: &[u8]) -> bool {
        let State::BlockUploading { index, sub, rx } = &mut self.state else {
            return false;
        };
        let (index, sub) = (*index, *sub);
        let blksize = rx.block_size();
        let Some(result) = rx.take(bytes) else {
            return false;
        };
        match result {
            Err(code) => self.abort_object(index, sub, code),
            Ok(step) => {
                if let Some((offset, data)) = step.write {
                    self.emit(ClientEvent::UploadData {
                        index,
                        sub,
                        offset,
                        data,
                    });
                }
                if let Some(ackseq) = step.ack {
                    self.send(words::block_ack(ackseq, blksize));
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
                let ServerCommand::BlockDownload(ServerBlockDownload::Initiate {
                    index: ri,
                    sub: rs,
                    crc,
                    blksize,
                }) = cmd
                else {
                    return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
                };
                if (ri, rs) != (index, sub) {
                    return self.abort_object(
                        index,
                        sub,
                        AbortCode::GeneralParameterIncompatibility,
                    );
                }
                let blksize = match check_block_size(blksize) {
                    Ok(b) => b,
                    Err(code) => return self.abort_object(index, sub, code),
                };
                let tx = Sender::new(data.as_ref().len(), blksize, crc && self.config.crc);
                self.state = State::BlockDownloading {
                    index,
                    sub,
                    data,
                    tx,
                };
                self.arm(now);
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
                    Ok(Acked::More) => {
                        self.state = State::BlockDownloading {
                            index,
                            sub,
                            data,
                            tx,
                        };
                        self.arm(now);
                    }
                    Ok(Acked::Done { unused, crc }) => {
                        self.send(words::block_end(unused, crc));
                        self.state = State::BlockDownloadEnding {
                            index,
                            sub,
                            len: data.as_ref().len(),
                        };
                        self.arm(now);
                    }
                }
            }
            State::BlockDownloadEnding { index, sub, len } => {
                if cmd != ServerCommand::BlockDownload(ServerBlockDownload::End) {
                    return self.abort_object(index, sub, AbortCode::InvalidCommandSpecifier);
                }
                self.finish(ClientEvent::Downloaded { index, sub, len });
            }
            State::BlockUploadInitiated { index, sub } => match cmd {
                ServerCommand::BlockUpload(ServerBlockUpload::Initiate {
                    index: ri,
                    sub: rs,
                    crc,
                    size,
                }) => {
                    if (ri, rs) != (index, sub) {
                        return self.abort_object(
                            index,
                            sub,
                            AbortCode::GeneralParameterIncompatibility,
                        );
                    }
                    let size = size.map(|s| usize::try_from(s).unwrap_or(usize::MAX));
                    let blksize = clamp_block_size(self.config.block_size);
                    // Start the upload (cs = 3).
                    self.send(0xA3);
                    self.state = State::BlockUploading {
                        index,
                        sub,
                        rx: Receiver::new(blksize, size, crc && self.config.crc).after(frame),
                    };
                    self.arm(now);
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
                            self.emit(ClientEvent::UploadData {
                                index,
                                sub,
                                offset,
                                data,
                            });
                        }
                        // End acknowledged (cs = 1).
                        self.send(0xA1);
                        self.finish(ClientEvent::Uploaded {
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
