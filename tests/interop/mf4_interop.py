#!/usr/bin/env python3
"""python-can's MF4Writer and asammdf write, canopen-decode reads (ASAM MDF 4).

Usage: mf4_interop.py CANOPEN_DECODE CAPTURE.log [CAPTURE.log ...]

Each real capture (candump -L lines) is written as MF4 bus logging by other
tools:

- python-can's `MF4Writer` (through asammdf) with each of its compression
  levels: 0 (##DT), 1 (deflate ##DZ) and 2 (transposed deflate ##DZ);
- asammdf itself re-saving that file as MDF 4.20 in 4 KiB data fragments
  (an ##HL and its ##DL list of transposed ##DZ blocks), and joining two
  python-can files of the capture's halves with its `MDF.concatenate`
  (one data group, deflate) and its `MDF.stack` (a data group each);
- python-can's `MF4Writer` with CAN FD frames among the capture's (the
  decoder reports and counts them, and gives the classic frames);
- python-can's `MF4Writer` with remote and error frames added between the
  capture's frames (python-can puts them in data groups of their own, so
  the decoder must merge the groups by time);
- the stored and the transposed deflate files and asammdf's, each
  gzip-compressed (Python's gzip), as fleets keep their logs, given by
  their path and on stdin (`canopen-decode -`), and the stored file on
  stdin;
- the capture repeated (times shifted) until python-can's stored file is
  over the 1 MiB the decoder holds in memory from stdin or gzip: from
  stdin and gzip-compressed it is copied to a temporary file, which must
  be gone from $TMPDIR (a folder of the script's own) when the decoder
  ends; with $TMPDIR a folder that does not exist, the decoder exits 2
  with an error naming it.

Each file is decoded by `canopen-decode --json` (detected by its MDF
identification) and must give exactly the candump original's frames, in
order: identifier, 29-bit flag, remote flag, DLC, data and the time to the
microsecond (MF4Writer stores seconds as float64 since the header's start
in nanoseconds). The error frames must be reported on stderr and counted,
not decoded; python-can's own `MF4Reader` must read back the same frames
(the file is a real MF4). Prints one line per case and "N cases, 0
failed"; exits 1 on any mismatch.
"""
import argparse
import gzip
import json
import os
import subprocess
import sys
import tempfile

import can
from asammdf import MDF


def candump(path):
    """The capture's frames: (us, id, extended, remote, dlc, data)."""
    frames = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            stamp, _iface, frame = line.split()
            secs, frac = stamp.strip("()").split(".")
            us = int(secs) * 1_000_000 + int(frac.ljust(6, "0")[:6])
            ident, data = frame.split("#", 1)
            remote = data.startswith("R")
            if remote:
                dlc = int(data[1:] or "0")
                payload = b""
            else:
                payload = bytes.fromhex(data)
                dlc = len(payload)
            frames.append((us, int(ident, 16), len(ident) == 8, remote, dlc, payload))
    return frames


def message(f, channel=1):
    us, ident, extended, remote, dlc, data = f
    return can.Message(
        timestamp=us / 1e6,
        arbitration_id=ident,
        is_extended_id=extended,
        is_remote_frame=remote,
        dlc=dlc,
        data=data,
        channel=channel,
    )


def with_events(frames):
    """The frames with a remote frame and an error frame in every 50th gap
    of at least 3 us (at distinct microseconds, so the order is the
    time's)."""
    out, errors = [], 0
    for i, f in enumerate(frames):
        out.append(f)
        nxt = frames[i + 1][0] if i + 1 < len(frames) else f[0] + 10
        if i % 50 == 25 and nxt - f[0] >= 3:
            out.append((f[0] + 1, 0x600 + i % 127 + 1, False, True, 4, b""))
            out.append(("error", f[0] + 2))
            errors += 1
    return out, errors


def write_python_can(path, frames, level):
    w = can.MF4Writer(path, compression_level=level)
    for f in frames:
        if f[0] == "error":
            w.on_message_received(can.Message(timestamp=f[1] / 1e6, arbitration_id=0x7, is_extended_id=False, is_error_frame=True, channel=1))
        else:
            w.on_message_received(message(f))
    w.stop()


def resave_asammdf(src, dst):
    """asammdf's own writer: MDF 4.20, transposed deflate, 4 KiB fragments."""
    with MDF(src) as mdf:
        converted = mdf.convert("4.20")
        converted.configure(write_fragment_size=4096)
        converted.save(dst, compression=2, overwrite=True)
        converted.close()


def write_with_fd(path, frames):
    """python-can's MF4Writer with a 12-byte CAN FD frame (BRS) 1 us after
    every 40th frame; returns how many."""
    w = can.MF4Writer(path, compression_level=2)
    fd = 0
    for i, f in enumerate(frames):
        w.on_message_received(message(f))
        if i % 40 == 7:
            fd += 1
            w.on_message_received(
                can.Message(timestamp=(f[0] + 1) / 1e6, arbitration_id=0x123, is_fd=True, bitrate_switch=True, data=bytes(range(12)), channel=1)
            )
    w.stop()
    return fd


def join_asammdf(tmp, base, frames):
    """asammdf's own writer joining two python-can files, each of one half
    of the frames: `MDF.concatenate` (the halves one after the other in one
    data group, deflate) and `MDF.stack` (a data group per half)."""
    half = len(frames) // 2
    parts = []
    for i, part in enumerate((frames[:half], frames[half:])):
        parts.append(os.path.join(tmp, f"{base}-half-{i}.mf4"))
        write_python_can(parts[-1], part, 2)
    joined = []
    for how in ("concatenate", "stack"):
        dst = os.path.join(tmp, f"{base}-asammdf-{how}.mf4")
        mdf = getattr(MDF, how)(parts)
        mdf.save(dst, compression=1, overwrite=True)
        mdf.close()
        joined.append((how, dst))
    return joined


def decode(decoder, path, stdin=False, spill=None):
    """`canopen-decode --json PATH`, or `-` with the file on stdin; TMPDIR
    is `spill` when given."""
    env = dict(os.environ, TMPDIR=spill) if spill else None
    with open(path, "rb") as f:
        run = subprocess.run(
            [decoder, "--json", "-" if stdin else path],
            stdin=f if stdin else subprocess.DEVNULL,
            capture_output=True,
            text=True,
            env=env,
        )
    got = [json.loads(l) for l in run.stdout.splitlines() if l.strip()]
    return run, [g for g in got if "id" in g]


def check(name, decoder, path, frames, errors, mf4=None, stdin=False, fd=0):
    """mf4: the MF4 file python-can reads back, when PATH is a gzip of it;
    stdin: PATH given on stdin; fd: the CAN FD frames PATH holds besides
    FRAMES (reported and counted, not decoded)."""
    want = [f for f in frames if f[0] != "error"]
    with tempfile.TemporaryDirectory() as spill:
        run, got = decode(decoder, path, stdin, spill)
        left = os.listdir(spill)
    bad = [f"left in the temporary folder: {left}"] if left else []
    for line in run.stderr.splitlines():
        if line.startswith(("record ", "after record")) and "does not decode" not in line and "not decoded" not in line:
            bad.append(f"stderr: {line}")
    if run.returncode not in (0, 1):
        bad.append(f"exit {run.returncode}: {run.stderr[-500:]}")
    if len(got) != len(want):
        bad.append(f"{len(got)} frames read, {len(want)} written")
    for i, (f, g) in enumerate(zip(want, got)):
        us, ident, extended, remote, dlc, data = f
        exp = {"id": ident, "extended": extended, "remote": remote, "dlc": dlc, "data": "" if remote else data.hex().upper()}
        have = {k: g.get(k) for k in exp}
        have["data"] = (have["data"] or "").upper()
        if have != exp:
            bad.append(f"frame {i}: {have} != {exp}")
        if round(g["t"] * 1e6) != us:
            bad.append(f"frame {i}: t {g['t']:.6f} != {us / 1e6:.6f}")
    if errors and f"{errors} error frame(s)" not in run.stderr:
        bad.append(f"stderr lacks '{errors} error frame(s)': {run.stderr[-300:]}")
    if fd and f"{fd} CAN FD frame(s)" not in run.stderr:
        bad.append(f"stderr lacks '{fd} CAN FD frame(s)': {run.stderr[-300:]}")
    with can.MF4Reader(mf4 or path) as r:
        back = [m for m in r if not m.is_error_frame and not m.is_fd]
    if [(m.arbitration_id, m.is_remote_frame, bytes(m.data)) for m in back] != [
        (f[1], f[3], f[5]) for f in want
    ]:
        bad.append("python-can's MF4Reader reads other frames")
    elif [round(m.timestamp * 1e6) for m in back] != [f[0] for f in want]:
        bad.append("python-can's MF4Reader reads other times")
    print(f"{name}: {len(want)} frames written, {len(got)} read, {errors} error frames reported, {len(bad)} mismatches")
    for x in bad[:10]:
        print("   ", x)
    return not bad


def repeated(frames):
    """The frames again and again, each copy 1 s after the last one's end,
    until python-can's stored file of them is over 1 MiB (it takes about
    84 bytes a frame)."""
    span = frames[-1][0] - frames[0][0] + 1_000_000
    copies = (1 << 20) // (84 * len(frames)) + 2
    return [(f[0] + k * span,) + f[1:] for k in range(copies) for f in frames]


def spilled(decoder, tmp, base, frames):
    """The repeated capture's stored file by its path, on stdin, and
    gzip-compressed by its path and on stdin: (cases, failed)."""
    frames = repeated(frames)
    path = os.path.join(tmp, f"{base}-repeated-0.mf4")
    write_python_can(path, frames, 0)
    if os.path.getsize(path) <= 1 << 20:
        print(f"{path}: {os.path.getsize(path)} bytes, not over 1 MiB")
        return 1, 1
    with open(path, "rb") as f, gzip.open(path + ".gz", "wb") as g:
        g.write(f.read())
    name = os.path.basename(path)
    cases = failed = 0
    for src, stdin in ((path, False), (path, True), (path + ".gz", False), (path + ".gz", True)):
        cases += 1
        way = f"{name}{'.gz' if src.endswith('.gz') else ''}{' on stdin' if stdin else ''}"
        failed += not check(f"{way} ({len(frames)} frames)", decoder, src, frames, 0, mf4=path, stdin=stdin)
    # A temporary folder that cannot be written: an error that says so.
    gone = os.path.join(tmp, "no-such-folder")
    run, _ = decode(decoder, path, stdin=True, spill=gone)
    cases += 1
    said = run.returncode == 2 and gone in run.stderr and "set TMPDIR to a writable folder" in run.stderr
    print(f"{name} on stdin, TMPDIR missing: exit {run.returncode}, {'the folder named' if said else 'MISMATCH: ' + run.stderr[-300:]}")
    failed += not said
    return cases, failed


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("decoder")
    ap.add_argument("captures", nargs="+")
    args = ap.parse_args()
    cases = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for capture in args.captures:
            frames = candump(capture)
            base = os.path.splitext(os.path.basename(capture))[0]
            for level in (0, 1, 2):
                path = os.path.join(tmp, f"{base}-python-can-{level}.mf4")
                write_python_can(path, frames, level)
                cases += 1
                failed += not check(f"{base} python-can compression {level}", args.decoder, path, frames, 0)
            src = os.path.join(tmp, f"{base}-python-can-0.mf4")
            dst = os.path.join(tmp, f"{base}-asammdf-4.20.mf4")
            resave_asammdf(src, dst)
            cases += 1
            failed += not check(f"{base} asammdf 4.20 4 KiB fragments", args.decoder, dst, frames, 0)
            for how, path in join_asammdf(tmp, base, frames):
                cases += 1
                failed += not check(f"{base} asammdf {how} of two halves", args.decoder, path, frames, 0)
            path = os.path.join(tmp, f"{base}-fd.mf4")
            fd = write_with_fd(path, frames)
            cases += 1
            failed += not check(f"{base} python-can CAN FD frames among them", args.decoder, path, frames, 0, fd=fd)
            mixed, errors = with_events(frames)
            path = os.path.join(tmp, f"{base}-events.mf4")
            write_python_can(path, mixed, 2)
            cases += 1
            failed += not check(f"{base} python-can remote and error frames", args.decoder, path, mixed, errors)
            for name in (f"{base}-python-can-0.mf4", f"{base}-python-can-2.mf4", f"{base}-asammdf-4.20.mf4"):
                src = os.path.join(tmp, name)
                with open(src, "rb") as f, gzip.open(src + ".gz", "wb") as g:
                    g.write(f.read())
                for stdin in (False, True):
                    cases += 1
                    way = " on stdin" if stdin else ""
                    failed += not check(f"{name}.gz{way}", args.decoder, src + ".gz", frames, 0, mf4=src, stdin=stdin)
            src = os.path.join(tmp, f"{base}-python-can-0.mf4")
            cases += 1
            failed += not check(f"{base}-python-can-0.mf4 on stdin", args.decoder, src, frames, 0, stdin=True)
            n, bad = spilled(args.decoder, tmp, base, frames)
            cases += n
            failed += bad
    print(f"{cases} cases, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
