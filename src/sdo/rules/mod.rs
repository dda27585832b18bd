//! The rules of SDO transfers that hold whichever machine applies them
//! (CiA 301 section 7.2.4.3, SDO protocols): the segment rules of
//! segmented transfers (toggle, indicated size) and the sub-block rules
//! of block transfers (sequence numbers, acknowledgements, CRC). The
//! client, the server and the observer apply them; none of them reads or
//! writes a frame (the `wire` layer does).

pub(crate) mod block;
pub(crate) mod segmented;
