#!/usr/bin/env python3
"""EDS interop: our SDO server serving a dictionary built from an EDS
(examples/sdo_node --server --eds FILE), read and written by python-canopen
with the same EDS loaded by its own importer (canopen.import_od through
Network.add_node).

For every variable of the description: a readable one uploads to the value
python-canopen computes from the same DefaultValue for the same node id
($NODEID resolved); a write-only one aborts 06010001h; a writable one takes
its own value back in a download; a read-only or const one refuses it with
06010002h. Then the EDS as we write it (sdo_node --print-eds) must load in
python-canopen's importer to the same objects: names, data types, access,
PDO mapping and defaults.

usage: eds_interop.py PATH/TO/sdo_node PATH/TO/FILE.eds
(when FILE.eds is absent it says so and passes: the real EDS files are not
part of the repository)
"""

import os
import subprocess
import sys
import tempfile

import canopen
from canopen.objectdictionary import ODArray, ODRecord
from canopen.objectdictionary.datatypes import DOMAIN, OCTET_STRING, VISIBLE_STRING
from pipebus import PipeBus

NODE = 10

failures = []
skipped = []
cases = 0


def check(name, ok, detail=""):
    global cases
    cases += 1
    if not ok:
        print(f"FAIL {name}: {detail}")
        failures.append(name)


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


def main(exe, eds):
    if not os.path.exists(eds):
        print(f"skipped: {eds} is absent")
        return 0
    bus = PipeBus([exe, "--server", "--node-id", str(NODE), "--eds", eds])
    net = canopen.Network(bus)
    net.connect()
    node = net.add_node(NODE, eds)
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
            if access == "wo":
                code = abort_code(lambda: node.sdo.upload(var.index, var.subindex))
                check(f"{where} write-only", code == 0x06010001, f"abort {code}")
                continue
            try:
                got = node.sdo.upload(var.index, var.subindex)
            except canopen.SdoAbortedError as e:
                check(f"{where} readable", False, f"abort {e.code:08X}")
                continue
            if var.default is not None and var.data_type not in (DOMAIN,):
                try:
                    want = var.encode_raw(var.default)
                except ValueError:
                    # A hex bit pattern for a signed type ("0xFF" in an
                    # INTEGER8): we keep the bits, python-canopen cannot
                    # encode it, so there is nothing to compare.
                    skipped.append(where)
                    want = got
                if var.data_type in (VISIBLE_STRING, OCTET_STRING):
                    want = want[:len(got)] if got == want[:len(got)] else want
                check(f"{where} value", got == want, f"ours {got.hex()} python {want.hex()}")
            if access in ("rw", "rwr", "rww"):
                code = abort_code(lambda: node.sdo.download(var.index, var.subindex, got))
                check(f"{where} writable", code is None, f"abort {code and hex(code)}")
            else:
                code = abort_code(lambda: node.sdo.download(var.index, var.subindex, got))
                check(f"{where} not writable", code == 0x06010002, f"abort {code and hex(code)}")
    finally:
        net.disconnect()
    written = subprocess.run([exe, "--print-eds", eds], check=True, capture_output=True).stdout
    with tempfile.NamedTemporaryFile(suffix=".eds") as f:
        f.write(written)
        f.flush()
        ours = canopen.import_od(f.name, NODE)
    theirs = canopen.import_od(eds, NODE)
    described = lambda od: {
        (v.index, v.subindex): (v.name, v.data_type, v.access_type.lower(), v.pdo_mappable, v.default)
        for v in variables(od)
    }
    a, b = described(ours), described(theirs)
    check("written EDS has the same variables", a.keys() == b.keys(), f"{set(a) ^ set(b)}")
    for key in sorted(a.keys() & b.keys()):
        check(f"written EDS {key[0]:04X}:{key[1]:02X}", a[key] == b[key], f"ours {a[key]} original {b[key]}")
    for where in skipped:
        print(f"note {where}: python-canopen cannot encode its DefaultValue")
    print(f"{cases - len(failures)}/{cases} EDS interop checks passed ({eds})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
