#!/usr/bin/env python3
"""Writes the seed corpora fuzz/seeds/TARGET/: one small file per real shape,
taken from the tests' own vectors. Rerunnable: rewrites the files it owns.

Covered so far: decode_frame (layout in fuzz/fuzz_targets/decode_frame.rs:
flags byte, identifier little-endian, data)."""
import pathlib

HERE = pathlib.Path(__file__).resolve().parent


def frame(cob_id, data_hex, remote=False):
    data = bytes.fromhex(data_hex)
    flags = (len(data) << 4) | (0x02 if remote else 0)
    return bytes([flags]) + cob_id.to_bytes(2, "little") + data


# (file name, bytes): frames from tests/sdo_vectors.rs and the CiA 301 services.
DECODE_FRAME = [
    ("nmt_start_all", frame(0x000, "01 00")),
    ("sync", frame(0x080, "")),
    ("emcy_node_10", frame(0x08A, "10 81 11 00 00 00 00 00")),
    ("time", frame(0x100, "00 00 00 00 00 00")),
    ("tpdo1_node_10", frame(0x18A, "01 02 03 04 05 06 07 08")),
    ("sdo_upload_request_1018_01", frame(0x602, "40 18 10 01 00 00 00 00")),
    ("sdo_expedited_upload_response", frame(0x582, "43 18 10 01 04 00 00 00")),
    ("sdo_block_upload_initiate", frame(0x602, "A4 00 20 00 7F 00 00 00")),
    ("sdo_abort", frame(0x582, "80 00 20 00 00 00 02 06")),
    ("heartbeat_operational", frame(0x70A, "05")),
    ("bootup", frame(0x70A, "00")),
    ("guarding_rtr", frame(0x70A, "", remote=True)),
    ("lss_switch_global", frame(0x7E5, "04 01 00 00 00 00 00 00")),
]


def write(target, seeds):
    out = HERE / "seeds" / target
    out.mkdir(parents=True, exist_ok=True)
    for name, data in seeds:
        (out / name).write_bytes(data)


if __name__ == "__main__":
    write("decode_frame", DECODE_FRAME)
