#!/usr/bin/env python3
"""Store parameters (1010h) and restore default parameters (1011h), CiA 301
sections 7.5.2.13/7.5.2.14, between the virtual CiA 418 battery module
(examples/battery_module --storage FILE) and python-canopen.

1. python-canopen reads 1010h/1011h (sub 0 = 3, capability 1 on command),
   remaps the 1st TPDO with its PdoMap.save(), sets 1017h and calls
   node.store() ("save" to 1010h sub 1); a wrong signature and a sub the
   device does not have are refused (08000020h, 06090011h).
2. The program is restarted with the same file: the remapped TPDO is read
   back by SDO, arrives on its new COB-ID with the new layout once started,
   and 1017h is the stored period. node.restore() ("load" to 1011h sub 1)
   changes nothing until the NMT reset node; after it the defaults are back.
3. A third start with the same file has the defaults too.
4. LSS (CiA 305) through the same storage: a module started without a
   node-ID (--lss --node-id 255) is given node-ID 5 by python-canopen's LSS
   master and stores it (store_configuration()); restarted on the same
   file it boots up as node 5 by itself.

The bus is tests/interop/pipebus.py's PipeBus; the object dictionary and
the module's options are battery_interop.py's.

usage: store_interop.py PATH/TO/battery_module
"""

import os
import sys
import tempfile
import time

import canopen
from canopen import lss
from battery_interop import ARGS, NODE, SOC, TEMPERATURE_RAW, VOLTAGE_RAW, dictionary
from pipebus import Cases, PipeBus

NEW_COB_ID = 0x1F1
NEW_EVENT_TIMER_MS = 100
NEW_HEARTBEAT_MS = 700
DEFAULT_MAPPING = [2, 0x60100010, 0x60000008]

CASES = Cases()
check = CASES.check
guarded = CASES.guarded


def u32(data):
    return int.from_bytes(data, "little")


def session(exe, path, body):
    """Runs the module on the storage `path`, `body(bus, node)`, stops it."""
    bus = PipeBus([exe] + ARGS + ["--storage", path])
    net = canopen.Network(bus)
    net.connect()
    node = net.add_node(NODE, dictionary())
    node.sdo.RESPONSE_TIMEOUT = 2.0
    try:
        end = time.time() + 5
        while time.time() < end and not any(i == 0x700 + NODE for _, i, _ in bus.seen):
            time.sleep(0.01)
        body(bus, node)
    finally:
        net.disconnect()


def abort_code(fn):
    try:
        fn()
    except canopen.SdoAbortedError as e:
        return e.code
    return None


def mapping(node):
    count = node.sdo[0x1A00][0].raw
    return [count] + [node.sdo[0x1A00][i].raw for i in range(1, count + 1)]


def first(bus, node):
    def objects():
        for index in (0x1010, 0x1011):
            subs = [node.sdo.upload(index, s) for s in range(0, 4)]
            check(f"{index:04X}h: sub 0 = 3, subs 1-3 capability 1 (on command)",
                  subs == [b"\x03", *([(1).to_bytes(4, "little")] * 3)],
                  [s.hex() for s in subs])
    guarded("1010h/1011h read", objects)

    def refused():
        code = abort_code(lambda: node.sdo.download(0x1010, 1, b"nope"))
        check("1010h sub 1 with a wrong signature: 08000020h", code == 0x08000020,
              code and hex(code))
        code = abort_code(lambda: node.sdo.download(0x1011, 2, b"save"))
        check("1011h sub 2 with 'save' (not its signature): 08000020h", code == 0x08000020,
              code and hex(code))
        code = abort_code(lambda: node.sdo.download(0x1010, 4, b"save"))
        check("1010h sub 4 (not there): 06090011h", code == 0x06090011, code and hex(code))
    guarded("wrong signature", refused)

    def remap_and_store():
        node.tpdo.read()
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
        node.sdo.download(0x1017, 0, NEW_HEARTBEAT_MS.to_bytes(2, "little"))
        node.store()
        time.sleep(0.1)
        check("node.store() accepted; the module stored both groups",
              "event: storage: Stored(Communication)" in bus.stderr_lines
              and "event: storage: Stored(Application)" in bus.stderr_lines,
              bus.stderr_lines[-4:])
    guarded("remap and store", remap_and_store)


def second(bus, node):
    check("restart: the module loaded the stored groups",
          "event: storage: Loaded(Communication)" in bus.stderr_lines, bus.stderr_lines[:4])

    def read_back():
        got = mapping(node)
        check("restart: 1A00h reads the remapped 3 entries",
              got == [3, 0x60600020, 0x60810008, 0x60100010], [hex(v) for v in got])
        cob = node.sdo[0x1800][1].raw
        check(f"restart: 1800h sub 1 = {NEW_COB_ID:X}h (valid), sub 5 = {NEW_EVENT_TIMER_MS} ms",
              cob == NEW_COB_ID and node.sdo[0x1800][5].raw == NEW_EVENT_TIMER_MS, hex(cob))
        hb = u32(node.sdo.upload(0x1017, 0))
        check(f"restart: 1017h = {NEW_HEARTBEAT_MS} ms", hb == NEW_HEARTBEAT_MS, hb)
    guarded("read back after restart", read_back)

    def on_the_bus():
        node.tpdo.read()
        t = node.tpdo[1]
        started = time.time()
        node.nmt.state = "OPERATIONAL"
        for _ in range(3):
            t.wait_for_reception(timeout=3)
        values = {v.index: v.raw for v in t.map}
        check("restart: the remapped TPDO arrives on 1F1h, 7 bytes, decoded by python-canopen",
              len(t.data) == 7
              and values == {0x6060: VOLTAGE_RAW, 0x6081: SOC, 0x6010: TEMPERATURE_RAW},
              (bytes(t.data).hex(), values))
        old = [d for ts, i, d in bus.seen if i == 0x180 + NODE and ts >= started]
        check("restart: nothing on the default COB-ID 181h", old == [], old[:3])
        node.nmt.state = "PRE-OPERATIONAL"
    guarded("remapped TPDO on the bus", on_the_bus)

    def restore_then_reset():
        node.restore()
        got = mapping(node)
        check("node.restore(): nothing changes before the reset", got[0] == 3,
              [hex(v) for v in got])
        # Watch the bus for the boot-up rather than python-canopen's
        # wait_for_bootup(), which misses one that comes before it waits.
        t = time.time()
        node.nmt.send_command(0x81)
        end = t + 3
        while time.time() < end and not any(
                ts >= t and i == 0x700 + node.id and d == b"\x00" for ts, i, d in bus.seen):
            time.sleep(0.02)
        check("restore + NMT reset node: the module boots up again",
              any(ts >= t and i == 0x700 + node.id and d == b"\x00" for ts, i, d in bus.seen))
        time.sleep(0.1)
        got = mapping(node)
        check("restore + NMT reset node: 1A00h has the default mapping (6010h/16, 6000h/8)",
              got == DEFAULT_MAPPING, [hex(v) for v in got])
        cob = node.sdo[0x1800][1].raw
        check("restore + reset node: 1800h sub 1 back to 181h", cob == 0x181, hex(cob))
        hb = u32(node.sdo.upload(0x1017, 0))
        check("restore + reset node: 1017h back to 1000 ms", hb == 1000, hb)
        check("the module reported the erase",
              "event: storage: Erased(Communication)" in bus.stderr_lines, bus.stderr_lines[-6:])
    guarded("restore then reset", restore_then_reset)


def third(bus, node):
    def defaults():
        got = mapping(node)
        check("third start: the defaults (the restore is kept in the file)",
              got == DEFAULT_MAPPING and node.sdo[0x1800][1].raw == 0x181,
              [hex(v) for v in got])
        check("third start: no communication record loaded",
              "event: storage: Loaded(Communication)" not in bus.stderr_lines,
              bus.stderr_lines[:4])
    guarded("third start", defaults)


LSS_NODE = 5
LSS_ARGS = ["--lss", "--node-id", "255", "--identity", "29A,418,10000,7",
            "--heartbeat-ms", "100", "--linger-ms", "0"]


def lss_session(exe, path, body):
    """Runs the module without a node-ID on the storage `path`."""
    bus = PipeBus([exe] + LSS_ARGS + ["--storage", path])
    net = canopen.Network(bus)
    net.connect()
    net.lss.RESPONSE_TIMEOUT = 0.5
    try:
        body(bus, net)
    finally:
        net.disconnect()


def lss_store(bus, net):
    def configure_and_store():
        time.sleep(0.3)
        check("LSS: the module without a node-ID is silent", bus.seen == [], bus.seen[:3])
        m = net.lss
        m.send_switch_state_global(m.CONFIGURATION_STATE)
        m.configure_node_id(LSS_NODE)
        try:
            m.store_configuration()
            stored = True
        except lss.LssError as e:
            stored = str(e)
        time.sleep(0.1)
        check("LSS: store_configuration() answered with success through the storage",
              stored is True and "event: storage: Stored(Lss)" in bus.stderr_lines,
              (stored, bus.stderr_lines[-4:]))
    guarded("LSS store", configure_and_store)


def lss_restart(bus, net):
    def boots_as_stored():
        # The boot-up and the stderr line come on two pipes: wait for both.
        end = time.time() + 3
        while time.time() < end and not (
                any(i == 0x700 + LSS_NODE for _, i, _ in bus.seen)
                and "event: storage: Loaded(Lss)" in bus.stderr_lines):
            time.sleep(0.02)
        hb = [d for _, i, d in bus.seen if i == 0x700 + LSS_NODE]
        check("LSS: restarted on the same file it boots up as node 5 (705#00) by itself",
              bool(hb) and hb[0] == b"\x00"
              and "event: storage: Loaded(Lss)" in bus.stderr_lines,
              (hb[:2], bus.stderr_lines[:3]))
    guarded("LSS restart", boots_as_stored)


def main():
    exe = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "module.storage")
        session(exe, path, first)
        check("the storage file exists after store()", os.path.exists(path))
        session(exe, path, second)
        session(exe, path, third)
        path = os.path.join(tmp, "lss.storage")
        lss_session(exe, path, lss_store)
        lss_session(exe, path, lss_restart)
    CASES.finish()


if __name__ == "__main__":
    main()
