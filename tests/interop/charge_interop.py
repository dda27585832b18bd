#!/usr/bin/env python3
"""The virtual charger and battery module charge, with python-canopen on
the other end (issue: the real-time programs use the same machines).

1. python-canopen plays the BMS against our charger in remote mode, as
   ICL1500 bring-up scripts do: it loads the charger's own EDS
   (`charger --print-eds`), remaps the charger's first RPDO by SDO to
   6000h battery status, 6070h current request and 2271h voltage request,
   sends the battery's heartbeat, starts the charger, then sends the RPDO
   every 200 ms. It checks that no charge flows before the module is ready,
   that 2002h (the output current), 2006h (charger enabled, AC present,
   override external), 6001h bit 0 and the TPDO follow the request, a
   lower request and a lower voltage limit, that "not ready" stops the
   charge, and that when the heartbeat stops the charge stops and the
   charger raises E-0-3-2 (EMCY 8130h, Delta-Q code 8020h).
2. python-canopen plays the charger against our battery module
   (`--simulate`: the pack model): it reads the model's 6020h, 6060h,
   6010h, 6081h and 6070h by SDO, enables the module's TPDOs, then sends
   the module's second RPDO (6001h charger status, 6052h Ah returned) as a
   charger does, the Ah rising as if 25 A flowed, and checks that the
   state of charge (6081h by SDO and in the TPDO) and the voltage rise by
   what was returned, and that the module asks less current near full.

Both programs run in real time (--speed 1, python-canopen's timers are the
wall clock's), except the module in the second part, run at --speed 200
with python's Ah rising 200 times as fast, which keeps the run short.

usage: charge_interop.py PATH/TO/charger PATH/TO/battery_module
"""

import os
import subprocess
import sys
import tempfile
import time

import canopen
from pipebus import Cases, PipeBus, frames, wait_until

CHARGER = 10
BATTERY = 1

CASES = Cases()
check = CASES.check


def u16(node, index, sub=0):
    return int.from_bytes(node.sdo.upload(index, sub), "little")


def bms_against_charger(exe):
    args = ["--mode", "remote", "--no-configure", "--node-id", str(CHARGER),
            "--battery-node", str(BATTERY), "--pack-soc", "30"]
    eds = subprocess.run([exe, *args, "--print-eds"], check=True, capture_output=True, text=True).stdout
    with tempfile.NamedTemporaryFile("w", suffix=".eds", delete=False) as f:
        f.write(eds)
        eds_path = f.name
    bus = PipeBus([exe, *args, "--linger-ms", "0"])
    net = canopen.Network(bus)
    net.connect()
    heartbeat = None
    try:
        charger = canopen.RemoteNode(CHARGER, eds_path)
        net.add_node(charger)
        charger.sdo.RESPONSE_TIMEOUT = 2.0
        check("the charger boots (70A#00)", wait_until(lambda: frames(bus, 0x700 + CHARGER, 0), 3))
        # The remap, by python-canopen's PDO API: 1400h:01 not valid,
        # 1600h:00 = 0, the entries, 1600h:00 = 3, 1400h:01 valid.
        charger.rpdo.read()
        rpdo = charger.rpdo[1]
        rpdo.clear()
        rpdo.add_variable(0x6000)
        rpdo.add_variable(0x6070)
        rpdo.add_variable(0x2271)
        rpdo.cob_id = 0x200 + CHARGER
        rpdo.trans_type = 255
        rpdo.enabled = True
        rpdo.save()
        entries = [int.from_bytes(charger.sdo.upload(0x1600, s), "little") for s in range(4)]
        check("1600h reads back 3 entries: 6000h/8, 6070h/16, 2271h/32",
              entries == [3, 0x60000008, 0x60700010, 0x22710020], [hex(e) for e in entries])
        check("1400h:01 = 20Ah, valid", u16(charger, 0x1400, 1) == 0x20A)
        # The module's heartbeat every 200 ms; the charger started.
        heartbeat = net.send_periodic(0x700 + BATTERY, [0x05], 0.2)
        check("the charger finds the module", wait_until(
            lambda: any("battery module found" in l for l in bus.stderr_lines), 3), bus.stderr_lines[-5:])
        charger.nmt.state = "OPERATIONAL"
        time.sleep(0.5)

        def send(ready, amps, volts):
            rpdo[0x6000].raw = 1 if ready else 0
            rpdo[0x6070].raw = round(amps * 16)
            rpdo[0x2271].raw = round(volts * 1024)
            rpdo.transmit()

        def rpdo_task(ready, amps, volts):
            send(ready, amps, volts)
            rpdo.start(0.2)

        def amps():
            return u16(charger, 0x2002) / 256

        status = u16(charger, 0x2006)
        check("before a request: 2002h = 0 A, 2006h charger not enabled",
              amps() == 0 and not status & 0x20, (amps(), hex(status)))
        rpdo_task(False, 10.0, 72.0)
        time.sleep(1.5)
        check("heartbeat and a 10 A request, but 6000h not ready: no charge",
              amps() == 0 and not u16(charger, 0x6001) & 1, amps())
        rpdo.stop()
        rpdo_task(True, 10.0, 72.0)
        check("ready, 10 A requested: 2002h follows to 10 A",
              wait_until(lambda: abs(amps() - 10.0) < 0.1, 4), amps())
        status = u16(charger, 0x2006)
        check("2006h: charger enabled, AC present, override external (0070h)", status & 0xF0 == 0x70, hex(status))
        check("6001h bit 0 set", u16(charger, 0x6001) & 1 == 1)
        t = time.time()
        time.sleep(0.7)
        tpdo = frames(bus, 0x180 + CHARGER, t)
        check("TPDO 0 (18Ah) reports 6001h = 01", tpdo and all(d == b"\x01" for _, d in tpdo), tpdo)
        rpdo.stop()
        rpdo_task(True, 4.5, 72.0)
        check("4.5 A requested: 2002h follows", wait_until(lambda: abs(amps() - 4.5) < 0.1, 4), amps())
        # A voltage limit below the battery: the charge is held at it.
        volts = u16(charger, 0x2101) / 256
        rpdo.stop()
        rpdo_task(True, 4.5, volts - 2.0)
        check(f"a voltage limit below the battery's {volts:.1f} V: the current falls to 0",
              wait_until(lambda: amps() < 0.1, 4), amps())
        rpdo.stop()
        rpdo_task(True, 8.0, 72.0)
        check("8 A at 72 V again: 2002h follows", wait_until(lambda: abs(amps() - 8.0) < 0.1, 4), amps())
        rpdo.stop()
        rpdo_task(False, 8.0, 72.0)
        check("6000h not ready: the charge stops", wait_until(lambda: amps() == 0, 3), amps())
        rpdo.stop()
        rpdo_task(True, 8.0, 72.0)
        check("ready again: it resumes", wait_until(lambda: abs(amps() - 8.0) < 0.1, 4), amps())
        # The module's heartbeat stops (the RPDO keeps coming).
        heartbeat.stop()
        heartbeat = None
        t1 = time.time()
        lost = wait_until(lambda: len(charger.emcy.log) >= 1, 4)
        e = charger.emcy.log[0] if lost else None
        check("heartbeat lost: EMCY 8130h, Delta-Q E-0-3-2 (20 80 ...)",
              e is not None and e.code == 0x8130 and bytes(e.data[:2]) == b"\x20\x80",
              e and (hex(e.code), bytes(e.data).hex()))
        check("raised after the 2000 ms consumer time", e is not None and 1.6 <= e.timestamp - t1 <= 3.5,
              e and e.timestamp - t1)
        check("the charge stops: 2002h = 0, 6001h bit 0 clear",
              wait_until(lambda: amps() == 0 and not u16(charger, 0x6001) & 1, 2), amps())
        rpdo.stop()
        events = [l for l in bus.stderr_lines if l.startswith("event: charge phase")]
        check("the charger reported its phases in words", any("-> remote" in l for l in events), events)
    finally:
        if heartbeat is not None:
            heartbeat.stop()
        net.disconnect()
        os.unlink(eds_path)


def charger_against_module(exe):
    speed = 200
    args = ["--node-id", str(BATTERY), "--simulate", "--speed", str(speed), "--capacity-ah", "40",
            "--max-current-a", "25", "--cells", "24", "--soc", "40", "--linger-ms", "0"]
    bus = PipeBus([exe, *args])
    net = canopen.Network(bus)
    net.connect()
    try:
        module = canopen.RemoteNode(BATTERY, canopen.ObjectDictionary())
        net.add_node(module)
        module.sdo.RESPONSE_TIMEOUT = 2.0
        check("the module boots (701#00)", wait_until(lambda: frames(bus, 0x700 + BATTERY, 0), 3))
        check("1000h: CiA 418 with every optional PDO (000F01A2h)",
              int.from_bytes(module.sdo.upload(0x1000, 0), "little") == 0x000F01A2)
        check("6020h: lead acid (10h), 40 Ah, 25 A, 24 cells",
              [module.sdo.upload(0x6020, s) for s in (1, 2, 3, 4)] ==
              [b"\x10", (40).to_bytes(2, "little"), (25).to_bytes(2, "little"), (24).to_bytes(2, "little")])
        soc0 = module.sdo.upload(0x6081, 0)[0]
        v0 = int.from_bytes(module.sdo.upload(0x6060, 0), "little") / 1024
        check("6081h = 40 %", soc0 == 40, soc0)
        check(f"6060h = {v0:.2f} V, the model's rest voltage of 24 lead-acid cells at 40 %",
              47.5 < v0 < 49.5, v0)
        check("6010h = 25 degC", int.from_bytes(module.sdo.upload(0x6010, 0), "little", signed=True) == 200)
        # The BMS asks what the pack accepts (its charge acceptance), at
        # most the pack's 25 A maximum charge current (6070h in 1/16 A).
        request = u16(module, 0x6070)
        check(f"6070h = {request / 16:.2f} A requested, at most the pack's 25 A",
              0 < request <= 25 * 16, request)
        check("6000h = 01 ready", module.sdo.upload(0x6000, 0) == b"\x01")
        module.nmt.state = "OPERATIONAL"
        # The charger: 6001h charging, 6052h rising as the current the
        # module asks for (6070h, in its TPDO 3 at 381h) flows, in the
        # module's (x200) time.
        def asked_now():
            tpdo = frames(bus, 0x380 + BATTERY, 0)
            return int.from_bytes(tpdo[-1][1][0:2], "little") / 16 if tpdo else 0.0

        returned = [0.0]

        def deliver(seconds):
            end = time.time() + seconds
            last = time.time()
            while time.time() < end:
                time.sleep(0.05)
                now = time.time()
                returned[0] += asked_now() * (now - last) * speed / 3600
                last = now
                eighths = int(returned[0] * 8)
                net.send_message(0x300 + BATTERY, bytes([0x01]) + eighths.to_bytes(2, "little"))

        deliver(6.0)
        time.sleep(0.5)
        ah = int(returned[0] * 8) / 8
        soc1 = module.sdo.upload(0x6081, 0)[0]
        v1 = int.from_bytes(module.sdo.upload(0x6060, 0), "little") / 1024
        want = 40 + ah / 40 * 100
        check(f"{ah:.2f} Ah returned into 40 Ah: 6081h rises from 40 % to about {want:.0f} %",
              ah > 5 and abs(soc1 - want) <= 2, (ah, soc1, want))
        check(f"6060h rises ({v0:.2f} V -> {v1:.2f} V)", v1 > v0 + 0.3, (v0, v1))
        t = time.time()
        time.sleep(1.2)
        tpdo3 = frames(bus, 0x380 + BATTERY, t)
        check("TPDO 3 (381h: 6070h, 6081h) carries the new state of charge",
              tpdo3 and abs(tpdo3[-1][1][2] - soc1) <= 1, tpdo3[-1:])
        # Near full the BMS holds the pack at its CV limit: it asks less,
        # and the charge tapers. Lead acid stores less than it is given
        # (its charge efficiency, gassing near full): 19 Ah returned into
        # the 40 Ah pack from 40 % leave it near 80 %, not 87 %.
        deliver(12.0)
        asked = u16(module, 0x6070) / 16
        soc2 = module.sdo.upload(0x6081, 0)[0]
        ready = module.sdo.upload(0x6000, 0)
        check(f"near full ({soc2} %) the module asks less than 25 A ({asked:.2f} A), still ready",
              0 < asked < 24.0 and soc2 > 75 and ready == b"\x01", (soc2, asked, ready))
        temperature = int.from_bytes(module.sdo.upload(0x6010, 0), "little", signed=True) / 8
        check(f"the pack warmed with I2R ({temperature:.1f} degC) below the BMS's 50 degC limit",
              25.0 < temperature < 50.0, temperature)
        check("the pack was reported on stderr", bus.lines("pack:"), bus.stderr_lines[-3:])
    finally:
        net.disconnect()


def main():
    charger_exe, module_exe = sys.argv[1], sys.argv[2]
    CASES.guarded("python-canopen BMS against the charger (remote mode)", lambda: bms_against_charger(charger_exe))
    CASES.guarded("python-canopen charger against the battery module",
                  lambda: charger_against_module(module_exe))
    CASES.finish()


if __name__ == "__main__":
    main()
