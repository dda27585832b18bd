#!/usr/bin/env python3
"""python-canopen's own SDO test transcripts, decoded by canopen-decode.

Usage: sdo_transcripts.py CANOPEN_DECODE [--source DIR]

python-canopen tests its SDO client against hand-written transcripts: each
test of its test/test_sdo.py lists the frames the client must send and the
server's answers (expedited, segmented and block transfers in both
directions, short frames from real servers, a retransmitted block, an
abort, every data type). Its source distribution ships those tests; this
script fetches the distribution of the installed python-canopen version
with pip (or reads an unpacked one given with --source), runs the tests
that exchange SDO frames with python-canopen itself, and records each
test's traffic as it happens: the frames the client sent, the frames the
test fed back, and what python-canopen's upload() and download() returned
or raised.

Each recorded transcript goes to `canopen-decode --json` as candump lines
(with the EDS file the test described node 2 by, so objects have their
types). A transcript passes when the decoder reassembles every transfer
python-canopen made, in order:

- a transfer python-canopen completed is "complete" in the decoder, with
  the bytes python-canopen's upload() returned or download() sent (for an
  expedited upload that does not indicate its size, python-canopen keeps
  the object's size from the EDS: the decoder's value is the same number);
- a transfer that ended in an abort frame is "aborted" with that frame's
  abort code;
- nothing else is reported as a transfer.

Prints one line per transcript and "N of M transcripts" and exits 1 when
any fails (or when no transcript was found: an empty run is an error).
"""
import argparse
import glob
import importlib
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import unittest

import logging

import canopen
from canopen.sdo.client import SdoClient

ABORT = 0x80


def fetch_source(workdir):
    """The unpacked source distribution of the installed python-canopen."""
    version = canopen.__version__
    subprocess.run(
        [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps",
         "--no-binary", ":all:", "--disable-pip-version-check",
         "-d", workdir, f"canopen=={version}"],
        check=True)
    archives = glob.glob(os.path.join(workdir, "canopen-*.tar.gz"))
    if not archives:
        sys.exit(f"pip fetched no source distribution of canopen {version}")
    with tarfile.open(archives[0]) as tar:
        tar.extractall(workdir, filter="data")
    roots = [d for d in glob.glob(os.path.join(workdir, "canopen-*")) if os.path.isdir(d)]
    if not roots:
        sys.exit(f"the canopen {version} source distribution did not unpack")
    return roots[0]


class Recorder:
    """The traffic and the client's results of the running test."""

    def __init__(self):
        self.frames = []
        self.results = []
        self.eds = None

    def start(self):
        self.frames = []
        self.results = []
        self.eds = None


def instrument(recorder, test_class):
    """Wraps the test class's send and the client calls to record them."""
    send = test_class._send_message
    setup = test_class.setUp

    def recording_send(self, can_id, data, remote=False):
        recorder.frames.append((can_id, bytes(data)))
        return send(self, can_id, data, remote)

    def recording_setup(self):
        setup(self)
        notify = self.network.notify

        def recording_notify(can_id, data, timestamp):
            recorder.frames.append((can_id, bytes(data)))
            return notify(can_id, data, timestamp)

        self.network.notify = recording_notify

    test_class._send_message = recording_send
    test_class.setUp = recording_setup


def instrument_network(recorder):
    """Records the EDS file the test's node 2 is described by."""
    add_node = canopen.Network.add_node

    def recording_add_node(self, node, object_dictionary=None, *a, **kw):
        if isinstance(object_dictionary, (str, os.PathLike)):
            recorder.eds = os.fspath(object_dictionary)
        return add_node(self, node, object_dictionary, *a, **kw)

    canopen.Network.add_node = recording_add_node


def instrument_client(recorder):
    upload = SdoClient.upload
    download = SdoClient.download

    def recording_upload(self, index, subindex):
        try:
            data = upload(self, index, subindex)
        except canopen.SdoAbortedError as e:
            recorder.results.append(("upload", index, subindex, None, e.code))
            raise
        recorder.results.append(("upload", index, subindex, bytes(data), None))
        return data

    def recording_download(self, index, subindex, data, force_segment=False):
        try:
            r = download(self, index, subindex, data, force_segment)
        except canopen.SdoAbortedError as e:
            recorder.results.append(("download", index, subindex, None, e.code))
            raise
        recorder.results.append(("download", index, subindex, bytes(data), None))
        return r

    SdoClient.upload = recording_upload
    SdoClient.download = recording_download


def candump(frames):
    lines = []
    for n, (can_id, data) in enumerate(frames):
        lines.append(f"({n / 1000:.6f}) can0 {can_id:03X}#{data.hex().upper()}")
    return "\n".join(lines) + "\n"


def transfers(decode, eds, frames):
    out = subprocess.run(
        [decode, "--json", "--eds", f"2={eds}", "-"],
        input=candump(frames), capture_output=True, text=True, timeout=60)
    if out.returncode not in (0,):
        raise RuntimeError(f"canopen-decode exited {out.returncode}: {out.stderr.strip()}")
    events = [json.loads(line) for line in out.stdout.splitlines() if line.strip()]
    return [e for e in events if e.get("kind") == "sdo_transfer"]


def abort_codes(frames):
    """The abort codes of the abort frames in the transcript, in order."""
    return [int.from_bytes(d[4:8], "little") for _, d in frames
            if len(d) >= 8 and d[0] == ABORT]


def same_value(ours, expected):
    """An expedited upload without a size: python-canopen keeps the EDS
    object's size; the decoder's bytes are the four the frame carries."""
    raw = bytes.fromhex(ours.get("bytes") or "")
    if raw == expected:
        return True
    return (ours.get("direction") == "upload" and ours.get("size_indicated") is False
            and raw.startswith(expected) and not any(raw[len(expected):]))


def check(name, frames, results, found):
    """Problems with the decoder's transfers against python-canopen's."""
    problems = []
    aborts = abort_codes(frames)
    if aborts:
        # Every abort frame ends one transfer as aborted, with its code.
        got = [(t.get("abort") or {}).get("code") for t in found if t.get("status") == "aborted"]
        if got != aborts:
            problems.append(f"aborts {got} in the decoder, {aborts} on the bus")
    done = [t for t in found if t.get("status") != "aborted"]
    completed = [r for r in results if r[4] is None]
    for t in done:
        if t.get("status") != "complete":
            problems.append(f"{t.get('index'):04X}h:{t.get('sub')} {t.get('status')}: {t.get('text')}")
    if results:
        # The transfers python-canopen completed, with their bytes, in order.
        mine = [(t.get("direction"), t.get("index"), t.get("sub")) for t in done]
        theirs = [(r[0], r[1], r[2]) for r in completed]
        if mine != theirs:
            problems.append(f"transfers {mine} in the decoder, {theirs} in python-canopen")
        else:
            for t, r in zip(done, completed):
                if not same_value(t, r[3]):
                    problems.append(f"{r[1]:04X}h:{r[2]} bytes {t.get('bytes')} in the decoder, "
                                    f"{r[3].hex()} in python-canopen")
    elif not found:
        problems.append("no transfer decoded")
    return problems


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("decode")
    ap.add_argument("--source", help="an unpacked python-canopen source distribution")
    args = ap.parse_args()
    decode = os.path.abspath(args.decode)
    # python-canopen warns about the data types its test EDS files use on
    # purpose; its log is not this script's output.
    logging.getLogger("canopen").setLevel(logging.ERROR)

    with tempfile.TemporaryDirectory() as tmp:
        root = args.source or fetch_source(tmp)
        sys.path.insert(0, root)
        module = importlib.import_module("test.test_sdo")
        recorder = Recorder()
        instrument_network(recorder)
        instrument_client(recorder)
        classes = [c for c in vars(module).values()
                   if isinstance(c, type) and issubclass(c, unittest.TestCase)
                   and hasattr(c, "_send_message")]
        for c in classes:
            instrument(recorder, c)

        cases = []
        loader = unittest.TestLoader()
        for c in classes:
            for test in loader.loadTestsFromTestCase(c):
                recorder.start()
                result = unittest.TestResult()
                test.run(result)
                if not result.wasSuccessful():
                    # python-canopen's own test fails against itself: not
                    # a transcript of what it does.
                    trouble = (result.errors + result.failures)[0][1].strip().splitlines()[-1]
                    print(f"skip {test.id()}: python-canopen's own test fails ({trouble})")
                    continue
                if not recorder.frames:
                    continue
                if recorder.eds is None:
                    sys.exit(f"{test.id()}: its node has no EDS file this script can give the decoder")
                cases.append((test.id().split(".", 2)[-1], recorder.eds, list(recorder.frames),
                              list(recorder.results)))

        failed = 0
        for name, eds, frames, results in cases:
            try:
                problems = check(name, frames, results, transfers(decode, eds, frames))
            except (RuntimeError, subprocess.TimeoutExpired, ValueError) as e:
                problems = [str(e)]
            if problems:
                failed += 1
                print(f"FAIL {name}: " + "; ".join(problems))
            else:
                print(f"ok   {name}: {len(frames)} frames")
        print(f"{len(cases) - failed} of {len(cases)} transcripts")
        if not cases or failed:
            sys.exit(1)


if __name__ == "__main__":
    main()
