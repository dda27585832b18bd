#!/usr/bin/env python3
"""Writes the same N classic CAN frames in every format canopen-decode reads,
for benches/decoder_memory.sh: candump -L, and through python-can's writers
ASC, PCAN TRC, CSV, BLF and MF4 (MF4Writer, its default compression level 2:
transposed deflate ##DZ, and level 0: ##DT, `frames-N.dt.mf4`),
pcap and pcapng of a SocketCAN interface (link type 227) written here.

Usage: memory_logs.py N FOLDER
The frames: a CANopen mix (heartbeats, TPDOs of nodes 1-4, an SDO
exchange, SYNC), 1 ms apart from 1 757 000 000 s.
"""
import os
import struct
import sys

import can


def frames(n):
    t0 = 1_757_000_000.0
    kinds = [
        (0x701, b"\x05"),
        (0x181, bytes(range(8))),
        (0x282, b"\x10\x20\x30\x40"),
        (0x603, b"\x40\x18\x10\x01\x00\x00\x00\x00"),
        (0x583, b"\x43\x18\x10\x01\x11\x22\x33\x44"),
        (0x080, b""),
        (0x184, b"\xAA\x55\x01\x02\x03\x04"),
    ]
    for i in range(n):
        ident, data = kinds[i % len(kinds)]
        if ident in (0x181, 0x184):
            data = bytes((b + i) & 0xFF for b in data)
        yield t0 + i / 1000, ident, data


def candump(path, n):
    with open(path, "w") as f:
        for t, ident, data in frames(n):
            f.write(f"({t:.6f}) can0 {ident:03X}#{data.hex().upper()}\n")


def python_can(path, n, **kw):
    with can.Logger(path, **kw) as w:
        for t, ident, data in frames(n):
            w.on_message_received(can.Message(timestamp=t, arbitration_id=ident, is_extended_id=False, data=data, channel=0))


def socketcan(ident, data):
    return struct.pack(">IB3x", ident, len(data)) + data.ljust(8, b"\0")


def pcap(path, n):
    with open(path, "wb") as f:
        f.write(struct.pack("<IHHiIII", 0xA1B2C3D4, 2, 4, 0, 0, 65535, 227))
        for t, ident, data in frames(n):
            us = round(t * 1e6)
            p = socketcan(ident, data)
            f.write(struct.pack("<IIII", us // 1_000_000, us % 1_000_000, len(p), len(p)) + p)


def pcapng(path, n):
    with open(path, "wb") as f:
        f.write(struct.pack("<IIIHHq", 0x0A0D0D0A, 28, 0x1A2B3C4D, 1, 0, -1) + struct.pack("<I", 28))
        f.write(struct.pack("<IIHHII", 1, 20, 227, 0, 65535, 20))
        for t, ident, data in frames(n):
            us = round(t * 1e6)
            p = socketcan(ident, data)
            length = 28 + len(p) + 4
            f.write(struct.pack("<IIIIIII", 6, length, 0, us >> 32, us & 0xFFFFFFFF, len(p), len(p)) + p + struct.pack("<I", length))


def main():
    n, folder = int(sys.argv[1]), sys.argv[2]
    os.makedirs(folder, exist_ok=True)
    out = lambda ext: os.path.join(folder, f"frames-{n}.{ext}")
    candump(out("log"), n)
    for ext in ("asc", "trc", "csv", "blf", "mf4"):
        python_can(out(ext), n)
    python_can(out("dt.mf4"), n, compression_level=0)
    pcap(out("pcap"), n)
    pcapng(out("pcapng"), n)


if __name__ == "__main__":
    main()
