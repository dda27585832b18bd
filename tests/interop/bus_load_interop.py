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

A third trace python-can writes holds CAN FD frames (0-64 bytes, BRS
and ESI at random, 11- and 29-bit) and error frames among classic ones.
A CAN FD frame is laid out as ISO 11898-1:2015 section 10.4.2 has it:
start of frame, identifier with RRS (SRR and IDE for 29 bits), FDF, res,
BRS (the arbitration phase, at the nominal rate), then ESI, DLC and the
data; dynamic stuff bits over those, none due after the last data bit
(the CRC field's first fixed stuff bit takes its place); the CRC field
(stuff count 4, CRC-17 or CRC-21 above 16 bytes, 6 or 7 fixed stuff
bits) in the data phase, at the data rate when BRS is set; the tail (13
bits) at the nominal rate. The worst case adds floor((g - 1) / 4) stuff
bits, floor((a - 1) / 4) of them in the a bits of the arbitration phase.
An error frame is 17 bits (23 in the worst case) at the nominal rate.
The time of a frame is its nominal bits over the nominal rate plus its
data-phase bits over the data rate; the loads and shares are of time.

`canopen-decode --json --summary-only --bitrate 250000` (and 125000 for
one log; and with `--data-bitrate` for the FD trace) must give: the exact bits of every COB-ID and every node
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


FD_LENGTHS = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64]


def fd_frame_bits(ident, extended, brs, esi, data):
    """((exact, unstuffed, worst) at the nominal rate, (the same) at the
    data rate) of a CAN FD frame."""
    dlc = next(i for i, n in enumerate(FD_LENGTHS) if n >= len(data))
    data = bytes(data) + bytes(FD_LENGTHS[dlc] - len(data))
    bits = [0]
    if extended:
        bits += to_bits(ident >> 18, 11) + [1, 1] + to_bits(ident & 0x3FFFF, 18) + [0]
    else:
        bits += to_bits(ident, 11) + [0, 0]
    bits += [1, 0, 1 if brs else 0]  # FDF, res, BRS
    a = len(bits)
    bits += [1 if esi else 0] + to_bits(dlc, 4)
    for byte in data:
        bits += to_bits(byte, 8)
    g = len(bits)
    stuff_at = []  # the index of the bit each stuff bit follows
    run_bit, run = None, 0
    for i, b in enumerate(bits):
        if b == run_bit:
            run += 1
        else:
            run_bit, run = b, 1
        if run == 5:
            stuff_at.append(i)
            run_bit, run = 1 - b, 1
    stuff_at = [i for i in stuff_at if i != g - 1]  # the fixed stuff bit instead
    s_a = sum(1 for i in stuff_at if i < a - 1)
    s_d = len(stuff_at) - s_a
    crc_field = 4 + 17 + 6 if len(data) <= 16 else 4 + 21 + 7
    w, w_a = (g - 1) // 4, (a - 1) // 4
    nominal = (a + 13 + s_a, a + 13, a + 13 + w_a)
    fast = (g - a + crc_field + s_d, g - a + crc_field, g - a + crc_field + w - w_a)
    if brs:
        return nominal, fast
    return tuple(x + y for x, y in zip(nominal, fast)), (0, 0, 0)


ERROR_FRAME = ((17, 17, 23), (0, 0, 0))


def node_of(ident, extended):
    if extended:
        return None
    fn, n = ident & 0x780, ident & 0x7F
    if n == 0:
        return None
    if fn == 0x080 or 0x180 <= fn <= 0x500 or fn in (0x580, 0x600, 0x700):
        return n
    return None


def our_load(path, bitrate, data_bitrate):
    frames = []
    with can.CanutilsLogReader(path) as r:
        for m in r:
            us = int((Decimal(repr(m.timestamp)) * 1000000).to_integral_value())
            if m.is_error_frame:
                counts, key = ERROR_FRAME, None
            elif m.is_fd:
                counts = fd_frame_bits(m.arbitration_id, m.is_extended_id, m.bitrate_switch, m.error_state_indicator, bytes(m.data))
                key = (m.arbitration_id, m.is_extended_id)
            else:
                counts = (frame_bits(m.arbitration_id, m.is_extended_id, m.is_remote_frame, m.dlc, bytes(m.data)), (0, 0, 0))
                key = (m.arbitration_id, m.is_extended_id)
            # Seconds on the bus: (exact, unstuffed, worst case).
            time = [counts[0][i] / bitrate + counts[1][i] / data_bitrate for i in range(3)]
            frames.append((us, key, counts, time))
    per_cob = defaultdict(int)
    per_node = defaultdict(int)
    node_time = defaultdict(float)
    totals = [0, 0, 0]
    total_time = [0.0, 0.0, 0.0]
    errors = fd = brs = 0
    for us, key, counts, time in frames:
        bits = counts[0][0] + counts[1][0]
        if key is None:
            errors += 1
        else:
            per_cob[key] += bits
            per_node[node_of(*key)] += bits
            node_time[node_of(*key)] += time[0]
        for i in range(3):
            totals[i] += counts[0][i] + counts[1][i]
            total_time[i] += time[i]
    first_us, last_us = frames[0][0], frames[-1][0]
    # The log runs from the first frame's start (its time less its own
    # exact time on the bus) to the last frame's time.
    duration = (last_us - first_us) / 1e6 + frames[0][3][0]
    mean = [100 * t / duration for t in total_time]
    windows = defaultdict(lambda: [0, 0.0, 0.0, 0.0])
    for us, _key, _counts, time in frames:
        w = windows[(us - first_us) // 1000000]
        w[0] += 1
        for i in range(3):
            w[i + 1] += time[i]
    k, w = max(sorted(windows.items()), key=lambda kw: kw[1][1])
    peak = {
        "start": (first_us + k * 1000000) / 1e6,
        "frames": w[0],
        "loads": [100 * t for t in w[1:]],
    }
    shares = {n: 100 * t / total_time[0] for n, t in node_time.items()}
    return len(frames), totals, mean, peak, dict(per_cob), dict(per_node), shares, errors


def decoder_load(decoder, path, bitrate, data_bitrate):
    rates = ["--bitrate", str(bitrate)] + (["--data-bitrate", str(data_bitrate)] if data_bitrate else [])
    run = subprocess.run(
        [decoder, "--json", "--summary-only", *rates, path],
        capture_output=True,
        text=True,
    )
    for line in run.stdout.splitlines():
        v = json.loads(line)
        if "bus_load" in v:
            return run, v
    return run, None


def check(name, decoder, path, bitrate, data_bitrate=None):
    """`data_bitrate` None: the decoder's assumed 2 Mbit/s."""
    problems = []
    data_rate = max(data_bitrate or 2000000, bitrate)
    count, totals, mean, peak, per_cob, per_node, shares, errors = our_load(path, bitrate, data_rate)
    run, summary = decoder_load(decoder, path, bitrate, data_bitrate)
    if summary is None:
        print(f"{name}: no summary (exit {run.returncode}): {run.stderr[-300:]}")
        return False
    b = summary["bus_load"]
    if "panicked" in run.stderr:
        problems.append("panicked")
    if b["bitrate"] != bitrate or b["bitrate_assumed"] or b["frames"] != count:
        problems.append(f"bitrate {b['bitrate']} assumed {b['bitrate_assumed']} frames {b['frames']} (ours {count})")
    if b["data_bitrate"] != data_rate or b["data_bitrate_assumed"] != (data_bitrate is None):
        problems.append(f"data bitrate {b['data_bitrate']} assumed {b['data_bitrate_assumed']}")
    if b["error_frames"] != errors or b["fd_frames_not_in_load"]:
        problems.append(f"error frames {b['error_frames']} (ours {errors}), FD not in the load {b['fd_frames_not_in_load']}")
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
    for n in b["nodes"]:
        if abs(n["share_percent"] - shares[n["node"]]) > 1e-9:
            problems.append(f"node {n['node']} share {n['share_percent']}, ours {shares[n['node']]}")
    rates = f"{bitrate} bit/s" + (f", data {data_rate} bit/s" if b["fd_frames"] else "")
    print(
        f"{name} at {rates}: {count} frames ({b['fd_frames']} FD, {errors} error), {totals[0]} bits (unstuffed {totals[1]}, worst {totals[2]}), "
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


def random_fd_trace(path):
    """A random trace of python-can's writer with CAN FD frames (BRS, ESI,
    0-64 bytes) and error frames among classic ones: 400 frames."""
    rng = random.Random(418)
    t = 1_700_000_000.0
    w = can.CanutilsLogWriter(path, channel="can0")
    for i in range(400):
        t += rng.choice([0.0002, 0.001, 0.01, 0.05])
        extended = rng.random() < 0.3
        ident = rng.randrange(1 << 29) if extended else rng.randrange(0x800)
        kind = rng.random()
        if kind < 0.05:
            m = can.Message(timestamp=t, is_error_frame=True, arbitration_id=rng.choice([0x4, 0x80]), data=bytes(8))
        elif kind < 0.5:
            n = rng.choice(FD_LENGTHS)
            data = bytes(rng.choice([0x00, 0xFF, 0x55, rng.randrange(256)]) for _ in range(n))
            m = can.Message(
                timestamp=t,
                arbitration_id=ident,
                is_extended_id=extended,
                is_fd=True,
                bitrate_switch=rng.random() < 0.7,
                error_state_indicator=rng.random() < 0.2,
                data=data,
            )
        else:
            dlc = rng.randrange(9)
            data = bytes(rng.choice([0x00, 0xFF, rng.randrange(256)]) for _ in range(dlc))
            m = can.Message(timestamp=t, arbitration_id=ident, is_extended_id=extended, data=data)
        w.on_message_received(m)
    w.stop()


def same_as_asc(decoder, log, asc):
    """The FD trace written again by python-can's ASCWriter (CANFD and
    ErrorFrame lines) gives the candump log's bus load: the same bits per
    COB-ID, FD and error frames, and mean loads."""
    with can.CanutilsLogReader(log) as r, can.ASCWriter(asc) as w:
        for m in r:
            m.channel = 0
            w.on_message_received(m)
    loads = []
    for path in (log, asc):
        run, summary = decoder_load(decoder, path, 500000, 2000000)
        if summary is None:
            print(f"ASC copy: no summary for {path} (exit {run.returncode}): {run.stderr[-300:]}")
            return False
        b = summary["bus_load"]
        cobs = {(c["cob_id"], c["extended"]): c["bits"] for c in b["cob_ids"]}
        counts = [b[k] for k in ("frames", "error_frames", "fd_frames", "fd_brs_frames", "fd_frames_not_in_load")]
        loads.append((cobs, counts, [b["bus_load_percent"], b["unstuffed_percent"], b["worst_case_percent"]]))
    (cobs, counts, mean), (a_cobs, a_counts, a_mean) = loads
    problems = []
    if cobs != a_cobs:
        problems.append(f"{len(set(cobs.items()) ^ set(a_cobs.items()))} COB-ID bit counts differ")
    if counts != a_counts:
        problems.append(f"frames, error, FD, BRS, FD not in the load: {a_counts}, the candump log's {counts}")
    if any(abs(x - y) > 1e-6 for x, y in zip(mean, a_mean)):
        problems.append(f"mean loads {a_mean}, the candump log's {mean}")
    print(f"python-can ASC copy of the FD trace: {a_counts[0]} frames ({a_counts[2]} FD, {a_counts[1]} error): {'ok' if not problems else 'FAILED'}")
    for x in problems:
        print("   ", x)
    return not problems


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
    # CAN FD by hand: 123h, BRS, 64 bytes FFh: 17 + 13 nominal bits (no
    # stuff bit: runs of at most 3), at most 4 stuff bits there; ESI 0,
    # DLC 1111 and 512 ones are one run of 516 ones (103 stuff bits), with
    # the CRC field's 4 + 21 + 7 bits: 549 + 103, at most 549 + 133 - 4.
    assert fd_frame_bits(0x123, False, True, False, b"\xff" * 64) == ((30, 30, 34), (652, 549, 678))
    # 123h, BRS, 1Fh: FDF 1, res 0, BRS 1, ESI 0, DLC 0001, 0001 1111:
    # the run of 5 ones ending the data takes no dynamic stuff bit; 62 + 8
    # bits, 30 nominal and 5 + 8 + 27 data; at most 4 and 3 stuff bits.
    assert fd_frame_bits(0x123, False, True, False, b"\x1f") == ((30, 30, 34), (40, 40, 43))
    # Without BRS: res, BRS, ESI and the DLC's three zeros are a run of 6,
    # one stuff bit; all 71 bits nominal.
    assert fd_frame_bits(0x123, False, False, False, b"\x1f") == ((71, 70, 77), (0, 0, 0))
    cases = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        generated = os.path.join(tmp, "python-can-random.log")
        random_trace(generated)
        logs = [(os.path.basename(c), c) for c in args.captures] + [("python-can random trace", generated)]
        for name, path in logs:
            for bitrate in (250000,) if path != generated else (125000, 1000000):
                cases += 1
                failed += not check(name, args.decoder, path, bitrate)
        fd_trace = os.path.join(tmp, "python-can-fd.log")
        random_fd_trace(fd_trace)
        for bitrate, data_bitrate in ((500000, 2000000), (1000000, 8000000), (250000, None)):
            cases += 1
            failed += not check("python-can CAN FD and error frames", args.decoder, fd_trace, bitrate, data_bitrate)
        cases += 1
        failed += not same_as_asc(args.decoder, fd_trace, os.path.join(tmp, "python-can-fd.asc"))
    print(f"{cases} cases, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
