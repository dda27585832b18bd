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
  one refuses the download with 06010002h;
- one whose DataType python-canopen cannot type either (above 001Bh, the
  last CiA 301 basic type: a complex or manufacturer type, which its
  importer warns about and reads as a DOMAIN) is refused, upload and
  download, with 06040047h.
The node serves every value it can encode and names on stderr, with the
reason, the ones it leaves out: those must be exactly the values of the
last kind (a check that fails on any other), and with --strict-eds the
node must refuse a file that has any, naming them, and serve one that has
none. Its warnings about the file must be words, each said once.
Then the EDS as we write it (sdo_node --print-eds) must load in
python-canopen's importer to the same objects: names, data types, access,
PDO mapping and defaults.

Each file ends with its figure: "N of M objects served; K refused because
..." (M: the objects python-canopen's importer reads, index 1000h and up;
an object with any value refused counts as refused, and an object whose
checks failed is in neither N nor K). Where python-canopen cannot read a
file as it stands (an empty number in [DeviceInfo]) or reads part of it
otherwise than CiA 306 (a CompactSubObj object's sub-index 0), the script
says so on a `note` line and compares the rest.

usage: eds_interop.py PATH/TO/sdo_node FILE.eds|FILE.dcf...
A file that is absent or unreadable fails under CI (CI=true); elsewhere it
is skipped with a message.
"""

import configparser
import logging
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
# The last CiA 301 basic data type (UNSIGNED64); python-canopen's importer
# types nothing above it (it warns and reads the value as a DOMAIN).
LAST_BASIC_TYPE = 0x1B
# 06040047h "general internal incompatibility in the device": the node's
# answer to a value it leaves out (eds::EdsDictionary::REFUSAL).
REFUSAL = 0x06040047
LEFT_OUT = re.compile(
    r"left out ([0-9A-F]{4})h:([0-9A-F]{2})(?: \(line \d+\))?: (.*); "
    r"SDO access refused with ([0-9A-F]{8})h$")
SERVING = re.compile(r"serving (\d+) values of (\d+) objects")
# What a Rust Debug print looks like (`SubNumberMismatch { index: .. }`).
DEBUG_STRUCT = re.compile(r"\b[A-Z][A-Za-z]+ \{ [a-z_]+: ")


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
        return ok

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


def untyped(cp, od):
    """The variables (index, sub) whose DataType, as the file writes it, is
    above the last CiA 301 basic type: python-canopen cannot type them
    (nor, without the sub1 section CANFestival writes, find what they
    stand for), and neither can the node. Read from the file's text, not
    from either side's report."""
    sections = {s.upper(): s for s in cp.sections()}

    def raw_type(var):
        names = [f"{var.index:04X}SUB{var.subindex:X}", f"{var.index:04X}"]
        for name in names:
            s = sections.get(name)
            if s and cp.has_option(s, "DataType"):
                try:
                    return int(cp.get(s, "DataType").split(";")[0].strip(), 0)
                except ValueError:
                    return None
        return None

    out = set()
    for var in variables(od):
        t = raw_type(var)
        if var.index >= 0x1000 and t is not None and t > LAST_BASIC_TYPE \
                and f"{t:X}SUB1" not in sections:
            out.add((var.index, var.subindex))
    return out


def copy_for_python(path, run):
    """A copy of the file python-canopen can load: [DeviceInfo] numbers
    that are empty (python-canopen's importer fails on int('')) removed.
    Returns the path to load."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().splitlines()
    out, section, changed = [], None, False
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
        out.append(line)
    if not changed:
        return path
    f = tempfile.NamedTemporaryFile("w", suffix=os.path.splitext(path)[1], delete=False)
    f.write("\n".join(out) + "\n")
    f.close()
    return f.name


class PythonNotes(logging.Handler):
    """python-canopen's warnings (its importer's, about a file) as notes of
    the run, while the run lasts."""

    def __init__(self, run):
        super().__init__(logging.WARNING)
        self.run = run

    def emit(self, record):
        self.run.note(f"python-canopen says: {record.getMessage()}")

    def __enter__(self):
        logging.getLogger("canopen").addHandler(self)
        return self

    def __exit__(self, *exc):
        logging.getLogger("canopen").removeHandler(self)


def new_value(var, got):
    """A value other than `got` for a download: a fixed-size value with its
    lowest bit flipped, a string or domain of new bytes."""
    if var.data_type in TEXT_TYPES:
        return b"new value" if got != b"new value" else b"other value"
    if not got:
        return b"\x01"
    return bytes([got[0] ^ 0x01]) + got[1:]


def node_stderr(exe, path, *extra):
    """The node started on `path` with no input: its exit code and stderr
    (what it says about the file before serving)."""
    probe = subprocess.run([exe, "--server", "--node-id", str(NODE), "--eds", path, *extra],
                           input="", capture_output=True, text=True)
    return probe.returncode, probe.stderr


def check_report(exe, path, refused, run):
    """What the node says about the file: its warnings in words, once each;
    the values it leaves out exactly `refused`, each with a reason and the
    refusal code; --strict-eds refuses the file when it has any. Returns
    ({(index, sub): reason}, objects the node says it serves) or None when
    it does not start."""
    code, err = node_stderr(exe, path)
    if not run.check("node starts", code == 0, err.strip()):
        return None
    lines = err.splitlines()
    warnings = [l for l in lines if ": warning: " in l]
    run.check("warnings said once each", len(warnings) == len(set(warnings)),
              [w for w in warnings if warnings.count(w) > 1])
    run.check("warnings in words, not Rust debug structs",
              not any(DEBUG_STRUCT.search(w) for w in warnings), warnings)
    left = {}
    for l in lines:
        m = LEFT_OUT.search(l)
        if m:
            left[(int(m.group(1), 16), int(m.group(2), 16))] = m.group(3)
            run.check(f"{m.group(1)}h:{m.group(2)} left out with 06040047h",
                      int(m.group(4), 16) == REFUSAL, l)
    fmt = lambda keys: ", ".join(f"{i:04X}h:{s:02X}" for i, s in sorted(keys)) or "none"
    run.check("node leaves out exactly the values python-canopen cannot type",
              set(left) == refused, f"node: {fmt(left)}; python-canopen: {fmt(refused)}")
    serving = SERVING.search(err)
    run.check("node says how many it serves", serving is not None, err.strip())
    code, err = node_stderr(exe, path, "--strict-eds")
    if refused:
        named = all(f"{i:04X}h:{s:02X}" in err for i, s in refused)
        run.check("--strict-eds refuses the file, naming what it cannot serve",
                  code == 2 and "--strict-eds" in err and named, f"exit {code}: {err.strip()}")
    else:
        run.check("--strict-eds serves a file it can serve whole", code == 0, f"exit {code}: {err.strip()}")
    return left, int(serving.group(2)) if serving else None


def compare(exe, path, python_path, compact, refused, run):
    """Every variable through python-canopen; returns {index: "served" |
    "refused" | "failed"} for the objects of index 1000h and up, and the
    set of those with a value the node does not leave out."""
    bus = PipeBus([exe, "--server", "--node-id", str(NODE), "--eds", path])
    net = canopen.Network(bus)
    net.connect()
    node = net.add_node(NODE, python_path)
    node.sdo.RESPONSE_TIMEOUT = 2.0
    status = {}
    held = set()

    def outcome(index, what):
        # An object is served when every value is; refused when any value
        # is refused as it must be; failed when any check failed.
        order = ("served", "refused", "failed")
        old = status.get(index, "served")
        status[index] = max(old, what, key=order.index)

    try:
        for var in variables(node.object_dictionary):
            if var.index < 0x1000:
                # The data type area: python-canopen lists [DummyUsage]
                # types as variables; CiA 301 makes them mapping dummies,
                # which our dictionary does not serve.
                continue
            if (var.index, var.subindex) not in refused:
                held.add(var.index)
            failures = len(run.failures)
            verdict = check_variable(node, var, compact, refused, run)
            outcome(var.index, "failed" if len(run.failures) > failures else verdict)
        for obj in node.object_dictionary.values():
            if obj.index < 0x1000 or obj.index in status:
                continue
            # An object python-canopen reads without a variable (an ARRAY
            # or RECORD with no sub-object described): nothing to compare,
            # but the node must answer its sub-index 0.
            where = f"{obj.index:04X}h {obj.name}"
            code = abort_code(lambda: node.sdo.upload(obj.index, 0))
            ok = run.check(f"{where} sub-index 0 readable", code is None, f"abort {code and hex(code)}")
            run.note(f"{where}: python-canopen reads it without a sub-object, so its "
                     "sub-index 0 is read but not compared")
            held.add(obj.index)
            outcome(obj.index, "served" if ok else "failed")
    finally:
        net.disconnect()
    return status, held


def check_variable(node, var, compact, refused, run):
    """The checks of one variable; "refused" when it is one the node
    leaves out, else "served"."""
    where = f"{var.index:04X}:{var.subindex:02X} {var.name}"
    if (var.index, var.subindex) in refused:
        code = abort_code(lambda: node.sdo.upload(var.index, var.subindex))
        run.check(f"{where} upload refused", code == REFUSAL, f"abort {code and hex(code)}")
        code = abort_code(lambda: node.sdo.download(var.index, var.subindex, b"\x00"))
        run.check(f"{where} download refused", code == REFUSAL, f"abort {code and hex(code)}")
        return "refused"
    access = var.access_type.lower()
    if var.index in compact and var.subindex == 0:
        run.note(f"{where}: python-canopen makes a CompactSubObj's sub-index 0 "
                 "rw without a value; CiA 306 gives it ro and the count: read only")
        access = "ro-compact"
    if access == "wo":
        code = abort_code(lambda: node.sdo.upload(var.index, var.subindex))
        run.check(f"{where} write-only", code == 0x06010001, f"abort {code}")
        return "served"
    try:
        got = node.sdo.upload(var.index, var.subindex)
    except canopen.SdoAbortedError as e:
        run.check(f"{where} readable", False, f"abort {e.code:08X}")
        return "served"
    start = var.value if var.value is not None else var.default
    if start is not None:
        try:
            want = var.encode_raw(start)
        except (ValueError, TypeError):
            # A hex bit pattern for a signed type ("0xFF" in an INTEGER8):
            # we keep the bits, python-canopen cannot encode it, so there
            # is nothing to compare.
            run.note(f"{where}: python-canopen cannot encode its value {start!r}")
            want = None
        if want is not None:
            run.check(f"{where} value", got == want, f"ours {got.hex()} python {want.hex()}")
    if access == "ro-compact":
        return "served"
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
    return "served"


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


def figure(status, left):
    """'N of M objects served; K refused because ...' for one file."""
    served = sorted(i for i, s in status.items() if s == "served")
    refused = sorted(i for i, s in status.items() if s == "refused")
    failed = sorted(i for i, s in status.items() if s == "failed")
    text = f"{len(served)} of {len(status)} objects served"
    if refused:
        reasons = "; ".join(
            f"{i:04X}h ({', '.join(sorted({r for (j, _), r in left.items() if j == i})) or 'the node gave no reason'})"
            for i in refused)
        its = "its" if len(refused) == 1 else "their"
        text += (f"; {len(refused)} refused with SDO abort 06040047h because neither the node "
                 f"nor python-canopen can encode {its} DataType: {reasons}")
    else:
        text += "; none refused"
    if failed:
        text += f"; {len(failed)} failed their checks (above): " + ", ".join(f"{i:04X}h" for i in failed)
    return text


def unreadable(path):
    """Why `path` cannot be read as a file, or None when it can."""
    try:
        with open(path, "rb") as f:
            f.read(1)
    except OSError as e:
        return e.strerror or str(e)
    return None


def one(exe, eds):
    run = Run(os.path.basename(eds))
    problem = unreadable(eds)
    if problem:
        message = f"shared test data missing or unreadable: {eds}: {problem}"
        if os.environ.get("CI") == "true":
            print(f"FAIL {message} (CI=true: every file given must be there)")
            return 1
        print(f"skipped: {message}")
        return 0
    with PythonNotes(run):
        figures = compare_file(exe, eds, run)
    for n in dict.fromkeys(run.notes):
        print(f"note {run.name} {n}")
    print(f"{run.cases - len(run.failures)}/{run.cases} EDS interop checks passed "
          f"({eds}: {figures})")
    return 1 if run.failures else 0


def compare_file(exe, eds, run):
    """Every check of one readable file; returns its figure."""
    cp = ini(eds)
    compact = compact_indexes(cp)
    python_path = copy_for_python(eds, run)
    refused = untyped(cp, canopen.import_od(python_path, NODE))
    report = check_report(exe, eds, refused, run)
    if report is None:
        return "the node did not start"
    left, said_served = report
    status, held = compare(exe, eds, python_path, compact, refused, run)
    run.check("node's count of objects served is python-canopen's", said_served == len(held),
              f"node {said_served}, python-canopen {len(held)}")
    written_eds(exe, eds, python_path, compact, run)
    return figure(status, left)


def main(exe, files):
    status = 0
    for eds in files:
        status |= one(exe, eds)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2:]))
