#!/usr/bin/env python3
"""Interop between the virtual charger (examples/charger) and python-canopen,
a real and independent CANopen implementation, playing the battery side.

python-canopen runs a LocalNode as the battery module (node 1: its SDO
server answers the charger's configuration reads of 1000h, 1400h:01 and
1800h:01; its NMT slave sends the heartbeat) and a RemoteNode for the
charger (node 10: NMT start as the real capture's BMS does with 000#010A,
SDO reads of the charger's objects, its EMCY consumer). Then the battery's
heartbeat stops: the charger must raise E-0-3-2 (EMCY 8130h, register 01h,
Delta-Q code 8020h little-endian) and keep it in 1003h with the Delta-Q byte
order, then E-0-3-0 when it takes the module as gone (2000 ms without a
heartbeat) and leave operational, as the real ICL1500 does; then the
heartbeat comes back, the charger reconfigures and sends an error reset,
and python-canopen as the master starts it again.

usage: charger_interop.py PATH/TO/charger
"""

import sys
import time

import canopen
from canopen.objectdictionary import ODRecord, ODVariable, ObjectDictionary
from canopen.objectdictionary.datatypes import UNSIGNED8, UNSIGNED16, UNSIGNED32
from pipebus import Cases, PipeBus, frames, wait_until

CHARGER = 10
BATTERY = 1

CASES = Cases()
check = CASES.check


def var(name, index, sub, dtype, access, default):
    v = ODVariable(name, index, sub)
    v.data_type = dtype
    v.access_type = access
    v.default = default
    return v


def battery_od():
    """The objects the charger reads from a CiA 418 battery module."""
    od = ObjectDictionary()
    od.add_object(var("Device type", 0x1000, 0, UNSIGNED32, "ro", 0x000001A2))
    od.add_object(var("Producer heartbeat time", 0x1017, 0, UNSIGNED16, "rw", 0))
    for index, cob in [(0x1400, 0x201), (0x1800, 0x181)]:
        rec = ODRecord(f"PDO {index:04X}", index)
        rec.add_member(var("Highest sub-index", index, 0, UNSIGNED8, "const", 5))
        rec.add_member(var("COB-ID", index, 1, UNSIGNED32, "rw", cob))
        od.add_object(rec)
    # python-canopen's LocalNode wants the mappings beside the parameters
    # (the CiA 418 defaults: 1600h 6001h/8; 1A00h 6010h/16, 6000h/8).
    for index, entries in [(0x1600, [0x60010008]), (0x1A00, [0x60100010, 0x60000008])]:
        rec = ODRecord(f"Mapping {index:04X}", index)
        rec.add_member(var("Number of entries", index, 0, UNSIGNED8, "rw", len(entries)))
        for n, e in enumerate(entries, 1):
            rec.add_member(var(f"Entry {n}", index, n, UNSIGNED32, "rw", e))
        od.add_object(rec)
    for index, dtype in [(0x6000, UNSIGNED8), (0x6001, UNSIGNED8), (0x6010, UNSIGNED16)]:
        v = var(f"{index:04X}", index, 0, dtype, "rw", 0)
        v.pdo_mappable = True
        od.add_object(v)
    return od


def charger_od():
    od = ObjectDictionary()
    od.add_object(var("Device type", 0x1000, 0, UNSIGNED32, "ro", 0))
    od.add_object(var("Producer heartbeat time", 0x1017, 0, UNSIGNED16, "rw", 0))
    return od


def charger_network(bus):
    """python-canopen on `bus`: the battery module as a LocalNode (its SDO
    reads recorded) and the charger as a remote node. Also used by
    firmware_interop.py. Returns (network, battery, charger, reads)."""
    net = canopen.Network(bus)
    net.connect()
    battery = canopen.LocalNode(BATTERY, battery_od())
    net.add_node(battery)
    reads = []
    battery.add_read_callback(lambda index, subindex, od: reads.append((index, subindex)))
    charger = net.add_node(CHARGER, charger_od())
    charger.sdo.RESPONSE_TIMEOUT = 2.0
    return net, battery, charger, reads


def main():
    exe = sys.argv[1]
    bus = PipeBus([exe, "--node-id", str(CHARGER), "--battery-node", str(BATTERY),
                   "--current", "19.5", "--voltage", "48", "--linger-ms", "0"])
    net, battery, charger, reads = charger_network(bus)
    try:
        check("the charger boots (70A#00)", wait_until(lambda: frames(bus, 0x700 + CHARGER, 0), 3))
        # The battery module boots and sends its heartbeat.
        net.send_message(0x700 + BATTERY, [0x00])
        battery.nmt.state = "OPERATIONAL"
        battery.nmt.start_heartbeat(200)
        configured = wait_until(lambda: any("configured" in l for l in bus.stderr_lines), 5)
        check("the charger reads 1000h, 1400h:01, 1800h:01 from python-canopen's server",
              configured and reads[:3] == [(0x1000, 0), (0x1400, 1), (0x1800, 1)], reads)
        # NMT start, as the BMS in the real capture (000#010A).
        charger.nmt.state = "OPERATIONAL"
        t0 = time.time()
        time.sleep(1.2)
        tpdo = frames(bus, 0x201, t0)
        # 6001h is the charge control's: the module never said ready
        # (6000h = 0), so the charger is not charging (00).
        check("charger TPDO 0 on the module's RPDO 0 COB-ID 201h, about every 200 ms, 6001h = 00",
              4 <= len(tpdo) <= 8 and all(d == b"\x00" for _, d in tpdo), tpdo)
        check("charger heartbeat reports operational",
              wait_until(lambda: frames(bus, 0x700 + CHARGER, t0)[-1:] and
                         frames(bus, 0x700 + CHARGER, t0)[-1][1] == b"\x05", 2))
        # python-canopen reads the charger's objects.
        check("1000h = 419 (CiA 419 charger)", charger.sdo.upload(0x1000, 0) == (419).to_bytes(4, "little"))
        check("1008h device name (segmented upload)",
              charger.sdo.upload(0x1008, 0) == b"canopen-codec charger")
        check("1016h:01 = node 1, 2000 ms", charger.sdo.upload(0x1016, 1) == bytes([0xD0, 0x07, 0x01, 0x00]))
        check("1017h = 1000 ms", charger.sdo.upload(0x1017, 0) == (1000).to_bytes(2, "little"))
        # 2002h is the charge control's reading of its output: the fixed
        # power stage (--current 19.5 --voltage 48) reads 19.5 A.
        check("2002h = 19.5 A (Q8): the fixed power stage's reading",
              charger.sdo.upload(0x2002, 0) == (19 * 256 + 128).to_bytes(2, "little"),
              charger.sdo.upload(0x2002, 0).hex())
        check("2101h = 48 V (Q8)", charger.sdo.upload(0x2101, 0) == (48 * 256).to_bytes(2, "little"),
              charger.sdo.upload(0x2101, 0).hex())
        check("1003h:00 = 0 (no error yet)", charger.sdo.upload(0x1003, 0) == b"\x00")
        code = None
        try:
            charger.sdo.download(0x2006, 0, b"\x00\x00")
        except canopen.SdoAbortedError as e:
            code = e.code
        check("2006h is read-only (06010002h)", code == 0x06010002,
              "written" if code is None else hex(code))
        # The battery's heartbeat stops.
        battery.nmt.stop_heartbeat()
        t1 = time.time()
        lost = wait_until(lambda: len(charger.emcy.log) >= 1, 4)
        e = charger.emcy.log[0] if lost else None
        check("EMCY 8130h, register 01h, Delta-Q E-0-3-2 (20 80 ...)",
              e is not None and e.code == 0x8130 and e.register == 0x01 and bytes(e.data[:2]) == b"\x20\x80",
              e and (hex(e.code), e.register, bytes(e.data).hex()))
        check("lost after the 2000 ms consumer time", e is not None and 1.6 <= e.timestamp - t1 <= 3.5,
              e and e.timestamp - t1)
        # With the 2000 ms consumer time the module is gone at once after
        # the loss: E-0-3-0, and the charger leaves operational (as the
        # real ICL1500 does in the capture).
        gone = wait_until(lambda: len(charger.emcy.log) >= 2, 2)
        g = charger.emcy.log[1] if gone else None
        check("module gone: EMCY 8130h, Delta-Q E-0-3-0 (1E 80 ...) right after E-0-3-2",
              g is not None and g.code == 0x8130 and bytes(g.data[:2]) == b"\x1e\x80"
              and g.timestamp - e.timestamp < 0.5,
              g and (hex(g.code), bytes(g.data).hex()))
        time.sleep(1.2)
        check("charger TPDOs stop", not frames(bus, 0x201, time.time() - 0.5))
        hb = frames(bus, 0x70A, time.time() - 1.1)
        check("the charger's heartbeat says pre-operational (70A#7F)", hb and hb[-1][1] == b"\x7f", hb)
        check("1003h:00 = 2", charger.sdo.upload(0x1003, 0) == b"\x02")
        check("1003h:01 = 1E808130h, 1003h:02 = 20808130h (Delta-Q byte order, newest first)",
              (charger.sdo.upload(0x1003, 1), charger.sdo.upload(0x1003, 2))
              == ((0x1E808130).to_bytes(4, "little"), (0x20808130).to_bytes(4, "little")))
        # The battery is back: boot-up and heartbeat.
        net.send_message(0x700 + BATTERY, [0x00])
        battery.nmt.start_heartbeat(200)
        reset = wait_until(lambda: any(x.code == 0 for x in charger.emcy.log), 5)
        check("reconfigured and error reset EMCY (0000h)", reset, [hex(x.code) for x in charger.emcy.log])
        check("the configuration was read again", reads.count((0x1000, 0)) == 2, reads)
        t2 = time.time()
        time.sleep(0.7)
        check("pre-operational: no TPDO until the master starts it", not frames(bus, 0x201, t2))
        charger.nmt.state = "OPERATIONAL"
        t3 = time.time()
        time.sleep(0.7)
        check("started again: charger TPDOs resume", len(frames(bus, 0x201, t3)) >= 2)
        charger.sdo.download(0x1003, 0, b"\x00")
        check("writing 0 to 1003h:00 clears the history", charger.sdo.upload(0x1003, 0) == b"\x00")
        check("no EMCY beyond E-0-3-2, E-0-3-0 and the reset",
              [x.code for x in charger.emcy.log] == [0x8130, 0x8130, 0],
              [hex(x.code) for x in charger.emcy.log])
    finally:
        battery.nmt.stop_heartbeat()
        net.disconnect()
    events = [l for l in bus.stderr_lines if l.startswith("event:")]
    check("the charger reported the loss and the recovery in words",
          any("heartbeat lost" in l for l in events) and
          any("module gone" in l for l in events) and
          sum("configured" in l for l in events) == 2, events)
    CASES.finish()


if __name__ == "__main__":
    main()
