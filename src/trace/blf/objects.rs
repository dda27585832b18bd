//! One stream of BLF objects (the file's top level, or the containers'
//! payloads), parsed from the bytes it is fed: the one place every object
//! is read, whichever way its bytes came.

use super::{
    object_type, BlfError, BlfEvent, BlfFrame, Compression, BASE_HEADER, BUF, CAN_MESSAGE_BODY,
    CONTAINER_HEADER, MAX_HEADER, MAX_PADDING, OBJECT_SIGNATURE, V1_HEADER, V2_HEADER,
};
use crate::clock::Timestamp;
use crate::frame::{CanFrame, CanId, MAX_EXTENDED_ID, MAX_STANDARD_ID};
use crate::trace::fields::{u16_at, u32_at, u64_at};
use crate::trace::{RxTx, Unsupported};

/// Where an object stream is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// The next object's `LOBJ`, `slack` padding bytes skipped so far.
    Signature { slack: u8 },
    /// The base header.
    Base,
    /// The first `want` bytes of the object (header and the fields read).
    Head { want: u8, object_size: u32 },
    /// The rest of the object, skipped.
    Skip { left: u32 },
    /// Top level: a container's payload.
    Payload {
        left: u32,
        compression: Compression,
        declared: u32,
    },
}

/// One stream of objects: the file's top level, or the containers'
/// payloads (one stream across containers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Objects {
    pub(super) step: Step,
    pub(super) buf: [u8; BUF],
    pub(super) have: usize,
    /// Bytes of this stream read.
    pub(super) offset: u64,
    /// The file's top level (its containers are opened).
    top: bool,
}

/// Takes `n` bytes of `input` (at most its length), returning them.
pub(super) fn take<'a>(input: &mut &'a [u8], n: usize) -> &'a [u8] {
    let (head, tail) = input.split_at(n.min(input.len()));
    *input = tail;
    head
}

impl Objects {
    pub(super) const fn new(top: bool) -> Self {
        Objects {
            step: Step::Signature { slack: 0 },
            buf: [0; BUF],
            have: 0,
            offset: 0,
            top,
        }
    }

    /// Fills the buffer up to `n` bytes from `input`; true when it has them.
    pub(super) fn fill(&mut self, input: &mut &[u8], n: usize) -> bool {
        let n = n.min(BUF);
        let got = take(input, n.saturating_sub(self.have));
        if let Some(dst) = self.buf.get_mut(self.have..self.have + got.len()) {
            dst.copy_from_slice(got);
        }
        self.have += got.len();
        self.offset += got.len() as u64;
        self.have >= n
    }

    /// Between objects: nothing held but padding (not the start of a
    /// signature).
    pub(super) fn between_objects(&self) -> bool {
        let held = self.buf.get(..self.have).unwrap_or(&[]);
        match self.step {
            Step::Signature { .. } => held.is_empty() || !OBJECT_SIGNATURE.starts_with(held),
            Step::Skip { left } => left == 0,
            _ => false,
        }
    }

    /// Skips the object's remaining `left` bytes next.
    fn skip(&mut self, left: u32) {
        self.step = Step::Skip { left };
    }

    /// The next event of this stream from `input`; `None` when `input` is
    /// used up (or the stream is in a container's payload, which the
    /// reader takes itself).
    pub(super) fn next(
        &mut self,
        input: &mut &[u8],
        start: Option<Timestamp>,
    ) -> Result<Option<BlfEvent<'static>>, BlfError> {
        loop {
            match self.step {
                Step::Signature { slack } => {
                    // The usual case: the whole object at hand, read where
                    // it lies (no copy).
                    if let (0, Some(&base @ [b'L', b'O', b'B', b'J', ..])) =
                        (self.have, input.first_chunk::<BASE_HEADER>())
                    {
                        let whole = *input;
                        take(input, BASE_HEADER);
                        self.offset += BASE_HEADER as u64;
                        if let Some(event) = self.plan(&base)? {
                            return Ok(Some(event));
                        }
                        let Step::Head { want, object_size } = self.step else {
                            return Ok(None);
                        };
                        if let Some(head) = whole.get(..usize::from(want)) {
                            let rest = usize::from(want) - BASE_HEADER;
                            take(input, rest);
                            self.offset += rest as u64;
                            self.after_head(object_size, want);
                            return self.object(head, start).map(Some);
                        }
                        // Not all at hand: on in the buffer.
                        if let Some(dst) = self.buf.first_chunk_mut::<BASE_HEADER>() {
                            *dst = base;
                        }
                        self.have = BASE_HEADER;
                        continue;
                    }
                    if !self.fill(input, 4) {
                        return Ok(None);
                    }
                    if self.buf.get(..4) == Some(&OBJECT_SIGNATURE[..]) {
                        self.step = Step::Base;
                        continue;
                    }
                    if slack >= MAX_PADDING {
                        return Err(BlfError::BadSignature {
                            offset: self.offset - 4,
                            in_container: !self.top,
                        });
                    }
                    self.buf.copy_within(1..4, 0);
                    self.have = 3;
                    self.step = Step::Signature { slack: slack + 1 };
                }
                Step::Base => {
                    if !self.fill(input, BASE_HEADER) {
                        return Ok(None);
                    }
                    let base = self.buf;
                    if let Some(event) = self.plan(&base)? {
                        return Ok(Some(event));
                    }
                }
                Step::Head { want, object_size } => {
                    if !self.fill(input, usize::from(want)) {
                        return Ok(None);
                    }
                    self.after_head(object_size, want);
                    let head = self.buf;
                    return self.object(&head, start).map(Some);
                }
                Step::Skip { left } => {
                    if left == 0 {
                        self.step = Step::Signature { slack: 0 };
                        self.have = 0;
                        continue;
                    }
                    if input.is_empty() {
                        return Ok(None);
                    }
                    let n = take(input, left as usize).len();
                    self.offset += n as u64;
                    self.skip(left - n as u32);
                }
                Step::Payload { .. } => return Ok(None),
            }
        }
    }

    /// After the first `want` bytes of the object: its rest skipped next.
    fn after_head(&mut self, object_size: u32, want: u8) {
        self.have = 0;
        match object_size.saturating_sub(u32::from(want)) {
            0 => self.step = Step::Signature { slack: 0 },
            left => self.skip(left),
        }
    }

    /// After the base header: what to read of the object. An event when
    /// the object is skipped whole.
    fn plan(&mut self, base: &[u8]) -> Result<Option<BlfEvent<'static>>, BlfError> {
        let header_size = u16_at(base, 4);
        let version = u16_at(base, 6);
        let object_size = u32_at(base, 8);
        let object_type = u32_at(base, 12);
        if (object_size as usize) < BASE_HEADER.max(usize::from(header_size)) {
            return Err(BlfError::ObjectSmallerThanHeader {
                object_size,
                header_size,
            });
        }
        let rest = object_size - BASE_HEADER as u32;
        let header = usize::from(header_size);
        if self.top && object_type == object_type::LOG_CONTAINER {
            // A container has the base header only (its header size says
            // where its own fields begin).
            let want = header + CONTAINER_HEADER;
            if !(BASE_HEADER..=MAX_HEADER).contains(&header) {
                return Err(BlfError::ContainerHeaderSize { header_size });
            }
            if (object_size as usize) < want {
                return Err(BlfError::ContainerTooShort { object_size });
            }
            self.step = Step::Head {
                want: want as u8,
                object_size,
            };
            return Ok(None);
        }
        let fixed = match version {
            1 => V1_HEADER,
            2 => V2_HEADER,
            _ => {
                self.skip(rest);
                return Ok(Some(BlfEvent::Skipped { object_type }));
            }
        };
        if !(fixed..=MAX_HEADER).contains(&header) {
            self.skip(rest);
            return Err(BlfError::HeaderSize {
                header_size,
                version,
            });
        }
        let body = match object_type {
            object_type::CAN_MESSAGE | object_type::CAN_MESSAGE2 => CAN_MESSAGE_BODY,
            _ => 0,
        };
        let want = header + body;
        if (object_size as usize) < want {
            self.skip(rest);
            return Err(BlfError::ObjectTooShort {
                object_type,
                object_size,
            });
        }
        self.step = Step::Head {
            want: want as u8,
            object_size,
        };
        Ok(None)
    }

    /// The object held in the buffer, read; the step after it is set.
    fn object(
        &mut self,
        b: &[u8],
        start: Option<Timestamp>,
    ) -> Result<BlfEvent<'static>, BlfError> {
        let header = usize::from(u16_at(b, 4));
        let object_size = u32_at(b, 8);
        let object_type = u32_at(b, 12);
        if self.top && object_type == object_type::LOG_CONTAINER {
            let method = u16_at(b, header);
            let declared = u32_at(b, header + 8);
            let left = object_size - (header + CONTAINER_HEADER) as u32;
            let compression = match method {
                0 if left != declared => {
                    return Err(BlfError::StoredSizeMismatch {
                        payload: left,
                        declared,
                    })
                }
                0 => Compression::Stored,
                2 => Compression::Zlib,
                _ => return Err(BlfError::UnknownCompression { method }),
            };
            self.step = Step::Payload {
                left,
                compression,
                declared,
            };
            return Ok(BlfEvent::ContainerStart {
                compression,
                uncompressed_size: declared,
            });
        }
        // Flags and timestamp sit at the same places in both versions.
        let ticks = u64_at(b, 24);
        let since_start = match u32_at(b, 16) {
            1 => Some(ticks.saturating_mul(10)),
            // To the nearest microsecond (a writer's float seconds make
            // 1 ms into 999 999 ns).
            2 => Some(ticks.saturating_add(500) / 1000),
            _ => None,
        };
        let timestamp = since_start.map(|us| start.unwrap_or(Timestamp::ZERO).add_micros(us));
        let unsupported = |what| BlfEvent::Unsupported {
            what,
            object_type,
            timestamp,
        };
        Ok(match object_type {
            object_type::CAN_MESSAGE | object_type::CAN_MESSAGE2 => {
                BlfEvent::Frame(can_message(b.get(header..).unwrap_or(&[]), timestamp)?)
            }
            object_type::CAN_ERROR | object_type::CAN_ERROR_EXT => {
                unsupported(Unsupported::ErrorFrame)
            }
            object_type::CAN_FD_MESSAGE | object_type::CAN_FD_MESSAGE_64 => {
                unsupported(Unsupported::CanFd)
            }
            _ => BlfEvent::Skipped { object_type },
        })
    }
}

/// A `CAN_MESSAGE` / `CAN_MESSAGE2` body: channel, flags, DLC, identifier,
/// data.
fn can_message(body: &[u8], timestamp: Option<Timestamp>) -> Result<BlfFrame, BlfError> {
    let [c0, c1, flags, dlc, i0, i1, i2, i3, d0, d1, d2, d3, d4, d5, d6, d7, ..] = *body else {
        return Err(BlfError::ObjectTooShort {
            object_type: object_type::CAN_MESSAGE,
            object_size: body.len() as u32,
        });
    };
    let raw = u32::from_le_bytes([i0, i1, i2, i3]);
    let id = if raw & 1 << 31 != 0 {
        CanId::Extended(raw & MAX_EXTENDED_ID)
    } else if raw <= u32::from(MAX_STANDARD_ID) {
        CanId::Standard(raw as u16)
    } else {
        return Err(BlfError::BadId { raw });
    };
    // ISO 11898-1: a classic frame's DLC above 8 carries 8 bytes.
    let len = dlc.min(8);
    let frame = if flags & 0x80 != 0 {
        CanFrame::remote(id, len)
    } else {
        CanFrame::new(
            id,
            [d0, d1, d2, d3, d4, d5, d6, d7]
                .get(..usize::from(len))
                .unwrap_or(&[]),
        )
    }
    .map_err(|_| BlfError::BadId { raw })?;
    Ok(BlfFrame {
        timestamp,
        channel: u16::from_le_bytes([c0, c1]),
        direction: if flags & 1 != 0 { RxTx::Tx } else { RxTx::Rx },
        frame,
    })
}
