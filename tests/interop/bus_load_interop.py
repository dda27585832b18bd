#!/usr/bin/env python3
"""The summary's bus load against a count of our own, written from
ISO 11898-1 (classic CAN frame format, bit stuffing, CRC-15) here and
sharing no code with the decoder.

Usage: bus_load_interop.py CANOPEN_DECODE CAPTURE.log [CAPTURE.log ...]

Each log (the real captures, and a random trace python-can's
CanutilsLogWriter writes: 11- and 29-bit identifiers, remote frames, 0-8
data bytes, seed 37) is read with python-can's CanutilsLogReader; each
frame's bits are laid out (start of frame, arbitration with SRR/IDE for
a 29-bit identifier, control, data, CRC sequence), its CRC-15 computed,
the stuff bits counted (one after five equal bits, the stuff bit
starting the next run) and the fixed tail (CRC delimiter, ACK slot and
delimiter, end of frame, intermission: 13 bits) added. The unstuffed
count is the same without stuff bits, the worst case adds floor((g - 1)
/ 4) stuff bits to the g stuffed-region bits.

`canopen-decode --json --summary-only --bitrate 250000` (and 125000 for
one log) must give: the exact bits of every COB-ID and every node
(predefined connection set: 080h+n EMCY, 180h-57Fh PDOs, 580h+n and
600h+n SDO, 700h+n heartbeat; anything else no node), the frames, the
mean load over the log (from the first frame's start to the last
frame's time) within 1e-9 of ours, lying between the unstuffed and the
worst-case loads, which equal ours too, and the peak 1-second window
(windows aligned to the first frame's time, a frame counting in the
window of its time): its start, frames and three loads. Prints one line
per case and "N cases, M failed"; exits 1 on any mismatch.
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
from collections import defaultdict
from decimal import Decimal

import can


def crc15(bits):
    """CAN's CRC-15 (polynomial 4599h) of a bit sequence."""
    crc = 0
    for b in bits:
        top = ((crc >> 14) & 1) ^ b
        crc = (crc << 1) & 0x7FFF
        if top:
            crc ^= 0x4599
    return crc


def to_bits(value, width):
    return [(value >> (width - 1 - i)) & 1 for i in range(width)]


def frame_bits(ident, extended, remote, dlc, data):
    """(exact stuffed, unstuffed, worst case) bit counts of a classic frame."""
    rtr = 1 if remote else 0
    bits = [0]  # start of frame (dominant)
    if extended:
        bits += to_bits(ident >> 18, 11) + [1, 1] + to_bits(ident & 0x3FFFF, 18) + [rtr, 0, 0]
    else:
        bits += to_bits(ident, 11) + [rtr, 0, 0]
    bits += to_bits(dlc, 4)
    if not remote:
        for byte in data:
            bits += to_bits(byte, 8)
    bits += to_bits(crc15(bits), 15)
    stuffed = 0
    run_bit, run = None, 0
    for b in bits:
        if b == run_bit:
            run += 1
        else:
            run_bit, run = b, 1
        if run == 5:
            stuffed += 1
            run_bit, run = 1 - b, 1  # the stuff bit is the complement
    tail = 13
    g = len(bits)
    return g + stuffed + tail, g + tail, g + tail + (g - 1) // 4


def node_of(ident, extended):
    if extended:
        return None
    fn, n = ident & 0x780, ident & 0x7F
    if n == 0:
        return None
    if fn == 0x080 or 0x180 <= fn <= 0x500 or fn in (0x580, 0x600, 0x700):
        return n
    return None


def our_load(path, bitrate):
    frames = []
    with can.CanutilsLogReader(path) as r:
        for m in r:
            if m.is_error_frame or m.is_fd:
                continue
            us = int((Decimal(repr(m.timestamp)) * 1000000).to_integral_value())
            counts = frame_bits(m.arbitration_id, m.is_extended_id, m.is_remote_frame, m.dlc, bytes(m.data))
            frames.append((us, m.arbitration_id, m.is_extended_id, counts))
    per_cob = defaultdict(int)
    per_node = defaultdict(int)
    totals = [0, 0, 0]
    for us, ident, extended, counts in frames:
        per_cob[(ident, extended)] += counts[0]
        per_node[node_of(ident, extended)] += counts[0]
        for i in range(3):
            totals[i] += counts[i]
    first_us, last_us = frames[0][0], frames[-1][0]
    # The log runs from the first frame's start (its time less its own
    # exact bits) to the last frame's time.
    duration = (last_us - first_us) / 1e6 + frames[0][3][0] / bitrate
    mean = [100 * t / bitrate / duration for t in totals]
    windows = defaultdict(lambda: [0, 0, 0, 0])
    for us, _ident, _extended, counts in frames:
        w = windows[(us - first_us) // 1000000]
        w[0] += 1
        for i in range(3):
            w[i + 1] += counts[i]
    k, w = max(sorted(windows.items()), key=lambda kw: kw[1][1])
    peak = {
        "start": (first_us + k * 1000000) / 1e6,
        "frames": w[0],
        "loads": [100 * b / bitrate for b in w[1:]],
    }
    return len(frames), totals, mean, peak, dict(per_cob), dict(per_node)


def decoder_load(decoder, path, bitrate):
    run = subprocess.run(
        [decoder, "--json", "--summary-only", "--bitrate", str(bitrate), path],
        capture_output=True,
        text=True,
    )
    for line in run.stdout.splitlines():
        v = json.loads(line)
        if "bus_load" in v:
            return run, v
    return run, None


def check(name, decoder, path, bitrate):
    problems = []
    count, totals, mean, peak, per_cob, per_node = our_load(path, bitrate)
    run, summary = decoder_load(decoder, path, bitrate)
    if summary is None:
        print(f"{name}: no summary (exit {run.returncode}): {run.stderr[-300:]}")
        return False
    b = summary["bus_load"]
    if "panicked" in run.stderr:
        problems.append("panicked")
    if b["bitrate"] != bitrate or b["bitrate_assumed"] or b["frames"] != count:
        problems.append(f"bitrate {b['bitrate']} assumed {b['bitrate_assumed']} frames {b['frames']} (ours {count})")
    got_mean = [b["bus_load_percent"], b["unstuffed_percent"], b["worst_case_percent"]]
    if any(abs(g - w) > 1e-9 for g, w in zip(got_mean, mean)):
        problems.append(f"mean loads {got_mean}, ours {mean}")
    if summary.get("bus_load_percent") != b["bus_load_percent"]:
        problems.append("the summary's bus_load_percent is not bus_load's")
    if not got_mean[1] <= got_mean[0] <= got_mean[2]:
        problems.append(f"the load {got_mean[0]} is not between {got_mean[1]} and {got_mean[2]}")
    p = b["peak_window"]
    got_peak = [p["bus_load_percent"], p["unstuffed_percent"], p["worst_case_percent"]]
    # The decoder rounds the window's loads to 4 decimals.
    if (
        abs(p["start"] - peak["start"]) > 1e-6
        or p["frames"] != peak["frames"]
        or any(abs(g - w) > 5e-5 for g, w in zip(got_peak, peak["loads"]))
    ):
        problems.append(f"peak window {p}, ours {peak}")
    cobs = {(c["cob_id"], c["extended"]): c["bits"] for c in b["cob_ids"]}
    if b["other_cob_ids"]["bits"] or cobs != per_cob:
        diff = {k: (cobs.get(k), per_cob.get(k)) for k in set(cobs) | set(per_cob) if cobs.get(k) != per_cob.get(k)}
        problems.append(f"COB-ID bits (decoder, ours) differ: {sorted(diff.items(), key=str)[:5]}")
    nodes = {n["node"]: n["bits"] for n in b["nodes"]}
    if nodes != per_node:
        problems.append(f"node bits {nodes}, ours {per_node}")
    total = sum(per_node.values())
    for n in b["nodes"]:
        if abs(n["share_percent"] - 100 * n["bits"] / total) > 1e-9:
            problems.append(f"node {n['node']} share {n['share_percent']}")
    print(
        f"{name} at {bitrate} bit/s: {count} frames, {totals[0]} bits (unstuffed {totals[1]}, worst {totals[2]}), "
        f"mean {got_mean[0]:.4f}% in [{got_mean[1]:.4f}, {got_mean[2]:.4f}], peak {got_peak[0]:.4f}%, "
        f"{len(per_node)} node entries: {'ok' if not problems else 'FAILED'}"
    )
    for x in problems[:5]:
        print("   ", x)
    return not problems


def random_trace(path):
    """A random trace of python-can's own writer: 11- and 29-bit, remote
    frames, 0-8 data bytes, 500 frames over 3.5 s, some very dense."""
    rng = random.Random(37)
    t = 1_700_000_000.0
    w = can.CanutilsLogWriter(path, channel="can0")
    for i in range(500):
        t += rng.choice([0.0005, 0.001, 0.01, 0.02])
        extended = rng.random() < 0.3
        ident = rng.randrange(1 << 29) if extended else rng.randrange(0x800)
        remote = rng.random() < 0.1
        dlc = rng.randrange(9)
        data = b"" if remote else bytes(rng.choice([0x00, 0xFF, rng.randrange(256)]) for _ in range(dlc))
        w.on_message_received(
            can.Message(timestamp=t, arbitration_id=ident, is_extended_id=extended, is_remote_frame=remote, dlc=dlc, data=data)
        )
    w.stop()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("decoder")
    ap.add_argument("captures", nargs="+")
    args = ap.parse_args()
    # A hand count first: the script's own counter must give what
    # ISO 11898-1 gives for frames laid out by hand (a base frame of no
    # data and all-zero identifier: the CRC of 19 zeros is 0, and the 34
    # stuffed-region bits, all dominant, take one stuff bit per five: 6;
    # the worst case is 8).
    assert crc15([0] * 19) == 0
    assert frame_bits(0, False, False, 0, b"") == (47 + 6, 47, 47 + 8)
    cases = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        generated = os.path.join(tmp, "python-can-random.log")
        random_trace(generated)
        logs = [(os.path.basename(c), c) for c in args.captures] + [("python-can random trace", generated)]
        for name, path in logs:
            for bitrate in (250000,) if path != generated else (125000, 1000000):
                cases += 1
                failed += not check(name, args.decoder, path, bitrate)
    print(f"{cases} cases, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
