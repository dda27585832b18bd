#!/usr/bin/env python3
"""`canopen-boot --node N=FILE.dcf` (issue 36) as the NMT master of
python-canopen `LocalNode` slaves whose device description the project has
not seen (a valve controller written here), through candump lines on a pipe.

`canopen-boot dcf` configures the EDS for each node (heartbeat 250 ms, two
application values); the manager then boots four nodes at once:

A. node 5 matches its DCF: it is configured (the values arrive in the
   LocalNode's dictionary), started (operational) and reported
   `{"node": 5, "result": "operational"}`;
B. node 6 has another vendor-ID than its DCF: refused with letter D, not
   configured, not started;
C. node 7 has another device type: refused with letter C;
D. node 8 is absent: letter B after the retries;
E. node 5's heartbeat stops: `{"node": 5, "event": "heartbeat", "code": "E"}`;
F. nodes 9 and 10 describe their application software's date and time in
   1F52h (CiA 302-3) and the manager checks them (`--software-date`,
   `--software-time`: 1F53h, 1F54h): node 9's match, it is configured and
   started; node 10's date differs, it is refused with letter H, not
   configured.

The LocalNodes boot as CiA 301 devices do: on an NMT reset (to them or to
all) they send their boot-up message and enter pre-operational.

usage: boot_manager_interop.py PATH/TO/canopen-boot
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import canopen
from edstext import comm_objects, software_stamp
from pipebus import Cases, PipeBus, wait_until

CASES = Cases()
check = CASES.check

VALVE_EDS = """[FileInfo]
FileName=vc7.eds
EDSVersion=4.0
Description=Acme VC-7 valve controller

[DeviceInfo]
VendorName=Acme Valves
VendorNumber=0x00004A44
ProductName=VC-7
ProductNumber=0x07
RevisionNumber=0x00020001

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[OptionalObjects]
SupportedObjects=1
1=0x1017

[ManufacturerObjects]
SupportedObjects=2
1=0x2000
2=0x2001

""" + comm_objects(0x194, 0x4A44, 0x07, 0x00020001) + """
[2000]
ParameterName=Opening time
DataType=0x0007
AccessType=rw
DefaultValue=0

[2001]
ParameterName=Flow limit
DataType=0x0006
AccessType=rw
DefaultValue=0
"""


# The application software's date (days since 1984) and time (ms after
# midnight) nodes 9 and 10 are expected to have.
SW_DATE = 15340
SW_TIME = 43200000

# The valve with its application software's stamp in 1F52h.
VALVE_SW_EDS = VALVE_EDS.replace(
    "SupportedObjects=1\n1=0x1017\n", "SupportedObjects=2\n1=0x1017\n2=0x1F52\n"
) + "\n" + software_stamp(SW_DATE, SW_TIME)


def local_node(network, node_id, eds_path, changes):
    """A LocalNode of the valve EDS with `changes` {(index, sub): value} to
    its defaults, booting as a CiA 301 device on an NMT reset."""
    od = canopen.import_od(eds_path, node_id)
    for (index, sub), value in changes.items():
        entry = od[index][sub] if sub else od[index]
        entry.default = value
    node = canopen.LocalNode(node_id, od)
    network.add_node(node)

    def on_nmt(can_id, data, timestamp):
        if len(data) == 2 and data[0] in (0x81, 0x82) and data[1] in (0, node_id):
            node.nmt.send_command(0x82)  # boot-up message
            node.nmt.send_command(0x80)  # pre-operational: heartbeat per 1017h

    network.subscribe(0, on_nmt)
    return node


def main():
    boot = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="boot-manager-interop-")
    eds_path = os.path.join(tmp, "vc7.eds")
    with open(eds_path, "w") as f:
        f.write(VALVE_EDS)
    sw_eds_path = os.path.join(tmp, "vc7sw.eds")
    with open(sw_eds_path, "w") as f:
        f.write(VALVE_SW_EDS)
    args = [boot]
    for n in (5, 6, 7, 8, 9, 10):
        dcf = os.path.join(tmp, f"node{n}.dcf")
        eds = sw_eds_path if n in (9, 10) else eds_path
        # 250 ms: the manager expects the first heartbeat within 1.5 periods
        # and 20 ms; python-canopen's heartbeat thread on a loaded two-core
        # machine was seen to miss the 170 ms a 100 ms period gives.
        subprocess.run([boot, "dcf", eds, dcf, "--node-id", str(n),
                        "--set", "1017=250", "--set", "2000=0x12345678",
                        "--set", "2001=750"], check=True, capture_output=True)
        args += ["--node", f"{n}={dcf}"]
    for n in (9, 10):
        args += ["--software-date", f"{n}={SW_DATE}", "--software-time", f"{n}={SW_TIME}"]
    args += ["--sdo-timeout-ms", "200"]

    bus = PipeBus(args)
    network = canopen.Network(bus)
    ok_node = local_node(network, 5, eds_path, {})
    vendor = local_node(network, 6, eds_path, {(0x1018, 1): 0x99})
    devtype = local_node(network, 7, eds_path, {(0x1000, 0): 0x195})
    dated = local_node(network, 9, sw_eds_path, {})
    misdated = local_node(network, 10, sw_eds_path, {(0x1F52, 1): SW_DATE + 1})
    # Connected once the nodes listen: the manager's first frames (its NMT
    # resets) wait in the pipe until then, so every node sees its reset.
    network.connect()

    def results():
        out = {}
        for line in bus.stderr_lines:
            if line.startswith("{"):
                j = json.loads(line)
                out.setdefault(j["node"], []).append(j)
        return out

    # A-D: every boot ends (B takes the 1 s boot-up wait and three reads).
    wait_until(lambda: len(results()) == 6, 10)
    r = results()
    check("A: node 5 operational", r.get(5, [{}])[0].get("result") == "operational", r.get(5))
    check("A: node 5 configured (2000h, 2001h)",
          ok_node.sdo[0x2000].raw == 0x12345678 and ok_node.sdo[0x2001].raw == 750,
          (ok_node.sdo[0x2000].raw, ok_node.sdo[0x2001].raw))
    check("A: node 5 started", ok_node.nmt.state == "OPERATIONAL", ok_node.nmt.state)
    for n, node, letter in ((6, vendor, "D"), (7, devtype, "C")):
        first = r.get(n, [{}])[0]
        check(f"{'B' if n == 6 else 'C'}: node {n} refused with {letter}",
              first.get("result") == "error" and first.get("code") == letter, first)
        check(f"node {n} neither configured nor started",
              node.sdo[0x2000].raw == 0 and node.nmt.state != "OPERATIONAL",
              (node.sdo[0x2000].raw, node.nmt.state))
    first = r.get(8, [{}])[0]
    check("D: absent node 8 is B", first.get("code") == "B", first)
    check("F: node 9's software date and time match: operational",
          r.get(9, [{}])[0].get("result") == "operational", r.get(9))
    check("F: node 9 configured and started",
          dated.sdo[0x2000].raw == 0x12345678 and dated.nmt.state == "OPERATIONAL",
          (dated.sdo[0x2000].raw, dated.nmt.state))
    first = r.get(10, [{}])[0]
    check("F: node 10's software date differs: H",
          first.get("result") == "error" and first.get("code") == "H"
          and "1F52h:01" in first.get("detail", ""), first)
    check("F: node 10 neither configured nor started",
          misdated.sdo[0x2000].raw == 0 and misdated.nmt.state != "OPERATIONAL",
          (misdated.sdo[0x2000].raw, misdated.nmt.state))

    # E: node 5 goes silent.
    ok_node.nmt.stop_heartbeat()
    lost = {"node": 5, "event": "heartbeat", "code": "E"}
    check("E: node 5's heartbeat lost",
          wait_until(lambda: lost in results().get(5, []), 3), results().get(5))

    network.disconnect()
    bus.shutdown()
    shutil.rmtree(tmp, ignore_errors=True)
    CASES.finish()


if __name__ == "__main__":
    main()
