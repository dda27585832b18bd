#!/usr/bin/env python3
"""Node guarding between python-canopen, as the NMT master, and the virtual
CiA 418 battery module (examples/battery_module), through candump lines on a
pipe (PipeBus).

python-canopen's `node.nmt.start_node_guarding(period)` sends a remote
request on 700h + node every period; it reads the replies as it reads
heartbeats (state in bits 6-0, toggle masked). It checks neither the toggle
nor the node life time, so this script checks those on the frames the
module sent:

- while the module produces heartbeats (1017h = 1000 ms, its default),
  remote requests are not answered (CiA 301: heartbeat and node guarding
  are exclusive);
- with 1017h, 100Ch and 100Dh written over SDO (0, 100 ms, 3), every request
  is answered with one byte: the NMT state (7Fh pre-operational, 05h
  operational, 04h stopped) and a toggle bit that starts at 0 and alternates;
  python-canopen's `node.nmt.state` follows the replies;
- when python-canopen stops guarding, the module reports its life guarding
  event within the node life time (300 ms) and resumes at the next request;
- reset communication restores 1017h (heartbeat again, no more replies).

usage: guarding_interop.py PATH/TO/battery_module
"""

import sys
import time

import canopen
from canopen.objectdictionary import ObjectDictionary, ODVariable
from canopen.objectdictionary.datatypes import UNSIGNED8, UNSIGNED16
from pipebus import Cases, PipeBus

NODE = 7
GUARD_S = 0.1

CASES = Cases()
check = CASES.check
guarded = CASES.guarded


def var(name, index, data_type):
    v = ODVariable(name, index, 0)
    v.data_type = data_type
    v.access_type = "rw"
    return v


def dictionary():
    od = ObjectDictionary()
    od.add_object(var("Guard time", 0x100C, UNSIGNED16))
    od.add_object(var("Life time factor", 0x100D, UNSIGNED8))
    od.add_object(var("Producer heartbeat time", 0x1017, UNSIGNED16))
    return od


def frames_from(bus, since):
    """The module's frames on 700h + node since `since`."""
    return [d for t, i, d in bus.seen if i == 0x700 + NODE and t >= since]


def requests_since(bus, since):
    return [l for t, l in bus.sent if t >= since and l == f"{0x700 + NODE:03X}#R"]


def guard_for(node, bus, seconds):
    """Guards for `seconds`; returns (requests sent, replies received)."""
    start = time.time()
    node.nmt.start_node_guarding(GUARD_S)
    time.sleep(seconds)
    node.nmt.stop_node_guarding()
    time.sleep(0.1)  # the last reply
    return requests_since(bus, start), frames_from(bus, start)


def alternates(replies):
    return all(((b[0] >> 7) & 1) == i % 2 for i, b in enumerate(replies))


def main():
    exe = sys.argv[1]
    bus = PipeBus([exe, "--node-id", str(NODE), "--linger-ms", "0"])
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
    end = time.time() + 5
    while time.time() < end and not frames_from(bus, 0):
        time.sleep(0.01)
    check("boot-up message seen", frames_from(bus, 0)[:1] == [b"\x00"], frames_from(bus, 0)[:3])

    def exclusive():
        requests, frames = guard_for(node, bus, 0.55)
        # Only heartbeats (7Fh, toggle 0, once a second) may appear.
        check("heartbeat on (1017h = 1000 ms): guarding requests are not answered",
              len(requests) >= 4 and len(frames) <= 1 and all(f == b"\x7f" for f in frames),
              (len(requests), frames))
    guarded("exclusive", exclusive)

    def configure():
        node.sdo["Producer heartbeat time"].raw = 0
        node.sdo["Guard time"].raw = 100
        node.sdo["Life time factor"].raw = 3
        got = (node.sdo["Producer heartbeat time"].raw, node.sdo["Guard time"].raw,
               node.sdo["Life time factor"].raw)
        check("1017h, 100Ch, 100Dh written and read back over SDO (0, 100, 3)",
              got == (0, 100, 3), got)
    guarded("configure", configure)

    def pre_operational():
        requests, replies = guard_for(node, bus, 0.55)
        check("every request answered with one byte", len(replies) == len(requests)
              and len(requests) >= 4 and all(len(r) == 1 for r in replies),
              (len(requests), replies))
        check("pre-operational replies: state 7Fh, toggle 0 first and alternating",
              all(r[0] & 0x7F == 0x7F for r in replies) and alternates(replies),
              [r.hex() for r in replies])
        check("python-canopen reads the state from the replies",
              node.nmt.state == "PRE-OPERATIONAL", node.nmt.state)
        return replies
    guarded("pre-operational", pre_operational)

    def operational():
        before = frames_from(bus, 0)
        toggle_next = 0 if not before else ((before[-1][0] >> 7) ^ 1)
        node.nmt.state = "OPERATIONAL"
        time.sleep(0.05)
        requests, replies = guard_for(node, bus, 0.55)
        check("operational replies: state 05h, the toggle goes on alternating",
              bool(replies) and all(r[0] & 0x7F == 0x05 for r in replies)
              and all(((r[0] >> 7) & 1) == (toggle_next + i) % 2 for i, r in enumerate(replies)),
              [r.hex() for r in replies])
        check("python-canopen: OPERATIONAL", node.nmt.state == "OPERATIONAL", node.nmt.state)
        node.nmt.state = "STOPPED"
        time.sleep(0.05)
        _, stopped = guard_for(node, bus, 0.35)
        check("stopped: still answered, state 04h",
              bool(stopped) and all(r[0] & 0x7F == 0x04 for r in stopped),
              [r.hex() for r in stopped])
        node.nmt.state = "PRE-OPERATIONAL"
    guarded("operational", operational)

    def life_guarding():
        # guard_for stopped guarding: the module must report it within
        # 300 ms of the last request (give the pipe some slack).
        start = time.time()
        lost = []
        while time.time() < start + 1.0 and not lost:
            lost = [l for l in bus.stderr_lines if "life guarding: LifeGuardingLost" in l]
            time.sleep(0.02)
        check("master stopped: the module reports the life guarding event", bool(lost),
              bus.stderr_lines[-3:])
        guard_for(node, bus, 0.25)
        resumed = [l for l in bus.stderr_lines if "life guarding: LifeGuardingResumed" in l]
        check("guarding again: the module reports it resumed", bool(resumed), bus.stderr_lines[-3:])
    guarded("life guarding", life_guarding)

    def reset_communication():
        start = time.time()
        node.nmt.state = "RESET COMMUNICATION"
        time.sleep(0.1)
        check("reset communication: boot-up message", frames_from(bus, start)[:1] == [b"\x00"],
              frames_from(bus, start)[:3])
        requests, frames = guard_for(node, bus, 0.45)
        check("after the reset 1017h is 1000 ms again: requests not answered",
              len(requests) >= 3 and all(f == b"\x7f" for f in frames), (len(requests), frames))
        check("1017h reads 1000 ms", node.sdo["Producer heartbeat time"].raw == 1000)
    guarded("reset communication", reset_communication)


if __name__ == "__main__":
    main()
