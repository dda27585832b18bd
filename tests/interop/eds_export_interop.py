#!/usr/bin/env python3
"""EDS export interop: the EDS our own nodes describe themselves with
(examples/battery_module --print-eds, examples/charger --print-eds) loaded
by python-canopen's importer (canopen.import_od), a real and independent
CANopen stack.

Each file must load without error, python-canopen must see every object
and sub-object the file has, and for each one its name, data type, access,
PDO-mappable flag and default must be what the file says. Then a few facts
are checked by value: 6010h INTEGER16 ro (module) / rw (charger), 1017h
UNSIGNED16 rw with the configured heartbeat, 1000h 000001A2h for the module
and 000001A3h for the charger, 1018h vendor-ID, 1008h device name, 1200h
COB-IDs for the node id (the charger's 1018h is all zero: ChargerConfig has no
identity).

usage: eds_export_interop.py PATH/TO/battery_module PATH/TO/charger
"""

import re
import subprocess
import sys
import tempfile

import canopen
from canopen.objectdictionary import ODArray, ODRecord
from canopen.objectdictionary.datatypes import INTEGER16, UNSIGNED16, UNSIGNED32, VISIBLE_STRING

failures = []
cases = 0


def check(name, ok, detail=""):
    global cases
    cases += 1
    if not ok:
        print(f"FAIL {name}: {detail}")
        failures.append(name)


def sections(text):
    """The file's sections as {name: {key: value}}, keys as written."""
    out, current = {}, None
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith(";"):
            continue
        if line.startswith("["):
            current = out.setdefault(line[1:-1], {})
        elif current is not None and "=" in line:
            k, v = line.split("=", 1)
            current[k] = v
    return out


def entries(secs):
    """{(index, sub): keys} for every value the file describes."""
    out = {}
    for name, keys in secs.items():
        m = re.fullmatch(r"([0-9A-F]{4})(?:sub([0-9A-F]+))?", name)
        if not m:
            continue
        index = int(m.group(1), 16)
        if m.group(2) is not None:
            out[(index, int(m.group(2), 16))] = keys
        elif int(keys.get("ObjectType", "0x7"), 0) == 7:
            out[(index, 0)] = keys
    return out


def variables(od):
    for obj in od.values():
        if isinstance(obj, (ODRecord, ODArray)):
            for var in obj.values():
                yield (obj.index, var.subindex), var
        else:
            yield (obj.index, 0), obj


def expected_default(keys):
    text = keys.get("DefaultValue")
    if text is None:
        return None
    if int(keys["DataType"], 0) == VISIBLE_STRING:
        return text
    return int(text, 0)


def run(exe, args):
    return subprocess.run([exe, *args, "--print-eds"], check=True, capture_output=True).stdout


def load(what, text, node):
    with tempfile.NamedTemporaryFile(suffix=".eds") as f:
        f.write(text)
        f.flush()
        error = None
        try:
            od = canopen.import_od(f.name, node)
        except Exception as e:  # noqa: BLE001 - any importer error is a failure
            error, od = e, None
    check(f"{what}: python-canopen imports the EDS", error is None, repr(error))
    return od


def compare(what, text, od):
    ours = entries(sections(text.decode()))
    theirs = dict(variables(od))
    check(f"{what}: same sub-objects", ours.keys() == theirs.keys(), f"{set(ours) ^ set(theirs)}")
    indexes = {i for i, _ in ours}
    check(f"{what}: every index present", all(i in od for i in indexes))
    for key in sorted(ours.keys() & theirs.keys()):
        keys, var = ours[key], theirs[key]
        want = (
            keys["ParameterName"],
            int(keys["DataType"], 0),
            keys["AccessType"],
            keys["PDOMapping"] == "1",
            expected_default(keys),
        )
        got = (var.name, var.data_type, var.access_type.lower(), var.pdo_mappable, var.default)
        check(f"{what} {key[0]:04X}:{key[1]:02X}", want == got, f"file {want} python-canopen {got}")
    return len(ours)


def fact(what, od, index, sub, data_type, access, default):
    obj = od[index]
    var = obj[sub] if isinstance(obj, (ODRecord, ODArray)) else obj
    got = (var.data_type, var.access_type.lower(), var.default)
    want = (data_type, access, default)
    check(f"{what} {index:04X}:{sub:02X} {want}", got == want, f"python-canopen {got}")


def main(module_exe, charger_exe):
    module_args = ["--node-id", "3", "--heartbeat-ms", "1000", "--identity", "110,2,3,4",
                   "--device-name", "interop module", "--temperature", "-12.5"]
    text = run(module_exe, module_args)
    od = load("battery module", text, 3)
    if od is not None:
        n = compare("battery module", text, od)
        fact("module", od, 0x6010, 0, INTEGER16, "ro", -100)
        fact("module", od, 0x1017, 0, UNSIGNED16, "rw", 1000)
        fact("module", od, 0x1000, 0, UNSIGNED32, "const", 0x000001A2)
        fact("module", od, 0x1018, 1, UNSIGNED32, "ro", 0x110)
        fact("module", od, 0x1008, 0, VISIBLE_STRING, "const", "interop module")
        fact("module", od, 0x1200, 1, UNSIGNED32, "ro", 0x603)
        fact("module", od, 0x1200, 2, UNSIGNED32, "ro", 0x583)
        print(f"battery module: {n} sub-objects compared")
    text = run(charger_exe, ["--node-id", "10", "--heartbeat-ms", "500"])
    od = load("charger", text, 10)
    if od is not None:
        n = compare("charger", text, od)
        fact("charger", od, 0x6010, 0, INTEGER16, "rw", 0)
        fact("charger", od, 0x1017, 0, UNSIGNED16, "rw", 500)
        fact("charger", od, 0x1000, 0, UNSIGNED32, "const", 0x000001A3)
        # ChargerConfig has no identity: the charger's 1018h is all zero.
        fact("charger", od, 0x1018, 1, UNSIGNED32, "ro", 0)
        fact("charger", od, 0x2002, 0, UNSIGNED16, "rw", 0)
        fact("charger", od, 0x1200, 2, UNSIGNED32, "ro", 0x58A)
        check("charger 1016h present", 0x1016 in od)
        print(f"charger: {n} sub-objects compared")
    print(f"{cases - len(failures)}/{cases} EDS export interop checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
