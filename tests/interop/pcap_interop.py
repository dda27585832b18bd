#!/usr/bin/env python3
"""scapy (and Wireshark's editcap, when installed) write the real captures
as pcap and pcapng; canopen-decode reads them.

Usage: pcap_interop.py CANOPEN_DECODE CAPTURE.log... [--editcap PATH]

Each real capture (candump -L lines) is read with python-can's
CanutilsLogReader and written with scapy's own writers, whose CAN layer
is LINKTYPE_CAN_SOCKETCAN (227): PcapWriter (pcap, microsecond times),
PcapWriter with nano=True (nanosecond times) and PcapNgWriter (pcapng).
With --editcap, Wireshark's editcap re-writes scapy's pcap as pcapng
(`editcap -F pcapng`) and scapy's pcapng as nanosecond pcap, and its
mergecap merges two pcaps of the capture (node 10's frames in
microseconds, the others' in nanoseconds) into one pcapng of two
interfaces (the second with if_tsresol 9). Where tcpdump is installed,
libpcap re-writes scapy's pcapng as pcap (`tcpdump -r -w`) and scapy's
pcap as nanosecond pcap (`--time-stamp-precision=nano`). scapy's pcapng
and nanosecond pcap gzip-compressed are cases, and so is scapy's pcapng with a CAN FD
frame (scapy's CANFD) after every 40th frame: the same classic frames,
each FD frame reported on stderr (`packet N: CanFd not decoded`) and
counted. The candump log gzip-compressed (Python's gzip) is a case too,
and so is a BLF written by python-can's BLFWriter, plain and
gzip-compressed.

Where Wireshark's tshark is installed it is the reference reader of
every pcap and pcapng case (its frame times and raw SocketCAN bytes must
give the same frames), and of one more file this script writes itself:
a pcapng of two interfaces with if_tsresol 2^-20 s and 10^-8 s and an
if_tsoffset, whose times the decoder gives to tshark's nearest
microsecond.

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
import logging
import os
import shutil
import struct
import subprocess
import sys
import tempfile
from decimal import Decimal

import can
from scapy.layers.can import CAN, CANFD
from scapy.utils import PcapNgWriter, PcapWriter

# scapy warns of "inconsistent linktypes" when a CANFD packet follows CAN
# ones: both are LINKTYPE_CAN_SOCKETCAN, which the file keeps.
logging.getLogger("scapy.runtime").setLevel(logging.ERROR)


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


def with_fd(packets):
    """The packets with a 12-byte CAN FD frame (BRS) after every 40th."""
    out, fd = [], 0
    for i, p in enumerate(packets):
        out.append(p)
        if i % 40 == 7:
            f = CANFD(identifier=0x123, length=12, fd_flags=0x01, data=bytes(range(12)))
            f.time = p.time
            out.append(f)
            fd += 1
    return out, fd


def odd_resolution_pcapng(path, messages):
    """A pcapng (little-endian) of two SocketCAN interfaces: even frames on
    interface 0 in 2^-20 s units since an if_tsoffset of 1 700 000 000 s,
    odd frames on interface 1 in 10^-8 s units."""

    def block(kind, body):
        body += b"\0" * (-len(body) % 4)
        n = len(body) + 12
        return struct.pack("<II", kind, n) + body + struct.pack("<I", n)

    def idb(options):
        body = struct.pack("<HHI", 227, 0, 0)
        for code, value in options:
            body += struct.pack("<HH", code, len(value)) + value + b"\0" * (-len(value) % 4)
        return block(1, body + struct.pack("<HH", 0, 0))

    offset = 1_700_000_000
    out = block(0x0A0D0D0A, struct.pack("<IHHq", 0x1A2B3C4D, 1, 0, -1))
    out += idb([(9, bytes([0x80 | 20])), (14, struct.pack("<q", offset))])
    out += idb([(9, bytes([8]))])
    for i, m in enumerate(messages):
        us = round(Decimal(str(m.timestamp)) * 1000000)
        if i % 2 == 0:
            units = ((us - offset * 1000000) << 20) // 1000000
        else:
            units = us * 100
        word = m.arbitration_id | (0x80000000 if m.is_extended_id else 0) | (0x40000000 if m.is_remote_frame else 0)
        data = bytes(m.data) if not m.is_remote_frame else b""
        frame = struct.pack(">I", word) + bytes([m.dlc, 0, 0, 0]) + data.ljust(8, b"\0")
        body = struct.pack("<IIIII", i % 2, units >> 32, units & 0xFFFFFFFF, len(frame), len(frame)) + frame
        out += block(6, body)
    with open(path, "wb") as f:
        f.write(out)


def tshark_frames(tshark, path):
    """tshark's reading of a capture: (ns, id, extended, remote, dlc, data)
    of each classic frame from its frame time and raw SocketCAN bytes."""
    run = subprocess.run(
        [tshark, "-r", path, "-T", "json", "-x", "--disable-protocol", "can"],
        capture_output=True,
        text=True,
        check=True,
    )
    frames = []
    for packet in json.loads(run.stdout):
        layers = packet["_source"]["layers"]
        raw = bytes.fromhex(layers["frame_raw"][0])
        word, dlc, flags = struct.unpack(">IBB", raw[:6])
        if len(raw) > 16 or flags & 0x04 or word & 0x20000000:
            continue  # CAN FD or an error frame
        ns = int(Decimal(layers["frame"]["frame.time_epoch"]) * 1000000000)
        extended, remote = bool(word & 0x80000000), bool(word & 0x40000000)
        ident = word & (0x1FFFFFFF if extended else 0x7FF)
        data = "" if remote else raw[8 : 8 + dlc].hex().upper()
        frames.append((ns, ident, extended, remote, dlc, data))
    return frames


def same_as_tshark(got, reference):
    """The decoder's frames are tshark's, each time its nearest microsecond."""
    if len(got) != len(reference):
        return f"{len(got)} frames, tshark {len(reference)}"
    for i, (g, r) in enumerate(zip(got, reference)):
        if g[1:] != r[1:] or abs(g[0] * 1000 - r[0]) > 500:
            return f"frame {i}: {g} != tshark's {r}"
    return None


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
    mergecap = shutil.which("mergecap")
    tcpdump = shutil.which("tcpdump")
    if not tcpdump:
        print("tcpdump not found: its cases are not run")
    tshark = shutil.which("tshark")
    if not tshark:
        print("tshark (Wireshark) not found: it is not a reference reader here")
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
            if mergecap:
                node10 = os.path.join(tmp, f"{base}.node10.pcap")
                others = os.path.join(tmp, f"{base}.others.pcap")
                write_scapy(node10, [p for p in packets if p.identifier & 0x7F == 10], PcapWriter)
                write_scapy(others, [p for p in packets if p.identifier & 0x7F != 10], PcapWriter, nano=True)
                merged = case("mergecap-two-interfaces.pcapng")
                subprocess.run([mergecap, "-F", "pcapng", "-w", merged, node10, others], check=True)
            if tcpdump:
                for name, source, nano in (("tcpdump.pcap", ng, []), ("tcpdump-nano.pcap", us_pcap, ["--time-stamp-precision=nano"])):
                    subprocess.run([tcpdump, "-r", source, "-w", case(name), *nano], check=True, capture_output=True)
            for name in ("scapy.pcapng", "scapy-nano.pcap"):
                src = os.path.join(tmp, f"{base}.{name}")
                with open(src, "rb") as f, gzip.open(case(name + ".gz"), "wb") as g:
                    g.write(f.read())
            fd_packets, fd_count = with_fd(packets)
            write_scapy(case("scapy-fd.pcapng"), fd_packets, PcapNgWriter)
            if tshark:
                odd_resolution_pcapng(case("odd-resolution.pcapng"), messages)
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
                stderr = run.stderr
                if name == "scapy-fd.pcapng":
                    lines = stderr.splitlines()
                    fd_lines = [l for l in lines if l.endswith(": CanFd not decoded: link type 227")]
                    total = f"canopen-decode: read, not decoded: {fd_count} CAN FD frame(s), 0 error frame(s), 0 other event(s)"
                    if len(fd_lines) != fd_count or total not in lines:
                        problems.append(f"{len(fd_lines)} FD frames reported of {fd_count}, total line {total in lines}")
                    stderr = "".join(l + "\n" for l in lines if l not in fd_lines and l != total)
                if stderr != want_run.stderr:
                    extra = [l for l in stderr.splitlines() if l not in want_run.stderr.splitlines()]
                    problems.append(f"stderr differs: {extra[:3]}")
                if name != "odd-resolution.pcapng":
                    if len(got) != len(expected):
                        problems.append(f"{len(got)} frames, the original {len(expected)}")
                    for i, (g, e) in enumerate(zip(got, expected)):
                        if g != e:
                            problems.append(f"frame {i}: {g} != {e}")
                            break
                if tshark and ".pcap" in name and not name.endswith(".gz"):
                    problem = same_as_tshark(got, tshark_frames(tshark, path))
                    if problem:
                        problems.append(problem)
                status = "ok" if not problems else "FAILED"
                print(f"{base} {name}: {len(got)} frames, {status}")
                for p in problems[:5]:
                    print("   ", p)
                failed += bool(problems)
    print(f"{cases} cases, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
