#!/usr/bin/env python3
"""scapy (and Wireshark's editcap, when installed) write the real captures
as pcap and pcapng; canopen-decode reads them.

Usage: pcap_interop.py CANOPEN_DECODE CAPTURE.log... [--editcap PATH]

Each real capture (candump -L lines) is read with python-can's
CanutilsLogReader and written with scapy's own writers, whose CAN layer
is LINKTYPE_CAN_SOCKETCAN (227): PcapWriter (pcap, microsecond times),
PcapWriter with nano=True (nanosecond times) and PcapNgWriter (pcapng).
With --editcap, Wireshark's editcap re-writes scapy's pcap as pcapng
(`editcap -F pcapng`) and scapy's pcapng as nanosecond pcap. The candump
log gzip-compressed (Python's gzip) is a case too, and so is a BLF
written by python-can's BLFWriter, plain and gzip-compressed.

Each file is decoded by `canopen-decode --json` (the format detected
from its content), and so is the candump original; the frames must be
exactly equal, in order: identifier, 29-bit flag, remote flag, DLC,
data and time to the microsecond (the BLF's to the microsecond of
BLFWriter's nanoseconds since its millisecond start). Nothing may be
reported on stderr for any file but what the original gives. Prints
"N cases, M failed" and exits 1 on any failure.
"""
import argparse
import gzip
import json
import os
import shutil
import subprocess
import sys
import tempfile

import can
from scapy.layers.can import CAN
from scapy.utils import PcapNgWriter, PcapWriter


def frames_of_log(path):
    with can.CanutilsLogReader(path) as r:
        return [m for m in r]


def scapy_packets(messages):
    out = []
    for m in messages:
        flags = 0
        if m.is_extended_id:
            flags |= 0x4  # extended
        if m.is_remote_frame:
            flags |= 0x2  # remote_transmission_request
        p = CAN(flags=flags, identifier=m.arbitration_id, length=m.dlc, data=bytes(m.data))
        # The candump time, exact to the microsecond (scapy keeps a
        # Decimal for times it is given as such).
        p.time = m.timestamp
        out.append(p)
    return out


def write_scapy(path, packets, writer, **kw):
    w = writer(path, **kw)
    for p in packets:
        w.write(p)
    w.close()


def decode(decoder, path):
    run = subprocess.run([decoder, "--json", path], capture_output=True, text=True)
    frames = []
    for line in run.stdout.splitlines():
        v = json.loads(line)
        if "id" in v:
            frames.append(
                (round(v["t"] * 1e6), v["id"], v["extended"], v["remote"], v["dlc"], (v["data"] or "").upper())
            )
    return run, frames


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("decoder")
    ap.add_argument("captures", nargs="+")
    ap.add_argument("--editcap")
    args = ap.parse_args()
    editcap = args.editcap or shutil.which("editcap")
    if not editcap:
        print("editcap (Wireshark) not found: its cases are not run")
    cases = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for capture in args.captures:
            base = os.path.basename(capture)
            want_run, want = decode(args.decoder, capture)
            messages = frames_of_log(capture)
            if want_run.returncode not in (0, 1) or len(want) != len(messages) or not want:
                print(f"{base}: the original decodes to {len(want)} of {len(messages)} frames (exit {want_run.returncode})")
                sys.exit(1)
            packets = scapy_packets(messages)
            files = []

            def case(name):
                path = os.path.join(tmp, f"{base}.{name}")
                files.append((name, path))
                return path

            us_pcap = case("scapy.pcap")
            write_scapy(us_pcap, packets, PcapWriter)
            write_scapy(case("scapy-nano.pcap"), packets, PcapWriter, nano=True)
            ng = case("scapy.pcapng")
            write_scapy(ng, packets, PcapNgWriter)
            if editcap:
                subprocess.run([editcap, "-F", "pcapng", us_pcap, case("editcap.pcapng")], check=True)
                subprocess.run([editcap, "-F", "nsecpcap", ng, case("editcap-nsec.pcap")], check=True)
            with open(capture, "rb") as f, gzip.open(case("log.gz"), "wb") as g:
                g.write(f.read())
            # BLF: python-can's writer, its times to the microsecond of
            # its nanoseconds since a start truncated to the millisecond.
            blf = case("python-can.blf")
            w = can.BLFWriter(blf)
            for m in messages:
                w.on_message_received(m)
            w.stop()
            with open(blf, "rb") as f, gzip.open(case("python-can.blf.gz"), "wb") as g:
                g.write(f.read())
            start = int(messages[0].timestamp * 1000) / 1000
            blf_want = [
                (round(start * 1e6) + (int((m.timestamp - start) * 1e9) + 500) // 1000,) + w_[1:]
                for m, w_ in zip(messages, want)
            ]
            for name, path in files:
                cases += 1
                run, got = decode(args.decoder, path)
                expected = blf_want if ".blf" in name else want
                problems = []
                if run.returncode != want_run.returncode:
                    problems.append(f"exit {run.returncode}, the original's {want_run.returncode}: {run.stderr[-300:]}")
                if run.stderr != want_run.stderr:
                    extra = [l for l in run.stderr.splitlines() if l not in want_run.stderr.splitlines()]
                    problems.append(f"stderr differs: {extra[:3]}")
                if len(got) != len(expected):
                    problems.append(f"{len(got)} frames, the original {len(expected)}")
                for i, (g, e) in enumerate(zip(got, expected)):
                    if g != e:
                        problems.append(f"frame {i}: {g} != {e}")
                        break
                status = "ok" if not problems else "FAILED"
                print(f"{base} {name}: {len(got)} frames, {status}")
                for p in problems[:5]:
                    print("   ", p)
                failed += bool(problems)
    print(f"{cases} cases, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
