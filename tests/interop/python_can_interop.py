#!/usr/bin/env python3
"""python-can as the reference for the trace formats, both ways.

A. python-can writes, canopen-decode reads. One random frame set (fixed
   seed, `--seed N`; `--frames N`, default 300): standard and extended
   identifiers (the extremes 0, 7FFh, 1FFFFFFFh and extended identifiers
   below 800h among them), data frames of DLC 0-8, remote frames of DLC
   0-8, received and transmitted (`is_rx`), channels 0 and 1, strictly
   increasing times on a whole-microsecond grid with gaps from 1 us to
   3 s. Written with python-can's own writers: `ASCWriter`, `TRCWriter` in
   every file version it writes (found by trying each `TRCFileVersion`),
   `CSVWriter`, `CanutilsLogWriter` and `BLFWriter` (zlib, and stored with
   containers of 1 KiB, so objects cross containers). `canopen-decode
   --json FILE` (detected) and `--json --format F FILE` (named) give the
   same lines, and they are the frames written, in order: identifier,
   extended, remote, DLC, data, direction (`rxtx`) where the format carries
   it (absent where it does not), and the time to the format's resolution:
   exact microseconds for ASC, `.trc` 2.1, CSV, candump and BLF, 1 ms for
   `.trc` 1.0 (written rounded to the millisecond: within 500 us). Times
   are compared from the first frame where the format stores times since
   a start (ASC, `.trc`, BLF) and as UNIX times where it stores those (CSV,
   candump, BLF's header start plus offset, `.trc` 2.1's `$STARTTIME` plus
   offset).

B. We write, python-can reads. The candump log lines our programs write
   (tests/data/virtual-session.log, recorded from the virtual charger and
   battery module; the session logs of `examples/charge_session`; the
   stdout of `examples/battery_module` started and run for a second)
   read by python-can's `CanutilsLogReader` give the frames and times
   `canopen-decode --json` gives for the same file.

Tolerances for what python-can's writers do not carry (python-can 4.6;
each one counted and printed, none hides a frame):
- `TRCWriter` skips remote frames ("Logging remote frames is not
  implemented"): the `.trc` files hold the data frames only.
- `CanutilsLogWriter` writes a remote frame as `ID#R` without its DLC
  (candump `-L` writes `ID#R5`): python-can's remote frames read back with
  DLC 0.
- `.trc` 1.0 and CSV carry no direction.

usage: python_can_interop.py PATH/TO/canopen-decode [--seed N] [--frames N]
       [--charge-session PATH/TO/charge_session] [--battery-module PATH/TO/battery_module]
       [--keep DIR] [LOG...]
LOG: more candump logs of ours for part B (tests/data/virtual-session.log
is always read).
"""

import argparse
import json
import logging
import os
import random
import re
import subprocess
import sys
import tempfile
from decimal import Decimal

import can
from can.io.trc import TRCFileVersion

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SESSION = os.path.join(REPO, "tests", "data", "virtual-session.log")
# Not on a millisecond: BLF's header start is whole milliseconds.
START_US = 1_756_955_653_123_457
FAILS = []


def fail(what):
    FAILS.append(what)
    print("FAIL", what)


# ---------------------------------------------------------------- frame set


class Frame:
    """One frame of the set, its time in whole microseconds."""

    def __init__(self, t_us, ident, extended, remote, dlc, data, is_rx, channel):
        self.t_us = t_us
        self.ident = ident
        self.extended = extended
        self.remote = remote
        self.dlc = dlc
        self.data = data
        self.is_rx = is_rx
        self.channel = channel

    def message(self):
        return can.Message(
            timestamp=self.t_us / 1e6,
            arbitration_id=self.ident,
            is_extended_id=self.extended,
            is_remote_frame=self.remote,
            dlc=self.dlc,
            data=None if self.remote else self.data,
            is_rx=self.is_rx,
            channel=self.channel,
        )


def frame_set(seed, count):
    rng = random.Random(seed)
    # The extremes first, then random frames.
    planted = [
        (0x000, False, False, 0),
        (0x7FF, False, False, 8),
        (0x1FFFFFFF, True, False, 8),
        (0x00000005, True, False, 3),
        (0x7FF, True, True, 0),
        (0x123, False, True, 8),
        (0x10000000, True, True, 5),
    ]
    frames = []
    t = START_US
    for i in range(count):
        if i:
            # Gaps of a few us, tens to hundreds of us, ms, seconds.
            lo, hi = rng.choice([(1, 9), (10, 999), (1000, 999_999), (1_000_000, 3_000_000)])
            t += rng.randint(lo, hi)
        if i < len(planted):
            ident, extended, remote, dlc = planted[i]
        else:
            extended = rng.random() < 0.35
            ident = rng.randrange(1 << 29 if extended else 1 << 11)
            if extended and rng.random() < 0.1:
                ident = rng.randrange(0x800)
            remote = rng.random() < 0.15
            dlc = rng.randint(0, 8)
        data = b"" if remote else bytes(rng.randrange(256) for _ in range(dlc))
        frames.append(Frame(t, ident, extended, remote, dlc, data, rng.random() < 0.5, rng.randint(0, 1)))
    kinds = {(f.extended, f.remote, f.is_rx) for f in frames}
    if len(kinds) != 8 or {f.dlc for f in frames if f.remote} != set(range(9)):
        raise SystemExit(f"seed {seed}: the frame set misses a kind of frame; use more frames")
    return frames


# ---------------------------------------------------------------- writers


def trc_versions():
    """The `.trc` versions python-can's TRCWriter writes (it raises
    NotImplementedError for the others)."""
    versions = []
    probe = Frame(START_US, 0x123, False, False, 1, b"\x01", True, 0).message()
    with tempfile.TemporaryDirectory() as d:
        for v in TRCFileVersion:
            if v == TRCFileVersion.UNKNOWN:
                continue
            w = can.TRCWriter(os.path.join(d, f"{v.name}.trc"))
            w.file_version = v
            try:
                w.on_message_received(probe)
                versions.append(v)
            except NotImplementedError:
                pass
            finally:
                w.stop()
    return versions


def write(writer, frames):
    for f in frames:
        writer.on_message_received(f.message())
    writer.stop()


def trc_writer(version):
    def make(path):
        w = can.TRCWriter(path)
        w.file_version = version
        return w

    return make


class Case:
    """One file python-can writes: how, what of the frames it keeps, and
    what canopen-decode should give back."""

    def __init__(self, name, suffix, fmt, make, **kw):
        self.name = name
        self.suffix = suffix
        self.fmt = fmt
        self.make = make
        self.direction = kw.get("direction", True)
        self.keeps_remote = kw.get("keeps_remote", True)
        self.remote_dlc = kw.get("remote_dlc", True)
        self.resolution_us = kw.get("resolution_us", 1)
        # "unix": the times are UNIX times; "start": since the first frame.
        self.clock = kw.get("clock", "start")
        # Also UNIX times, after the header's start (BLF, .trc 2.x), to
        # within this many us.
        self.unix_too = kw.get("unix_too", False)
        self.unix_tolerance_us = kw.get("unix_tolerance_us", 0)


def cases():
    out = [Case("asc", ".asc", "asc", can.ASCWriter)]
    versions = trc_versions()
    print("python-can's TRCWriter writes .trc versions:", ", ".join(v.name for v in versions))
    if TRCFileVersion.V1_0 not in versions or TRCFileVersion.V2_1 not in versions:
        fail(f"TRCWriter writes {versions}; expected at least V1_0 and V2_1")
    for v in versions:
        major = v.value // 100
        out.append(
            Case(
                f"trc {v.value // 100}.{v.value % 100}",
                f"-{v.name}.trc",
                "trc",
                trc_writer(v),
                keeps_remote=False,
                # 1.0 has no Rx/Tx column; its time is whole ms (`{time:7.0f}`).
                direction=v >= TRCFileVersion.V1_1,
                resolution_us=1000 if v == TRCFileVersion.V1_0 else 1,
                unix_too=major >= 2,
                # $STARTTIME is a float of days: ~0.6 us apart in 2025.
                unix_tolerance_us=1,
            )
        )
    out += [
        Case("csv", ".csv", "csv", can.CSVWriter, direction=False, clock="unix"),
        Case("candump", ".log", "candump", can.CanutilsLogWriter, remote_dlc=False, clock="unix"),
        Case("blf zlib", ".blf", "blf", can.BLFWriter, unix_too=True),
        Case(
            "blf stored, 1 KiB containers",
            "-stored.blf",
            "blf",
            lambda p: can.BLFWriter(p, compression_level=0, max_container_size=1024),
            unix_too=True,
        ),
    ]
    return out


# ---------------------------------------------------------------- the decoder


def decode_json(decoder, args):
    out = subprocess.run([decoder, "--json", *args], capture_output=True, text=True, check=False)
    objects = [json.loads(line, parse_float=Decimal) for line in out.stdout.splitlines()]
    return out, [o for o in objects if "id" in o and o.get("kind") != "sdo_transfer"]


# What canopen-decode says on stderr of a trace read whole: the random
# frames are no CANopen messages (a frame that does not decode as one is
# a bad line, counted at the end: exit status 1), ASC's `Start of
# measurement` is an event.
NOT_DECODED = re.compile(r"(line|object) \d+: frame \S+ does not decode: .*")
NOT_TRACE_ERRORS = re.compile(
    r"line \d+: Event not decoded: +[0-9.]+ Start of measurement"
    r"|canopen-decode: read, not decoded: 0 CAN FD frame\(s\), 0 error frame\(s\), 1 other event\(s\)"
)


def trace_errors(out):
    """What canopen-decode said about the trace itself (a line or object
    it could not read), or an exit status that is not 0 or 1 (1 only with
    the count of the frames that are no CANopen message)."""
    lines = out.stderr.splitlines()
    not_decoded = sum(bool(NOT_DECODED.fullmatch(line)) for line in lines)
    count = f"canopen-decode: {not_decoded} bad line(s)"
    said = [
        line
        for line in lines
        if not (NOT_DECODED.fullmatch(line) or NOT_TRACE_ERRORS.fullmatch(line) or line == count)
    ]
    if said or out.returncode != (1 if not_decoded else 0):
        return [f"canopen-decode exit {out.returncode}: " + " | ".join(said[:5])]
    return []


def micros(t):
    return int(t * 1_000_000)


def compare(case, frames, got):
    """Mismatches between the frames written and the JSON read back."""
    bad = []
    want = [f for f in frames if case.keeps_remote or not f.remote]
    if len(got) != len(want):
        bad.append(f"{len(got)} frames read, {len(want)} written")
    t0_want, t0_got = want[0].t_us, micros(got[0]["t"]) if got else 0
    for i, (w, g) in enumerate(zip(want, got)):
        what = []
        dlc = w.dlc if (not w.remote or case.remote_dlc) else 0
        expect = {
            "id": w.ident,
            "extended": w.extended,
            "remote": w.remote,
            "dlc": dlc,
            "data": w.data.hex(),
            "rxtx": ("rx" if w.is_rx else "tx") if case.direction else None,
        }
        for key, value in expect.items():
            if g.get(key) != value:
                what.append(f"{key} {g.get(key)!r} (wrote {value!r})")
        t = micros(g["t"])
        if case.clock == "unix":
            if t != w.t_us:
                what.append(f"t {t} us (wrote {w.t_us})")
        else:
            rel, rel_want = t - t0_got, w.t_us - t0_want
            off = abs(rel - rel_want)
            if off * 2 > case.resolution_us or rel % case.resolution_us:
                what.append(f"t {rel} us after the first frame (wrote {rel_want}, resolution {case.resolution_us} us)")
            if case.unix_too and abs(t - w.t_us) > case.unix_tolerance_us:
                what.append(f"UNIX t {t} us (wrote {w.t_us}, within {case.unix_tolerance_us})")
        if what:
            bad.append(f"frame {i}: " + "; ".join(what))
    return bad


def part_a(decoder, frames, workdir):
    print(
        f"A. {len(frames)} frames: "
        f"{sum(f.extended for f in frames)} extended, {sum(f.remote for f in frames)} remote, "
        f"{sum(not f.is_rx for f in frames)} transmitted, "
        f"{(frames[-1].t_us - frames[0].t_us) / 1e6:.6f} s"
    )
    logging.getLogger("can.io.trc").setLevel(logging.ERROR)
    for case in cases():
        path = os.path.join(workdir, "python-can" + case.suffix)
        write(case.make(path), frames)
        detected, got = decode_json(decoder, [path])
        named, got_named = decode_json(decoder, ["--format", case.fmt, path])
        bad = []
        for o in (detected, named):
            bad += trace_errors(o)
        if detected.stdout != named.stdout:
            bad.append("--format " + case.fmt + " gives other lines than the detected format")
        bad += compare(case, frames, got)
        kept = sum(case.keeps_remote or not f.remote for f in frames)
        print(f"  {case.name:<30} {len(got):>4} frames read of {kept} written, {len(bad)} mismatches")
        for b in bad[:10]:
            fail(f"{case.name}: {b}")


# ---------------------------------------------------------------- part B


def part_b(decoder, logs):
    print(f"B. {len(logs)} candump logs of ours read by python-can's CanutilsLogReader")
    for name, path in logs:
        out, got = decode_json(decoder, [path])
        bad = []
        if out.returncode != 0:
            bad.append(f"canopen-decode exit {out.returncode}: {out.stderr.strip()[:400]}")
        theirs = list(can.CanutilsLogReader(path))
        if len(theirs) != len(got):
            bad.append(f"python-can reads {len(theirs)} frames, canopen-decode {len(got)}")
        for i, (m, g) in enumerate(zip(theirs, got)):
            mine = (micros(g["t"]), g["id"], g["extended"], g["remote"], g["dlc"], g["data"], g.get("rxtx"))
            # python-can says is_rx True of a line without the R / T flag.
            rxtx = None if g.get("rxtx") is None and m.is_rx else ("rx" if m.is_rx else "tx")
            t = int(Decimal(repr(m.timestamp)) * 1_000_000)
            data = "" if m.is_remote_frame else bytes(m.data).hex()
            theirs_ = (t, m.arbitration_id, m.is_extended_id, m.is_remote_frame, m.dlc, data, rxtx)
            if mine != theirs_:
                bad.append(f"frame {i}: canopen-decode {mine}, python-can {theirs_}")
        print(f"  {name:<40} {len(theirs):>7} frames, {len(bad)} mismatches")
        for b in bad[:10]:
            fail(f"{name}: {b}")


def our_logs(args, workdir):
    logs = [("tests/data/virtual-session.log", SESSION)]
    logs += [(os.path.basename(p), p) for p in args.logs]
    if args.charge_session:
        for scenario in ("bms-lost-during", "communication-restored"):
            path = os.path.join(workdir, f"{scenario}.log")
            subprocess.run(
                [args.charge_session, "--scenario", scenario, "--log", path],
                check=True,
                stdout=subprocess.DEVNULL,
            )
            logs.append((f"charge_session --scenario {scenario}", path))
    if args.battery_module:
        path = os.path.join(workdir, "battery_module.log")
        with open(path, "w") as out:
            # NMT start all, then a second of TPDOs and heartbeats.
            subprocess.run(
                [args.battery_module, "--node-id", "1", "--linger-ms", "1000"],
                input="(0.000000) can0 000#0100\n",
                text=True,
                stdout=out,
                stderr=subprocess.DEVNULL,
                check=True,
                timeout=30,
            )
        logs.append(("battery_module stdout", path))
    return logs


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("decoder")
    p.add_argument("--seed", type=int, default=418)
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--charge-session")
    p.add_argument("--battery-module")
    p.add_argument("--keep", help="write the files here and keep them")
    p.add_argument("logs", nargs="*")
    args = p.parse_args()
    print(f"python-can {can.__version__}, seed {args.seed}")
    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.keep or tmp
        os.makedirs(workdir, exist_ok=True)
        part_a(args.decoder, frame_set(args.seed, args.frames), workdir)
        part_b(args.decoder, our_logs(args, workdir))
    if FAILS:
        print(f"{len(FAILS)} failure(s)")
        sys.exit(1)
    print("all python-can trace checks passed")


if __name__ == "__main__":
    main()
