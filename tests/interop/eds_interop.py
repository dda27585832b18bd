#!/usr/bin/env python3
"""EDS interop: our SDO server serving the dictionary built from an EDS or
DCF (examples/sdo_node --server --eds FILE), read and written by
python-canopen with the same file loaded by its own importer
(canopen.import_od through Network.add_node).

For every variable of the description:
- a readable one uploads to exactly the value python-canopen reads from the
  file for the same node id ($NODEID resolved): its ParameterValue (DCF),
  else its DefaultValue, encoded by python-canopen (no prefix matches);
- a writable one takes a new value (its bytes with the lowest bit flipped;
  a new string or domain) and uploads that value back, then its old one;
- a write-only one refuses the upload with 06010001h, a read-only or const
  one refuses the download with 06010002h.
Then the EDS as we write it (sdo_node --print-eds) must load in
python-canopen's importer to the same objects: names, data types, access,
PDO mapping and defaults.

The node serves a file whole or refuses it naming the objects it cannot
serve; a refused file is reported and the rest of it is compared on a copy
without those objects. Where python-canopen cannot read a file as it
stands (an empty number in [DeviceInfo]) or reads part of it otherwise
than CiA 306 (a CompactSubObj object's sub-index 0), the script says so on
a `note` line and compares the rest.

usage: eds_interop.py PATH/TO/sdo_node FILE.eds|FILE.dcf...
A file that is absent fails under CI (CI=true); elsewhere it is skipped
with a message.
"""

import configparser
import os
import re
import subprocess
import sys
import tempfile

import canopen
from canopen.objectdictionary import ODArray, ODRecord
from canopen.objectdictionary.datatypes import (
    DOMAIN, OCTET_STRING, UNICODE_STRING, VISIBLE_STRING)
from pipebus import PipeBus

NODE = 10
TEXT_TYPES = (VISIBLE_STRING, OCTET_STRING, UNICODE_STRING, DOMAIN)


class Run:
    def __init__(self, name):
        self.name = name
        self.cases = 0
        self.failures = []
        self.notes = []

    def check(self, what, ok, detail=""):
        self.cases += 1
        if not ok:
            print(f"FAIL {self.name} {what}: {detail}")
            self.failures.append(what)

    def note(self, text):
        self.notes.append(text)


def variables(od):
    for obj in od.values():
        if isinstance(obj, (ODRecord, ODArray)):
            yield from obj.values()
        else:
            yield obj


def abort_code(op):
    try:
        op()
    except canopen.SdoAbortedError as e:
        return e.code
    return None


def ini(path):
    cp = configparser.RawConfigParser(strict=False, interpolation=None)
    cp.optionxform = str
    with open(path, encoding="utf-8", errors="replace") as f:
        cp.read_file(f)
    return cp


def compact_indexes(cp):
    """Objects described by one section with CompactSubObj (CiA 306)."""
    out = set()
    for section in cp.sections():
        if re.fullmatch(r"[0-9A-Fa-f]{4}", section) and cp.has_option(section, "CompactSubObj"):
            out.add(int(section, 16))
    return out


def copy_for_python(path, run, drop=()):
    """A copy of the file python-canopen can load: [DeviceInfo] numbers
    that are empty (python-canopen's importer fails on int('')) removed,
    and the objects in `drop` left out. Returns the path to load."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().splitlines()
    out, section, changed = [], None, False
    drop_sections = {f"{i:04X}" for i in drop}
    for line in lines:
        stripped = line.strip()
        m = re.fullmatch(r"\[([^\]]+)\]", stripped)
        if m:
            section = m.group(1)
        key, _, value = stripped.partition("=")
        upper = (section or "").upper()
        if upper == "DEVICEINFO" and _ and not value.strip() and key not in ("VendorName", "ProductName", "OrderCode"):
            run.note(f"[DeviceInfo] {key} is empty: left out for python-canopen's importer")
            changed = True
            continue
        if upper[:4] in drop_sections:
            changed = True
            continue
        if upper in ("MANDATORYOBJECTS", "OPTIONALOBJECTS", "MANUFACTUREROBJECTS") and _:
            try:
                if key != "SupportedObjects" and int(value, 0) in drop:
                    continue
            except ValueError:
                pass
        out.append(line)
    if not changed:
        return path
    f = tempfile.NamedTemporaryFile("w", suffix=os.path.splitext(path)[1], delete=False)
    f.write("\n".join(out) + "\n")
    f.close()
    return f.name


def new_value(var, got):
    """A value other than `got` for a download: a fixed-size value with its
    lowest bit flipped, a string or domain of new bytes."""
    if var.data_type in TEXT_TYPES:
        return b"new value" if got != b"new value" else b"other value"
    if not got:
        return b"\x01"
    return bytes([got[0] ^ 0x01]) + got[1:]


def serve(exe, path, run):
    """Starts the node on `path`; returns (bus, objects served) or
    (None, the objects it refused) when it refuses the file."""
    probe = subprocess.run([exe, "--server", "--node-id", str(NODE), "--eds", path],
                           input="", capture_output=True, text=True)
    m = re.search(r"cannot serve \d+ object\(s\)[^:]*: (.*)$", probe.stderr, re.M)
    if probe.returncode != 0:
        if not m:
            run.check("node starts", False, probe.stderr.strip())
            return None, []
        refused = sorted({int(x.split(":")[0].rstrip("h"), 16) for x in m.group(1).split(", ")})
        return None, refused
    served = re.search(r"serving (\d+) objects", probe.stderr)
    bus = PipeBus([exe, "--server", "--node-id", str(NODE), "--eds", path])
    return bus, int(served.group(1)) if served else -1


def compare(exe, served_path, python_path, compact, run):
    bus, served = serve(exe, served_path, run)
    if bus is None:
        run.check("node serves the file", False, f"refused {served}")
        return 0
    net = canopen.Network(bus)
    net.connect()
    node = net.add_node(NODE, python_path)
    node.sdo.RESPONSE_TIMEOUT = 2.0
    try:
        for var in variables(node.object_dictionary):
            if var.index < 0x1000:
                # The data type area: python-canopen lists [DummyUsage]
                # types as variables; CiA 301 makes them mapping dummies,
                # which our dictionary does not serve.
                continue
            where = f"{var.index:04X}:{var.subindex:02X} {var.name}"
            access = var.access_type.lower()
            if var.index in compact and var.subindex == 0:
                run.note(f"{where}: python-canopen makes a CompactSubObj's sub-index 0 "
                         "rw without a value; CiA 306 gives it ro and the count: read only")
                access = "ro-compact"
            if access == "wo":
                code = abort_code(lambda: node.sdo.upload(var.index, var.subindex))
                run.check(f"{where} write-only", code == 0x06010001, f"abort {code}")
                continue
            try:
                got = node.sdo.upload(var.index, var.subindex)
            except canopen.SdoAbortedError as e:
                run.check(f"{where} readable", False, f"abort {e.code:08X}")
                continue
            start = var.value if var.value is not None else var.default
            if start is not None:
                try:
                    want = var.encode_raw(start)
                except (ValueError, TypeError):
                    # A hex bit pattern for a signed type ("0xFF" in an
                    # INTEGER8): we keep the bits, python-canopen cannot
                    # encode it, so there is nothing to compare.
                    run.note(f"{where}: python-canopen cannot encode its value {start!r}")
                    want = None
                if want is not None:
                    run.check(f"{where} value", got == want, f"ours {got.hex()} python {want.hex()}")
            if access == "ro-compact":
                continue
            if access in ("rw", "rwr", "rww"):
                new = new_value(var, got)
                code = abort_code(lambda: node.sdo.download(var.index, var.subindex, new))
                run.check(f"{where} writable", code is None, f"abort {code and hex(code)}")
                if code is None:
                    back = node.sdo.upload(var.index, var.subindex)
                    run.check(f"{where} reads back", back == new, f"wrote {new.hex()} read {back.hex()}")
                    node.sdo.download(var.index, var.subindex, got)
            else:
                code = abort_code(lambda: node.sdo.download(var.index, var.subindex, got))
                run.check(f"{where} not writable", code == 0x06010002, f"abort {code and hex(code)}")
    finally:
        net.disconnect()
    return served


def written_eds(exe, eds, python_path, compact, run):
    written = subprocess.run([exe, "--print-eds", eds], check=True, capture_output=True).stdout
    with tempfile.NamedTemporaryFile(suffix=".eds") as f:
        f.write(written)
        f.flush()
        ours = canopen.import_od(copy_for_python(f.name, Run("copy")), NODE)
    theirs = canopen.import_od(python_path, NODE)
    described = lambda od: {
        (v.index, v.subindex): (v.name, v.data_type, v.access_type.lower(), v.pdo_mappable,
                                v.default, v.value)
        for v in variables(od) if v.index not in compact
    }
    if compact:
        run.note("CompactSubObj objects " + ", ".join(f"{i:04X}h" for i in sorted(compact))
                 + ": python-canopen expands them otherwise than CiA 306; left out of the written-EDS check")
    a, b = described(ours), described(theirs)
    run.check("written EDS has the same variables", a.keys() == b.keys(), f"{set(a) ^ set(b)}")
    for key in sorted(a.keys() & b.keys()):
        run.check(f"written EDS {key[0]:04X}:{key[1]:02X}", a[key] == b[key],
                  f"ours {a[key]} original {b[key]}")


def one(exe, eds):
    run = Run(os.path.basename(eds))
    if not os.path.exists(eds):
        if os.environ.get("CI") == "true":
            print(f"FAIL {eds} is absent (CI=true: the shared EDS files must be there)")
            return 1
        print(f"skipped: {eds} is absent")
        return 0
    compact = compact_indexes(ini(eds))
    bus, refused = serve(exe, eds, run)
    served_path = eds
    if bus is None and refused:
        print(f"{run.name}: refused by the node, which names "
              + ", ".join(f"{i:04X}h" for i in refused)
              + " (a data type it cannot encode); the rest compared on a copy without them")
        run.check("refusal names the objects", True)
        served_path = copy_for_python(eds, Run("copy"), drop=set(refused))
    elif bus is not None:
        bus.shutdown()
    python_path = copy_for_python(served_path, run)
    served = compare(exe, served_path, python_path, compact, run)
    written_eds(exe, served_path, python_path, compact, run)
    for n in dict.fromkeys(run.notes):
        print(f"note {run.name} {n}")
    print(f"{run.cases - len(run.failures)}/{run.cases} EDS interop checks passed "
          f"({eds}: {served} objects served)")
    return 1 if run.failures else 0


def main(exe, files):
    status = 0
    for eds in files:
        status |= one(exe, eds)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2:]))
