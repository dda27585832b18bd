#!/usr/bin/env python3
"""Interop between the virtual CiA 418 battery module (examples/battery_module)
and python-canopen, a real and independent CANopen implementation.

python-canopen, as the master, reads the module's objects by SDO (1000h,
1008h, 1018h, 6020h, 6030h as a packed string, 6060h), reads its TPDO
configuration and remaps the 1st TPDO with its own PdoMap.save() (new
COB-ID, event timer and layout), starts the node with NMT and checks that the
remapped TPDO arrives with the new layout and decodes (python-canopen's PDO
decoding) to the values the module was started with. Last, an illegal
mapping (a non-mappable object) must be refused with abort 06040041h.

The two talk through a python-can bus class, PipeBus (a copy of the one in
sdo_interop.py), that exchanges candump log lines with the program's
stdin/stdout. The object dictionary python-canopen needs is built below.

usage: battery_interop.py PATH/TO/battery_module
"""

import sys
import time

import canopen
from pipebus import Cases, PipeBus
from canopen.objectdictionary import ODArray, ODRecord, ODVariable, ObjectDictionary
from canopen.objectdictionary.datatypes import (
    INTEGER16, UNSIGNED8, UNSIGNED16, UNSIGNED32, VISIBLE_STRING)

NODE = 1

# The values the module is started with.
DEVICE_NAME = "vbat interop"
IDENTITY = (0x0000ABCD, 0x418, 0x00010002, 0x12345678)
SERIAL = "SN-4711"
BATTERY_TYPE = 0x19          # gel (lead acid, maintenance free)
CAPACITY_AH = 600
MAX_CURRENT_A = 75
CELLS = 24
VOLTAGE_RAW = 52736          # 51.5 V in 1/1024 V
TEMPERATURE_RAW = -84        # -10.5 degC in 0.125 degC
SOC = 73
NEW_COB_ID = 0x1F1
NEW_EVENT_TIMER_MS = 100

ARGS = [
    "--node-id", str(NODE),
    "--device-type", "40000",
    "--device-name", DEVICE_NAME,
    "--identity", ",".join(f"{v:X}" for v in IDENTITY),
    "--serial", SERIAL,
    "--battery-type", "gel",
    "--capacity-ah", str(CAPACITY_AH),
    "--max-current-a", str(MAX_CURRENT_A),
    "--cells", str(CELLS),
    "--voltage", "51.5",
    "--temperature", "-10.5",
    "--soc", str(SOC),
    "--linger-ms", "0",
]


def var(name, index, sub, data_type, access="ro", mappable=False):
    v = ODVariable(name, index, sub)
    v.data_type = data_type
    v.access_type = access
    v.pdo_mappable = mappable
    return v


def record(cls, name, index, members):
    r = cls(name, index)
    for m in members:
        r.add_member(m)
    return r


def dictionary():
    """The module's objects python-canopen reads or maps (CiA 301 / CiA 418 types)."""
    od = ObjectDictionary()
    od.add_object(var("Device type", 0x1000, 0, UNSIGNED32, "const"))
    od.add_object(var("Manufacturer device name", 0x1008, 0, VISIBLE_STRING, "const"))
    od.add_object(record(ODRecord, "Identity", 0x1018, [
        var("Highest sub-index", 0x1018, 0, UNSIGNED8),
        var("Vendor-ID", 0x1018, 1, UNSIGNED32),
        var("Product code", 0x1018, 2, UNSIGNED32),
        var("Revision number", 0x1018, 3, UNSIGNED32),
        var("Serial number", 0x1018, 4, UNSIGNED32),
    ]))
    od.add_object(record(ODRecord, "TPDO 1 communication", 0x1800, [
        var("Highest sub-index", 0x1800, 0, UNSIGNED8),
        var("COB-ID", 0x1800, 1, UNSIGNED32, "rw"),
        var("Transmission type", 0x1800, 2, UNSIGNED8, "rw"),
        var("Inhibit time", 0x1800, 3, UNSIGNED16, "rw"),
        var("Event timer", 0x1800, 5, UNSIGNED16, "rw"),
    ]))
    od.add_object(record(ODRecord, "TPDO 1 mapping", 0x1A00,
                         [var("Number of entries", 0x1A00, 0, UNSIGNED8, "rw")]
                         + [var(f"Entry {i}", 0x1A00, i, UNSIGNED32, "rw") for i in range(1, 9)]))
    od.add_object(var("Battery status", 0x6000, 0, UNSIGNED8, mappable=True))
    od.add_object(var("Temperature", 0x6010, 0, INTEGER16, mappable=True))
    od.add_object(record(ODRecord, "Battery parameters", 0x6020, [
        var("Highest sub-index", 0x6020, 0, UNSIGNED8),
        var("Battery type", 0x6020, 1, UNSIGNED8),
        var("Ah capacity", 0x6020, 2, UNSIGNED16),
        var("Maximum charge current", 0x6020, 3, UNSIGNED16),
        var("Number of cells", 0x6020, 4, UNSIGNED16),
    ]))
    serial = ODArray("Battery serial number", 0x6030)
    serial.add_member(var("Number of elements", 0x6030, 0, UNSIGNED8))
    for i in range(1, 4):
        serial.add_member(var(f"Element {i}", 0x6030, i, UNSIGNED32))
    od.add_object(serial)
    od.add_object(var("Battery voltage", 0x6060, 0, UNSIGNED32, mappable=True))
    od.add_object(var("Battery state of charge", 0x6081, 0, UNSIGNED8, mappable=True))
    return od


def unpack(words):
    """CiA 418 packed string: 4 ISO 646 characters per U32, first in the LSB."""
    data = b"".join(w.to_bytes(4, "little") for w in words)
    return data.rstrip(b"\0").decode("ascii")


CASES = Cases()
check = CASES.check
guarded = CASES.guarded


def main():
    exe = sys.argv[1]
    bus = PipeBus([exe] + ARGS)
    net = canopen.Network(bus)
    net.connect()
    node = net.add_node(NODE, dictionary())
    node.sdo.RESPONSE_TIMEOUT = 2.0
    try:
        run(bus, node)
    finally:
        net.disconnect()
    CASES.finish()


def run(bus, node):
    # Wait for the boot-up message (the module boots at start).
    end = time.time() + 5
    while time.time() < end and not any(i == 0x700 + NODE for _, i, _ in bus.seen):
        time.sleep(0.01)
    check("boot-up message 701#00 seen",
          (0x700 + NODE, b"\x00") in [(i, d) for _, i, d in bus.seen], bus.seen[:3])

    guarded("1000h device type", lambda: check(
        "1000h device type = 000401A2h (418, 2nd TPDO)", node.sdo[0x1000].raw == 0x000401A2,
        hex(node.sdo[0x1000].raw)))
    guarded("1008h", lambda: check(
        f"1008h device name = {DEVICE_NAME!r} (segmented upload)",
        node.sdo[0x1008].raw == DEVICE_NAME, node.sdo[0x1008].raw))

    def identity():
        got = tuple(node.sdo[0x1018][i].raw for i in range(1, 5))
        check("1018h identity sub 1-4", got == IDENTITY and node.sdo[0x1018][0].raw == 4,
              [hex(v) for v in got])
    guarded("1018h identity", identity)

    def parameters():
        got = tuple(node.sdo[0x6020][i].raw for i in range(0, 5))
        check("6020h battery parameters (4, gel 19h, 600 Ah, 75 A, 24 cells)",
              got == (4, BATTERY_TYPE, CAPACITY_AH, MAX_CURRENT_A, CELLS), got)
    guarded("6020h battery parameters", parameters)

    def serial():
        count = node.sdo[0x6030][0].raw
        words = [node.sdo[0x6030][i].raw for i in range(1, count + 1)]
        check(f"6030h serial number as a packed string = {SERIAL!r}",
              count == 2 and unpack(words) == SERIAL, (count, [hex(w) for w in words]))
    guarded("6030h serial number", serial)

    guarded("6060h", lambda: check(
        "6060h battery voltage = 52736 (51.5 V)", node.sdo[0x6060].raw == VOLTAGE_RAW,
        node.sdo[0x6060].raw))

    def read_tpdo():
        node.tpdo.read()
        t = node.tpdo[1]
        layout = [(v.index, v.subindex, v.length) for v in t.map]
        check("TPDO 1 read: COB-ID 181h, valid, type 255, 200 ms, 6010h/16 + 6000h/8",
              (t.cob_id, t.enabled, t.trans_type, t.event_timer, layout)
              == (0x181, True, 255, 200, [(0x6010, 0, 16), (0x6000, 0, 8)]),
              (hex(t.cob_id), t.enabled, t.trans_type, t.event_timer, layout))
    guarded("TPDO 1 read", read_tpdo)

    def remap():
        t = node.tpdo[1]
        t.clear()
        t.add_variable(0x6060)
        t.add_variable(0x6081)
        t.add_variable(0x6010)
        t.cob_id = NEW_COB_ID
        t.trans_type = 255
        t.event_timer = NEW_EVENT_TIMER_MS
        t.enabled = True
        t.save()
        back = [node.sdo[0x1A00][i].raw for i in range(0, 4)]
        check("TPDO 1 remapped by PdoMap.save(): 1A00h reads back 3 entries",
              back == [3, 0x60600020, 0x60810008, 0x60100010], [hex(v) for v in back])
        cob = node.sdo[0x1800][1].raw
        check(f"1800h sub 1 reads back {NEW_COB_ID:X}h (valid) and sub 5 {NEW_EVENT_TIMER_MS} ms",
              cob & 0xBFFFFFFF == NEW_COB_ID and node.sdo[0x1800][5].raw == NEW_EVENT_TIMER_MS,
              hex(cob))
    guarded("TPDO 1 remap", remap)

    def start_and_receive():
        t = node.tpdo[1]
        started = time.time()
        node.nmt.state = "OPERATIONAL"
        t.wait_for_reception(timeout=3)
        t.wait_for_reception(timeout=3)
        t.wait_for_reception(timeout=3)
        values = {v.index: v.raw for v in t.map}
        check("remapped TPDO arrives on 1F1h with 7 bytes",
              len(t.data) == 7, bytes(t.data).hex())
        check("python-canopen decodes it: 6060h 52736, 6081h 73 %, 6010h -84 (-10.5 degC)",
              values == {0x6060: VOLTAGE_RAW, 0x6081: SOC, 0x6010: TEMPERATURE_RAW}, values)
        check(f"event timer: period about {NEW_EVENT_TIMER_MS} ms",
              t.period is not None and 0.05 <= t.period <= 0.3, t.period)
        old = [d for ts, i, d in bus.seen if i == 0x180 + NODE and ts >= started]
        check("nothing more on the old COB-ID 181h", old == [], old[:3])
        second = [d for ts, i, d in bus.seen if i == 0x280 + NODE and ts >= started]
        check("2nd TPDO (281h) keeps its default layout: 6010h, 6000h, 6060h",
              bool(second) and second[-1] == bytes.fromhex("ACFF01") + VOLTAGE_RAW.to_bytes(4, "little"),
              [d.hex() for d in second[:2]])
        check("heartbeat reports operational",
              node.nmt.wait_for_heartbeat(timeout=3) == "OPERATIONAL")
    guarded("start and receive", start_and_receive)

    def illegal_mapping():
        node.nmt.state = "PRE-OPERATIONAL"
        t = node.tpdo[1]
        t.clear()
        t.add_variable(0x6020, 2)  # Ah capacity: not PDO-mappable in CiA 418
        try:
            t.save()
            code = None
        except canopen.SdoAbortedError as e:
            code = e.code
        check("mapping a non-mappable object (6020h sub 2) is refused with 06040041h",
              code == 0x06040041, code and hex(code))
    guarded("illegal mapping", illegal_mapping)

    time.sleep(0.1)
    events = bus.stderr_lines
    check("the module reported the remapping and the NMT start in words",
          "event: SDO download to 1A00h sub 00h" in events
          and "event: NMT pre-operational -> operational" in events, events[-5:])


if __name__ == "__main__":
    main()
