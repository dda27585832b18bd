#!/usr/bin/env python3
"""The footprint firmware (examples/firmware: the CiA 418 battery module at
node 1 and the Delta-Q charger at node 10, Cortex-M4 ELF files) run on the
emulated CPU of examples/firmware/emulate.py, with python-canopen, a real
and independent CANopen implementation, as the peer on the same candump
pipe the host examples use (PipeBus).

Battery module: boot-up and the heartbeat period (1000 ms, then 500 ms
after an expedited and a segmented download of 1017h), SDO downloads of
the writable profile objects (6052h-6054h, expedited and segmented), SDO
uploads of
1000h, 1008h (segmented), 1018h, 6030h (packed string) and of the
measurements the emulator's sensor registers give, TPDO 1 in
operational with those values (the 2nd TPDO absent, as device type
000001A2h says), a sensor change reaching the TPDO, the
RPDO (6001h written by a PDO), EMCY 5010h on the temperature sensor fault
bit and its error reset, NMT stop / start / reset communication / reset
node. Charger: python-canopen's LocalNode as the battery module (the
charger's configuration reads), NMT start and its TPDO, SDO reads, the
battery's heartbeat loss (EMCY 8130h, E-0-3-2), the recovery, and the
battery's EMCY reaching the firmware's stop output. Each emulator run ends
on stdin EOF with its summary (stack high-water mark, RAM use,
instructions per frame), printed here; the stack plus .data/.bss must fit
the RAM of memory.x.

The firmware is built without the optional services (the cargo features
lss, guarding, sync-time, sdo-block are off): their cases are not run (a
"skip ... not in this build" line each) and instead their objects must be
refused with 06020000h, an SDO block transfer with 05040001h, and LSS and
node guarding requests must go unanswered. The battery module is built
without heartbeat-consumer too (the charger needs it): its 1016h is
refused with 06020000h.

usage: firmware_interop.py EMULATE_PY BATTERY_ELF CHARGER_ELF [--stack-report FILE]
"""

import sys
import time

import can
import canopen
from pipebus import Cases, PipeBus

import battery_interop
import charger_interop
from charger_interop import charger_network, frames, wait_until

BATTERY = 1
CHARGER = 10
VOLTAGE_RAW = 52736    # the emulator's battery voltage sensor: 51.5 V in 1/1024 V
TEMPERATURE_RAW = -84  # -10.5 degC in 1/8 degC
SOC = 73

CASES = Cases()
check = CASES.check
guarded = CASES.guarded
# The host scripts' dictionaries and helpers count their cases in their own
# Cases; ours are counted here.
battery_interop.CASES = charger_interop.CASES = CASES

OPTIONAL_OBJECTS = [  # (index, the service left out of the firmware)
    (0x100C, "guarding"), (0x100D, "guarding"), (0x1006, "sync-time"), (0x1012, "sync-time")]
SKIPPED = [  # the cases of the host scripts for services not in the firmware
    "lss: fast scan, inquire, configure node-ID, store (lss_interop.py)",
    "guarding: node guarding answers and life guarding (guarding_interop.py)",
    "sync-time: SYNC-driven TPDOs, TIME stamp",
    "sdo-block: block upload and download",
]


def skip_optional():
    for case in SKIPPED:
        print(f"skip {case}: not in this build (cargo feature off in examples/firmware)")


def heartbeats(bus, node, since):
    return [(ts, d) for ts, d in frames(bus, 0x700 + node, since)]


def period(stamps):
    gaps = [b - a for a, b in zip(stamps, stamps[1:])]
    return sum(gaps) / len(gaps) if gaps else None


def aborted(fn):
    """The abort code `fn` ends with, or None when it succeeds."""
    try:
        fn()
    except canopen.SdoAbortedError as e:
        return e.code
    return None


def left_out(node, bus, who):
    """The optional services' objects and requests, refused or ignored."""
    for index, feature in OPTIONAL_OBJECTS:
        guarded(f"{who} {index:04X}h", lambda index=index, feature=feature: check(
            f"{who}: {index:04X}h ({feature} not in this build) refused with 06020000h",
            aborted(lambda: node.sdo.upload(index, 0)) == 0x06020000))

    def block_upload():
        def run():
            with node.sdo.open(0x1008, 0, "rb", block_transfer=True) as f:
                f.read()
        code = aborted(run)
        check(f"{who}: SDO block upload of 1008h (sdo-block not in this build) refused with "
              "05040001h", code == 0x05040001, code and hex(code))
    guarded(f"{who} block upload", block_upload)

    def block_download():
        def run():
            with node.sdo.open(0x1017, 0, "wb", size=2, block_transfer=True) as f:
                f.write(b"\xe8\x03")
        code = aborted(run)
        check(f"{who}: SDO block download to 1017h refused with 05040001h",
              code == 0x05040001, code and hex(code))
    guarded(f"{who} block download", block_download)

    def lss():
        # LSS inquire node-ID (CiA 305): no answer on 7E4h.
        t = time.time()
        bus.send(can.Message(arbitration_id=0x7E5, data=bytes([0x5E] + [0] * 7),
                             is_extended_id=False))
        time.sleep(0.3)
        check(f"{who}: LSS inquire node-ID (lss not in this build) unanswered",
              not frames(bus, 0x7E4, t))
    guarded(f"{who} LSS", lss)


def battery(emulate, elf, report):
    cmd = [sys.executable, emulate, elf] + (["--stack-report", report] if report else [])
    bus = PipeBus(cmd)
    net = canopen.Network(bus)
    net.connect()
    node = net.add_node(BATTERY, battery_interop.dictionary())
    node.sdo.RESPONSE_TIMEOUT = 2.0
    try:
        battery_cases(bus, net, node)
    except BrokenPipeError:
        check("the emulator ran until stdin closed", False, "it exited early")
    finally:
        net.disconnect()
    return summary(bus, "battery_module")


def battery_cases(bus, net, node):
    booted = wait_until(lambda: (0x701, b"\x00") in [(i, d) for _, i, d in bus.seen], 5)
    check("battery: boot-up message 701#00", booted, bus.seen[:3])
    if not booted:
        return  # the emulator's summary below says why
    t0 = time.time()
    wait_until(lambda: len(heartbeats(bus, BATTERY, t0)) >= 3, 3.5)
    beats = heartbeats(bus, BATTERY, t0)
    p = period([ts for ts, _ in beats])
    check("battery: heartbeat 701#7F (pre-operational) about every 1000 ms",
          len(beats) >= 3 and all(d == b"\x7f" for _, d in beats) and 0.85 <= p <= 1.15,
          (len(beats), p))

    guarded("battery 1000h", lambda: check(
        "battery: 1000h device type = 000001A2h (CiA 418)",
        node.sdo[0x1000].raw == 0x000001A2, hex(node.sdo[0x1000].raw)))
    guarded("battery 1008h", lambda: check(
        "battery: 1008h = 'CiA 418 battery module' (segmented upload)",
        node.sdo[0x1008].raw == "CiA 418 battery module", node.sdo[0x1008].raw))
    guarded("battery 1018h", lambda: check(
        "battery: 1018h identity: 4 sub-indices, all zero (the firmware's default)",
        [node.sdo[0x1018][i].raw for i in range(5)] == [4, 0, 0, 0, 0]))

    def serial():
        count = node.sdo[0x6030][0].raw
        words = [node.sdo[0x6030][i].raw for i in range(1, count + 1)]
        check("battery: 6030h serial number = 'FW-0001' (packed string)",
              battery_interop.unpack(words) == "FW-0001", (count, [hex(w) for w in words]))
    guarded("battery 6030h", serial)
    guarded("battery sensors", lambda: check(
        "battery: 6060h 52736, 6010h -84, 6081h 73 %, 6000h 01h from the sensor registers",
        (node.sdo[0x6060].raw, node.sdo[0x6010].raw, node.sdo[0x6081].raw, node.sdo[0x6000].raw)
        == (VOLTAGE_RAW, TEMPERATURE_RAW, SOC, 1)))

    def heartbeat_time():
        node.sdo.download(0x1017, 0, (500).to_bytes(2, "little"))
        first = node.sdo.upload(0x1017, 0)
        node.sdo.download(0x1017, 0, (500).to_bytes(2, "little"), force_segment=True)
        check("battery: 1017h = 500 by expedited and by segmented download",
              first == node.sdo.upload(0x1017, 0) == (500).to_bytes(2, "little"))
        t = time.time()
        wait_until(lambda: len(heartbeats(bus, BATTERY, t)) >= 4, 2.5)
        p = period([ts for ts, _ in heartbeats(bus, BATTERY, t)])
        check("battery: heartbeat then about every 500 ms", p is not None and 0.4 <= p <= 0.6, p)
    guarded("battery 1017h", heartbeat_time)

    def profile_download():
        node.sdo.download(0x6053, 0, (1234).to_bytes(2, "little"))
        expedited = node.sdo.upload(0x6053, 0)
        node.sdo.download(0x6052, 0, (4321).to_bytes(2, "little"), force_segment=True)
        node.sdo.download(0x6054, 1, (600).to_bytes(2, "little"), force_segment=True)
        node.sdo.download(0x6054, 2, (9000).to_bytes(2, "little"))
        check("battery: profile objects written, expedited and segmented: 6053h 1234 Ah, "
              "6052h 4321 Ah, 6054h 600 min / day 9000",
              (expedited, node.sdo.upload(0x6052, 0), node.sdo.upload(0x6054, 1),
               node.sdo.upload(0x6054, 2))
              == tuple(v.to_bytes(2, "little") for v in (1234, 4321, 600, 9000)))
        check("battery: 6060h (read-only, a measurement) refused with 06010002h",
              aborted(lambda: node.sdo.download(0x6060, 0, b"\0\0\0\0")) == 0x06010002)
    guarded("battery profile download", profile_download)

    def tpdo_config():
        node.tpdo.read()
        t = node.tpdo[1]
        check("battery: TPDO 1 read: 181h, valid, type 255, 200 ms, 6010h/16 + 6000h/8",
              (t.cob_id, t.enabled, t.trans_type, t.event_timer,
               [(v.index, v.subindex, v.length) for v in t.map])
              == (0x181, True, 255, 200, [(0x6010, 0, 16), (0x6000, 0, 8)]))
    guarded("battery TPDO config", tpdo_config)

    def operational():
        t = time.time()
        node.nmt.state = "OPERATIONAL"
        time.sleep(1.1)
        tpdo1 = frames(bus, 0x181, t)
        check("battery: operational: TPDO 1 (181h) = ACFF01 (-10.5 degC, status 01h) every 200 ms",
              4 <= len(tpdo1) <= 7 and all(d == bytes.fromhex("ACFF01") for _, d in tpdo1)
              and 0.15 <= period([ts for ts, _ in tpdo1]) <= 0.25, tpdo1[:3])
        tpdo2 = frames(bus, 0x281, t)
        check("battery: no 2nd TPDO (281h): device type 000001A2h does not announce it",
              not tpdo2, tpdo2[:2])
        check("battery: heartbeat 701#05", heartbeats(bus, BATTERY, t)[-1:][0][1] == b"\x05")
        bus.command("#sensor temperature 200")  # 25 degC
        t = time.time()
        check("battery: a sensor change reaches TPDO 1 (C80001: 25 degC)",
              wait_until(lambda: any(d == bytes.fromhex("C80001") for _, d in frames(bus, 0x181, t)), 1))
    guarded("battery operational", operational)

    def rpdo():
        bus.send(can.Message(arbitration_id=0x201, data=b"\x05", is_extended_id=False))
        time.sleep(0.1)
        check("battery: RPDO 1 (201h) writes 6001h charger status = 05h",
              node.sdo.upload(0x6001, 0) == b"\x05")
    guarded("battery RPDO", rpdo)

    def emcy():
        node.emcy.reset()
        bus.command("#sensor status 0x101")
        got = wait_until(lambda: node.emcy.log, 1)
        e = node.emcy.log[0] if got else None
        check("battery: temperature sensor fault bit -> EMCY 5010h, register 21h",
              e is not None and (e.code, e.register) == (0x5010, 0x21),
              e and (hex(e.code), e.register))
        check("battery: 1001h = 21h, 1003h:01 = 5010h",
              node.sdo.upload(0x1001, 0) == b"\x21"
              and node.sdo.upload(0x1003, 1)[:2] == b"\x10\x50")
        bus.command("#sensor status 0x1")
        check("battery: fault cleared -> error reset EMCY 0000h",
              wait_until(lambda: any(x.code == 0 for x in node.emcy.log), 1),
              [hex(x.code) for x in node.emcy.log])
    guarded("battery EMCY", emcy)

    def nmt():
        node.nmt.state = "STOPPED"
        time.sleep(0.1)
        t = time.time()
        time.sleep(0.8)
        beats = heartbeats(bus, BATTERY, t)
        check("battery: NMT stop: heartbeat 701#04, no TPDO",
              bool(beats) and beats[-1][1] == b"\x04"
              and not frames(bus, 0x181, t) and not frames(bus, 0x281, t), beats)
        node.nmt.state = "OPERATIONAL"
        t = time.time()
        check("battery: NMT start again: TPDOs resume",
              wait_until(lambda: len(frames(bus, 0x181, t)) >= 2, 1))
        t = time.time()
        node.nmt.state = "RESET COMMUNICATION"
        check("battery: NMT reset communication: boot-up 701#00",
              wait_until(lambda: (BATTERY + 0x700, b"\x00") in
                         [(i, d) for ts, i, d in bus.seen if ts >= t], 1))
        check("battery: ... and 1017h back to 1000 ms",
              node.sdo.upload(0x1017, 0) == (1000).to_bytes(2, "little"))
        t = time.time()
        node.nmt.state = "RESET"
        check("battery: NMT reset node: boot-up 701#00",
              wait_until(lambda: (BATTERY + 0x700, b"\x00") in
                         [(i, d) for ts, i, d in bus.seen if ts >= t], 1))
        check("battery: ... pre-operational: SDO answered, no TPDO",
              node.sdo.upload(0x1000, 0) == (0x1A2).to_bytes(4, "little")
              and not frames(bus, 0x181, t))
    guarded("battery NMT", nmt)

    left_out(node, bus, "battery")

    def no_consumer():
        # The module's firmware leaves the heartbeat consumer out (only the
        # charger consumes a heartbeat in CiA 418): no 1016h.
        entry = (0x0001_07D0).to_bytes(4, "little")  # node 1, 2000 ms
        codes = (aborted(lambda: node.sdo.upload(0x1016, 0)),
                 aborted(lambda: node.sdo.upload(0x1016, 1)),
                 aborted(lambda: node.sdo.download(0x1016, 1, entry)))
        check("battery: 1016h (heartbeat-consumer not in the module's build) refused with "
              "06020000h: upload of sub 0 and 1, download of sub 1",
              codes == (0x06020000,) * 3, [c and hex(c) for c in codes])
    guarded("battery 1016h", no_consumer)

    def guarding_rtr():
        node.sdo.download(0x1017, 0, b"\x00\x00")  # heartbeat off: no 701h at all
        time.sleep(0.1)
        t = time.time()
        bus.send(can.Message(arbitration_id=0x701, is_remote_frame=True, dlc=1,
                                     is_extended_id=False))
        time.sleep(0.4)
        check("battery: node guarding RTR 701h (guarding not in this build) unanswered",
              not heartbeats(bus, BATTERY, t), heartbeats(bus, BATTERY, t))
    guarded("battery guarding", guarding_rtr)


def charger(emulate, elf, report):
    cmd = [sys.executable, emulate, elf] + (["--stack-report", report] if report else [])
    bus = PipeBus(cmd)
    net, battery_node, node, reads = charger_network(bus)
    try:
        charger_cases(bus, net, battery_node, node, reads)
    except BrokenPipeError:
        check("the emulator ran until stdin closed", False, "it exited early")
    finally:
        battery_node.nmt.stop_heartbeat()
        net.disconnect()
    return summary(bus, "charger")


def charger_cases(bus, net, battery_node, node, reads):
    booted = wait_until(lambda: frames(bus, 0x700 + CHARGER, 0), 5)
    check("charger: boot-up 70A#00", booted)
    if not booted:
        return  # the emulator's summary below says why
    net.send_message(0x700 + BATTERY, [0x00])
    battery_node.nmt.state = "OPERATIONAL"
    battery_node.nmt.start_heartbeat(200)
    check("charger: reads 1000h, 1400h:01, 1800h:01 from python-canopen's server",
          wait_until(lambda: reads[:3] == [(0x1000, 0), (0x1400, 1), (0x1800, 1)], 5), reads)
    node.nmt.state = "OPERATIONAL"
    t0 = time.time()
    time.sleep(1.2)
    tpdo = frames(bus, 0x201, t0)
    check("charger: TPDO on 201h about every 200 ms", 4 <= len(tpdo) <= 8, tpdo)
    check("charger: heartbeat reports operational (70A#05)",
          wait_until(lambda: frames(bus, 0x70A, t0)[-1:] and frames(bus, 0x70A, t0)[-1][1] == b"\x05",
                     2))
    guarded("charger SDO", lambda: check(
        "charger: 1000h = 419, 1008h segmented, 1016h:01 node 1 / 2000 ms, 1017h 1000 ms, "
        "2002h 19.5 A, 1003h:00 = 0",
        (node.sdo.upload(0x1000, 0), node.sdo.upload(0x1008, 0), node.sdo.upload(0x1016, 1),
         node.sdo.upload(0x1017, 0), node.sdo.upload(0x2002, 0), node.sdo.upload(0x1003, 0))
        == ((419).to_bytes(4, "little"), b"canopen-codec charger", bytes([0xD0, 0x07, 0x01, 0]),
            (1000).to_bytes(2, "little"), (19 * 256 + 128).to_bytes(2, "little"), b"\x00")))
    guarded("charger 2006h", lambda: check(
        "charger: 2006h is read-only (06010002h)",
        aborted(lambda: node.sdo.download(0x2006, 0, b"\x00\x00")) == 0x06010002))
    battery_node.nmt.stop_heartbeat()
    t1 = time.time()
    lost = wait_until(lambda: len(node.emcy.log) >= 1, 4)
    e = node.emcy.log[0] if lost else None
    check("charger: battery heartbeat lost -> EMCY 8130h, 01h, Delta-Q E-0-3-2 (20 80)",
          e is not None and (e.code, e.register, bytes(e.data[:2])) == (0x8130, 1, b"\x20\x80"),
          e and (hex(e.code), e.register, bytes(e.data).hex()))
    check("charger: after the 2000 ms consumer time",
          e is not None and 1.6 <= e.timestamp - t1 <= 3.5, e and e.timestamp - t1)
    gone = wait_until(lambda: len(node.emcy.log) >= 2, 2)
    g = node.emcy.log[1] if gone else None
    check("charger: module gone -> EMCY 8130h, Delta-Q E-0-3-0 (1E 80) right after",
          g is not None and (g.code, bytes(g.data[:2])) == (0x8130, b"\x1e\x80")
          and g.timestamp - e.timestamp < 0.5, g and (hex(g.code), bytes(g.data).hex()))
    time.sleep(1.2)
    check("charger: TPDOs stop", not frames(bus, 0x201, time.time() - 0.5))
    hb = frames(bus, 0x70A, time.time() - 1.1)
    check("charger: left operational (70A#7F)", hb and hb[-1][1] == b"\x7f", hb)
    guarded("charger 1003h", lambda: check(
        "charger: 1003h:01 = 1E808130h, 1003h:02 = 20808130h (Delta-Q byte order)",
        (node.sdo.upload(0x1003, 1), node.sdo.upload(0x1003, 2))
        == ((0x1E808130).to_bytes(4, "little"), (0x20808130).to_bytes(4, "little"))))
    net.send_message(0x700 + BATTERY, [0x00])
    battery_node.nmt.start_heartbeat(200)
    check("charger: battery back: reconfigured, error reset EMCY 0000h",
          wait_until(lambda: any(x.code == 0 for x in node.emcy.log), 5)
          and reads.count((0x1000, 0)) == 2, ([hex(x.code) for x in node.emcy.log], reads))
    node.nmt.state = "OPERATIONAL"
    t2 = time.time()
    check("charger: started again, TPDOs resume", wait_until(lambda: len(frames(bus, 0x201, t2)) >= 2, 1))
    # The battery's EMCY (temperature sensor fault): the firmware's policy
    # reaction writes OUTPUT_STOP, which the emulator reports at exit.
    battery_node.emcy.send(0x5010, 0x21)
    time.sleep(0.3)
    left_out(node, bus, "charger")


def summary(bus, name):
    """The emulator's exit summary; its stack figure (None when missing)."""
    deadline = time.time() + 5
    while time.time() < deadline and bus.proc.poll() is None:
        time.sleep(0.05)
    time.sleep(0.2)  # the stderr reader drains the pipe
    lines = bus.lines("emulate:")
    for line in lines:
        print(f"  {line}")
    check(f"{name}: the emulated firmware ran to stdin EOF without a fault",
          bus.proc.returncode == 0 and not any("FAILED" in l for l in lines), lines[-2:])
    check(f"{name}: stack high-water mark + .data/.bss fit the RAM of memory.x",
          any("stack high-water mark" in l and l.endswith("(fits)") for l in lines), lines)
    return lines


def main():
    args = sys.argv[1:]
    report = None
    if "--stack-report" in args:
        i = args.index("--stack-report")
        report = args[i + 1]
        del args[i:i + 2]
    if len(args) != 3:
        sys.exit(__doc__.rsplit("usage: ", 1)[1])
    emulate, battery_elf, charger_elf = args
    skip_optional()
    battery(emulate, battery_elf, report)
    lines = charger(emulate, charger_elf, report)
    check("charger: the battery's EMCY made the firmware write its stop output (OUTPUT_STOP)",
          any(l.startswith("emulate: OUTPUT_STOP writes:") and not l.endswith(" 0")
              for l in lines), lines)
    CASES.finish()


if __name__ == "__main__":
    main()
