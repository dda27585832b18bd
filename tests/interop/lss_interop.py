#!/usr/bin/env python3
"""Interop of LSS (CiA 305, "Layer setting services and protocol") between
python-canopen's LSS master (`network.lss`) and the virtual CiA 418
battery module (examples/battery_module) started without a node-ID
(`--lss --node-id 255`).

The module must stay silent until configured; python-canopen finds it by
fastscan (its 128-bit LSS address is the module's 1018h identity), inquires
its node-ID and serial number, gives it node-ID 5 (an out-of-range node-ID
is refused with error 1), stores the configuration and switches it back to
waiting state; the module then boots up as node 5 and serves SDO there. A
second fastscan finds nobody, and switch state selective with the address
reaches the now configured module.

usage: lss_interop.py PATH/TO/battery_module
"""

import sys
import time

import canopen
from canopen import lss
from pipebus import Cases, PipeBus

IDENTITY = (0x0000029A, 0x00000418, 0x00010000, 0x00000007)
NEW_NODE = 5

ARGS = [
    "--lss", "--node-id", "255",
    "--identity", ",".join(f"{v:X}" for v in IDENTITY),
    "--heartbeat-ms", "100",
    "--linger-ms", "0",
]

CASES = Cases()
check = CASES.check
guarded = CASES.guarded


def succeeds(fn):
    """True when `fn()` returns without an LSS error (no answer included)."""
    try:
        fn()
        return True
    except lss.LssError as e:
        print(f"     {e}")
        return False


def main():
    exe = sys.argv[1]
    bus = PipeBus([exe] + ARGS)
    net = canopen.Network(bus)
    net.connect()
    # The pipe answers within milliseconds; every fastscan bit that is 1 waits
    # for one timeout.
    net.lss.RESPONSE_TIMEOUT = 0.2
    try:
        run(bus, net)
    finally:
        net.disconnect()
    CASES.finish()


def run(bus, net):
    m = net.lss
    time.sleep(0.5)
    check("a module without a node-ID sends nothing (no boot-up, no heartbeat)",
          bus.seen == [], bus.seen[:3])

    def fastscan():
        m.send_switch_state_global(m.WAITING_STATE)
        found, address = m.fast_scan()
        check("fast_scan() finds the module", found, address)
        check("fast_scan() reads its LSS address = 1018h identity",
              address is not None and tuple(address) == IDENTITY,
              address and [hex(v) for v in address])
    guarded("fastscan", fastscan)

    def inquire():
        check("inquire_node_id() after fastscan: 255 (not configured)",
              m.inquire_node_id() == 255)
        check("inquire serial number",
              m.inquire_lss_address(lss.CS_INQUIRE_SERIAL_NUMBER) == IDENTITY[3])
        check("inquire vendor-ID",
              m.inquire_lss_address(lss.CS_INQUIRE_VENDOR_ID) == IDENTITY[0])
    guarded("inquire", inquire)

    def configure():
        try:
            m.configure_node_id(200)
            refused = False
        except lss.LssError as e:
            refused = "1" in str(e)
        check("configure_node_id(200) is refused with error 1 (out of range)", refused)
        check("configure_node_id(5) succeeds",
              succeeds(lambda: m.configure_node_id(NEW_NODE)))
        check("the node-ID is pending: inquire still answers 255",
              m.inquire_node_id() == 255)
        check("store_configuration() succeeds", succeeds(m.store_configuration))
    guarded("configure", configure)

    def boot():
        t = time.time()
        m.send_switch_state_global(m.WAITING_STATE)
        deadline = t + 2
        while time.time() < deadline:
            if any(i == 0x700 + NEW_NODE for _, i, _ in bus.seen):
                break
            time.sleep(0.02)
        hb = [d for ts, i, d in bus.seen if i == 0x700 + NEW_NODE]
        check("switched to waiting, the module boots up as node 5 (705#00)",
              bool(hb) and hb[0] == b"\x00", hb[:2])
        time.sleep(0.35)
        hb = [d for ts, i, d in bus.seen if i == 0x700 + NEW_NODE]
        check("then heartbeats pre-operational (7Fh) every 100 ms as node 5",
              len(hb) >= 3 and all(d == b"\x7f" for d in hb[1:]), hb[:4])
        node = net.add_node(NEW_NODE, canopen.ObjectDictionary())
        node.sdo.RESPONSE_TIMEOUT = 2.0
        serial = int.from_bytes(node.sdo.upload(0x1018, 4), "little")
        check("SDO upload 1018h:04 from node 5 reads the serial number",
              serial == IDENTITY[3], hex(serial))
    guarded("boot", boot)

    def again():
        found, address = m.fast_scan()
        check("a second fast_scan() finds nobody (the module is configured)",
              not found, address)
        check("switch state selective with the LSS address reaches the module",
              m.send_switch_state_selective(*IDENTITY))
        check("inquire_node_id() now answers 5", m.inquire_node_id() == NEW_NODE)
        m.send_switch_state_global(m.WAITING_STATE)
    guarded("again", again)

    time.sleep(0.1)
    events = bus.stderr_lines
    check("the module reported the LSS services in words",
          "event: LSS node-ID 5 configured (active after reset communication)" in events
          and "event: LSS store configuration (node-ID 5): ok" in events
          and "event: LSS reset communication under the new node-ID" in events, events[-6:])


if __name__ == "__main__":
    main()
