#!/usr/bin/env python3
"""python-can's BLFWriter writes, canopen-decode reads (Vector BLF).

Usage: blf_interop.py CANOPEN_DECODE [--seed N]

Writes one random frame set (fixed seed: 11- and 29-bit identifiers,
remote frames with DLC 0-8, data of 0-8 bytes, both directions, times
from microseconds to seconds apart) with python-can's own `BLFWriter`,
zlib-compressed (its default) and stored (compression_level=0), with
small containers (4 KiB, so objects straddle them) and the default
128 KiB, plus CAN FD and error frames among them. Each file is decoded by
`canopen-decode --json` (detected by its LOGG signature; frames that are
not valid CANopen are its bad lines, nothing else may be) and must give
exactly the classic frames written, in order: identifier, 29-bit flag,
remote flag, DLC, data, and time to the microsecond (BLFWriter stores
nanoseconds since a start truncated to the millisecond, in its header).
The CAN FD and error frames must be reported on stderr and counted, not
decoded; python-can's own BLFReader must read back the same frames (the
file is a real BLF). Exits 1 on any mismatch.
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile

import can


def frame_set(seed):
    rng = random.Random(seed)
    t = 1757000000.0 + rng.random()
    frames = []
    for _ in range(300):
        t += rng.choice([1e-6, 37e-6, 1e-3, 0.25, 1.7])
        extended = rng.random() < 0.3
        arb = rng.randrange(1 << 29) if extended else rng.randrange(1 << 11)
        remote = rng.random() < 0.1
        dlc = rng.randrange(9)
        data = b"" if remote else bytes(rng.randrange(256) for _ in range(dlc))
        frames.append(
            can.Message(
                timestamp=round(t, 6),
                arbitration_id=arb,
                is_extended_id=extended,
                is_remote_frame=remote,
                dlc=dlc,
                data=data,
                is_rx=rng.random() < 0.5,
                channel=rng.randrange(2),
            )
        )
    return frames


def write(path, frames, level, container):
    w = can.BLFWriter(path, compression_level=level, max_container_size=container)
    odd = 0
    for i, m in enumerate(frames):
        w.on_message_received(m)
        if i % 97 == 50:
            w.on_message_received(can.Message(timestamp=m.timestamp, arbitration_id=0x123, is_fd=True, data=bytes(range(12))))
            w.on_message_received(can.Message(timestamp=m.timestamp, arbitration_id=0x7FF, is_error_frame=True))
            odd += 1
    w.stop()
    return odd


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("decoder")
    ap.add_argument("--seed", type=int, default=24)
    args = ap.parse_args()
    frames = frame_set(args.seed)
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, level, container in [
            ("zlib-4k", -1, 4096),
            ("zlib-128k", -1, 128 * 1024),
            ("stored-4k", 0, 4096),
            ("stored-128k", 0, 128 * 1024),
        ]:
            path = os.path.join(tmp, name + ".blf")
            odd = write(path, frames, level, container)
            run = subprocess.run([args.decoder, "--json", path], capture_output=True, text=True)
            got = [json.loads(l) for l in run.stdout.splitlines() if l.strip()]
            got = [g for g in got if "id" in g]
            # BLFWriter's start: the first time truncated to the millisecond.
            start = int(frames[0].timestamp * 1000) / 1000
            mismatches = []
            # Random frames are often not valid CANopen (a short EMCY, a
            # remote frame on an SDO identifier): the decoder calls those
            # bad lines and exits 1. Any other complaint is a BLF problem.
            for line in run.stderr.splitlines():
                if line.startswith(("object ", "after object")) and "does not decode" not in line and "not decoded" not in line:
                    mismatches.append(f"stderr: {line}")
            if run.returncode not in (0, 1):
                mismatches.append(f"exit {run.returncode}: {run.stderr[-500:]}")
            if len(got) != len(frames):
                mismatches.append(f"{len(got)} frames read, {len(frames)} written")
            for i, (m, g) in enumerate(zip(frames, got)):
                want = {
                    "id": m.arbitration_id,
                    "extended": m.is_extended_id,
                    "remote": m.is_remote_frame,
                    "dlc": m.dlc,
                    "data": "" if m.is_remote_frame else m.data.hex().upper(),
                }
                have = {k: g.get(k) for k in want}
                have["data"] = (have["data"] or "").upper()
                if have != want:
                    mismatches.append(f"frame {i}: {have} != {want}")
                # Nanoseconds since the start, truncated by BLFWriter, then
                # rounded to the microsecond by the reader.
                ns = int((m.timestamp - start) * 1e9)
                want_t = round(start * 1e6) + (ns + 500) // 1000
                if round(g["t"] * 1e6) != want_t:
                    mismatches.append(f"frame {i}: t {g['t']} != {want_t / 1e6:.6f}")
            for text in [f"{odd} CAN FD frame(s), {odd} error frame(s)", "CanFd not decoded", "ErrorFrame not decoded"]:
                if text not in run.stderr:
                    mismatches.append(f"stderr lacks {text!r}: {run.stderr[-300:]}")
            with can.BLFReader(path) as r:
                back = [m for m in r if not m.is_fd and not m.is_error_frame]
            if [(m.arbitration_id, bytes(m.data)) for m in back] != [(m.arbitration_id, bytes(m.data)) for m in frames]:
                mismatches.append("python-can's BLFReader reads other frames")
            print(f"{name}: {len(frames)} frames written, {len(got)} read, {odd} CAN FD and {odd} error frames reported, {len(mismatches)} mismatches")
            for x in mismatches[:10]:
                print("   ", x)
            failures += bool(mismatches)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
