#!/usr/bin/env python3
"""Runs a footprint firmware ELF (the battery module or the charger of
examples/firmware) on an emulated Cortex-M4 and puts it on a candump-line
pipe, like the host example programs: every candump log line read from
stdin goes into the CAN receive mailbox, every frame the firmware sends
through the transmit mailbox comes out on stdout as a candump log line.
It also measures the firmware's stack.

    python3 examples/firmware/emulate.py ELF [--stack-report FILE] [--interface NAME]
                                         [--no-count] [--profile N]

The CPU is unicorn's (pip install unicorn): Thumb-2, M-class, CPU model
Cortex-M4. The ELF (read with pyelftools) is loaded at its load addresses
into the FLASH and RAM regions that memory.x beside this file gives, the
initial SP and the reset vector come from the vector table, and the
firmware boots through cortex-m-rt's reset handler (.data copied, .bss
zeroed, the FPU enabled through CPACR in the system control space, which
is mapped as plain memory: unicorn's Cortex-M4 runs floating-point
instructions whether or not CPACR enables them, and the firmware has none).

The peripherals of the firmware (src/lib.rs and the nodes' */src/main.rs) are served
by unicorn's MMIO callbacks on their three pages only (no per-instruction
hook):

- CAN mailbox at 4000_6400h: a frame read from stdin is put into the
  receive mailbox once the firmware has released the previous one
  (RX_STATUS bit 0 clear); a write of 1 to TX_STATUS prints the transmit
  mailbox as a candump line. The transmit mailbox is always free.
- Timer at 4000_0024h: the wall-clock microseconds since start (mod 2^32),
  so a peer's timeouts and the heartbeat and PDO periods are real time.
- Sensor block at 4001_2400h, fixed plausible values until a command line
  changes them (see SENSORS below):
  battery module: voltage 52736 (51.5 V in 1/1024 V), temperature -84
  (-10.5 degC in 1/8 degC), state of charge 73 %, status 01h (bit 0 ready
  to charge; bit 8 is the temperature sensor fault);
  charger: current 4992 (19.5 A in 1/256 A), battery voltage 12288 (48 V
  in 1/256 V), AC voltage 58880 (230 V in 1/256 V), status 01h; writes to
  OUTPUT_STOP (4001_2410h) are recorded and reported at exit.

A stdin line starting with '#' is a command for the emulator, not a frame,
applied in order with the frames:

    #sensor NAME VALUE     set a sensor register (NAME as in SENSORS, VALUE
                           decimal or 0x hex), e.g. `#sensor status 0x101`

While the firmware polls an empty receive mailbox with nothing to read the
emulator waits up to half a millisecond for input, so an idle node does not
spin a host core.

Stack measurement: before reset the RAM between the end of .bss
(`_stack_end`) and the top of the stack (`_stack_start`) is painted with a
pattern word; the lowest word that no longer holds it gives the stack's
high-water mark. It is taken twice: when the main loop first polls the
receive mailbox (the boot's mark; the paint is then renewed below the live
SP, there being no interrupts) and at exit (the main loop's mark); the
larger is the firmware's.

Instructions: a basic-block hook adds up each block's instructions
(counted once per block from its Thumb encodings) to give the instructions
run per received frame (from the read of RX_STATUS that delivers a frame
to the next read of RX_STATUS: handling, transmission and the rest of that
loop turn) and per loop turn without a frame. The hook halves the
emulator's speed (about 5 million instructions a second instead of 12 on
a CI machine, some 1600 SDO requests a second); --no-count leaves it
out. --profile N prints the N functions (by symbol, innermost only) that
ran the most instructions after boot, with their share and instructions
per loop turn.

unicorn stops at YIELD (the hint `core::hint::spin_loop` emits) as an
invalid instruction; the emulator steps over it as the hardware would.

On stdin EOF the emulator stops once the receive mailbox is empty, prints a
summary to stderr (frames in and out, stack high-water mark, RAM use,
instructions per frame) and, with --stack-report FILE, appends the
line `node stack_bytes` to FILE (one line per run, so the runs of both
nodes can share a file). It exits 1 when the firmware faults or stops
touching its peripherals for 2 s (a panic halts in a loop), printing the PC.
"""

import argparse
import bisect
import collections
import os
import queue
import re
import sys
import threading
import time

from elftools.elf.elffile import ELFFile
from elftools.elf.sections import SymbolTableSection
from unicorn import (UC_ARCH_ARM, UC_HOOK_BLOCK, UC_MODE_MCLASS, UC_MODE_THUMB, UC_PROT_ALL,
                     Uc, UcError)
from unicorn.arm_const import UC_ARM_REG_PC, UC_ARM_REG_SP, UC_CPU_ARM_CORTEX_M4

HERE = os.path.dirname(os.path.abspath(__file__))

CAN_PAGE = 0x4000_6000
CAN_BASE = 0x4000_6400
TIMER_PAGE = 0x4000_0000
TIMER_COUNT = 0x4000_0024
SENSOR_PAGE = 0x4001_2000
SENSOR_BASE = 0x4001_2400
SCS_BASE = 0xE000_E000  # system control space (SCB CPACR at E000_ED88h)
PAGE = 0x1000

# Register offsets in the CAN page (4000_6400h + the offsets of src/lib.rs).
RX_STATUS, RX_ID, RX_DLC, RX_DATA_LO, RX_DATA_HI = 0x400, 0x404, 0x408, 0x40C, 0x410
TX_STATUS, TX_ID, TX_DLC, TX_DATA_LO, TX_DATA_HI = 0x420, 0x424, 0x428, 0x42C, 0x430
ID_EXTENDED = 1 << 31
ID_REMOTE = 1 << 30

# Sensor registers per node (offset from 4001_2400h, name, start value).
SENSORS = {
    "battery_module": [(0x0, "voltage", 52736), (0x4, "temperature", -84 & 0xFFFF_FFFF),
                       (0x8, "soc", 73), (0xC, "status", 0x01)],
    "charger": [(0x0, "current", 4992), (0x4, "voltage", 12288), (0x8, "ac_voltage", 58880),
                (0xC, "status", 0x01), (0x10, "output_stop", 0)],
}
# The ELF symbol of each node's state (size.sh uses the same).
STATE_SYMBOL = {"battery_module": "BATTERY_MODULE_STATE", "charger": "CHARGER_STATE"}

PAINT = 0x5AA5_C33C
YIELD = 0xBF10
WATCHDOG_S = 2.0
IDLE_WAIT_S = 0.0005

LINE = re.compile(r"^(?:\(\d+(?:\.\d+)?\)\s+)?(?:\S+\s+)?([0-9A-Fa-f]{3}|[0-9A-Fa-f]{8})#"
                  r"(R[0-8]?|(?:[0-9A-Fa-f]{2}){0,8})$")


def memory_regions(path):
    """FLASH and RAM (origin, length) from memory.x."""
    text = open(path, encoding="utf-8").read()
    regions = {}
    for m in re.finditer(r"(\w+)\s*(?:\([^)]*\))?\s*:\s*ORIGIN\s*=\s*(0x[0-9A-Fa-f_]+|\d+)\s*,"
                         r"\s*LENGTH\s*=\s*(\d+)\s*([KM]?)", text):
        name, origin, length, unit = m.groups()
        regions[name] = (int(origin.replace("_", ""), 0),
                         int(length) * {"": 1, "K": 1024, "M": 1024 * 1024}[unit])
    return regions["FLASH"], regions["RAM"]


def parse_line(line):
    """A candump log line -> (raw id word, dlc, data bytes), or None."""
    m = LINE.match(line.strip())
    if not m:
        return None
    ident = int(m.group(1), 16)
    raw = ident | (ID_EXTENDED if len(m.group(1)) == 8 else 0)
    body = m.group(2)
    if body.startswith("R"):
        return raw | ID_REMOTE, int(body[1:] or "0"), b""
    data = bytes.fromhex(body)
    return raw, len(data), data


def thumb_instructions(code):
    """How many Thumb instructions `code` (a basic block) holds."""
    count, i = 0, 0
    while i + 1 < len(code):
        half = code[i] | code[i + 1] << 8
        i += 4 if half >> 11 in (0b11101, 0b11110, 0b11111) else 2
        count += 1
    return count


class Firmware:
    """One firmware ELF on the emulated Cortex-M4 with its peripherals."""

    def __init__(self, elf_path, interface, count=True, profile=False):
        self.interface = interface
        (self.flash_base, self.flash_len), (self.ram_base, self.ram_len) = \
            memory_regions(os.path.join(HERE, "memory.x"))
        with open(elf_path, "rb") as f:
            elf = ELFFile(f)
            self.symbols = {}
            self.sizes = {}
            self.functions = []
            for sec in elf.iter_sections():
                if isinstance(sec, SymbolTableSection):
                    for s in sec.iter_symbols():
                        self.symbols[s.name] = s["st_value"]
                        self.sizes[s.name] = s["st_size"]
                        if s["st_info"]["type"] == "STT_FUNC":
                            self.functions.append((s["st_value"] & ~1, s["st_size"], s.name))
            segments = [(seg["p_paddr"], seg.data()) for seg in elf.iter_segments()
                        if seg["p_type"] == "PT_LOAD" and seg["p_filesz"]]
        self.node = next((n for n, s in STATE_SYMBOL.items() if s in self.symbols), None)
        if self.node is None:
            raise SystemExit(f"{elf_path}: neither {' nor '.join(STATE_SYMBOL.values())} in it")
        self.sensors = {name: (off, value) for off, name, value in SENSORS[self.node]}
        self.regs = {off: value for off, _, value in SENSORS[self.node]}
        self.stop_writes = []

        self.uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
        self.uc.ctl_set_cpu_model(UC_CPU_ARM_CORTEX_M4)
        self.uc.mem_map(self.flash_base, self.flash_len, UC_PROT_ALL)
        self.uc.mem_map(self.ram_base, self.ram_len, UC_PROT_ALL)
        self.uc.mem_map(SCS_BASE, PAGE, UC_PROT_ALL)
        for addr, data in segments:
            self.uc.mem_write(addr, data)
        self.flash = bytes(self.uc.mem_read(self.flash_base, self.flash_len))

        # Stack paint: from the end of .bss to the top of the stack.
        self.stack_top = self.symbols["_stack_start"]
        self.stack_floor = self.symbols.get("_stack_end", self.symbols["__ebss"])
        words = (self.stack_top - self.stack_floor) // 4
        self.uc.mem_write(self.stack_floor, PAINT.to_bytes(4, "little") * words)

        self.uc.mmio_map(CAN_PAGE, PAGE, self._can_read, None, self._can_write, None)
        self.uc.mmio_map(TIMER_PAGE, PAGE, self._timer_read, None, self._ignore_write, None)
        self.uc.mmio_map(SENSOR_PAGE, PAGE, self._sensor_read, None, self._sensor_write, None)

        # Instructions per basic block, counted once per block.
        self.block_len = {}
        self.executed = 0
        self.counting = count or profile
        self.profile = collections.Counter() if profile else None
        if self.counting:
            self.uc.hook_add(UC_HOOK_BLOCK, self._profiled_block if profile else self._block,
                             begin=self.flash_base, end=self.flash_base + self.flash_len - 1)

        self.inbox = queue.Queue()
        self.eof = False
        self.rx = None  # (raw id, dlc, lo, hi) while the firmware holds a frame
        self.tx = [0, 0, 0, 0]
        self.frames_in = 0
        self.frames_out = 0
        self.last_poll = None  # instruction count at the last RX_STATUS read
        self.polled_frame = False  # whether that read delivered a frame
        self.idle = [0, 0, None]  # turns without a frame: count, instructions, least
        self.per_frame = []
        self.start = time.monotonic()
        self.last_mmio = self.start
        self.failure = None
        self.yields = 0
        self.boot_stack = None  # the stack mark when the main loop starts

    # ---- peripherals -------------------------------------------------
    def _block(self, _uc, address, size, _data):
        n = self.block_len.get((address, size))
        if n is None:
            off = address - self.flash_base
            n = thumb_instructions(self.flash[off:off + size])
            self.block_len[(address, size)] = n
        self.executed += n

    def _profiled_block(self, uc, address, size, data):
        self._block(uc, address, size, data)
        if self.boot_stack is not None:
            self.profile[(address, size)] += 1

    def profile_lines(self, top):
        """The `top` functions by instructions run in the main loop (after
        boot), innermost function only."""
        functions = sorted(self.functions)
        starts = [f[0] for f in functions]
        per_function = collections.Counter()
        for (address, size), times in self.profile.items():
            i = bisect.bisect_right(starts, address) - 1
            name = functions[i][2] if i >= 0 else "?"
            per_function[name] += times * self.block_len[(address, size)]
        total = sum(per_function.values()) or 1
        turns = self.idle[0] + len(self.per_frame) or 1
        lines = [f"emulate: profile of the main loop: {total} instructions in {turns} turns"]
        for name, n in per_function.most_common(top):
            lines.append(f"emulate:   {100 * n / total:5.1f}% {n // turns:7d}/turn  {name}")
        return lines

    def _timer_read(self, _uc, offset, _size, _data):
        self.last_mmio = time.monotonic()
        if TIMER_PAGE + offset == TIMER_COUNT:
            return int((self.last_mmio - self.start) * 1e6) & 0xFFFF_FFFF
        return 0

    def _ignore_write(self, _uc, _offset, _size, _value, _data):
        pass

    def _sensor_read(self, _uc, offset, _size, _data):
        self.last_mmio = time.monotonic()
        return self.regs.get(SENSOR_PAGE + offset - SENSOR_BASE, 0)

    def _sensor_write(self, _uc, offset, _size, value, _data):
        reg = SENSOR_PAGE + offset - SENSOR_BASE
        self.regs[reg] = value
        if self.node == "charger" and reg == 0x10:
            self.stop_writes.append(value)

    def _command(self, line):
        parts = line[1:].split()
        if len(parts) == 3 and parts[0] == "sensor" and parts[1] in self.sensors:
            try:
                value = int(parts[2], 0) & 0xFFFF_FFFF
            except ValueError:
                value = None
            if value is not None:
                self.regs[self.sensors[parts[1]][0]] = value
                print(f"emulate: sensor {parts[1]} = {value:#x}", file=sys.stderr, flush=True)
                return
        print(f"emulate: unknown command: {line}", file=sys.stderr, flush=True)

    def _next_frame(self, wait):
        """Loads the next frame from stdin into the receive mailbox (commands
        applied on the way); False when there is none."""
        while True:
            try:
                line = self.inbox.get(timeout=wait) if wait else self.inbox.get_nowait()
            except queue.Empty:
                return False
            if line is None:
                self.eof = True
                return False
            if line.startswith("#"):
                self._command(line.strip())
                continue
            parsed = parse_line(line)
            if parsed is None:
                if line.strip():
                    print(f"emulate: input: not a candump line: {line.strip()}",
                          file=sys.stderr, flush=True)
                continue
            raw, dlc, data = parsed
            padded = data.ljust(8, b"\0")
            self.rx = (raw, dlc, int.from_bytes(padded[:4], "little"),
                       int.from_bytes(padded[4:], "little"))
            self.frames_in += 1
            return True

    def _can_read(self, uc, offset, _size, _data):
        self.last_mmio = time.monotonic()
        reg = offset
        if reg == RX_STATUS:
            if self.boot_stack is None:
                self._repaint_after_boot(uc)
            if self.last_poll is not None:
                turn = self.executed - self.last_poll
                if self.polled_frame:
                    self.per_frame.append(turn)
                else:
                    self.idle[0] += 1
                    self.idle[1] += turn
                    self.idle[2] = turn if self.idle[2] is None else min(self.idle[2], turn)
            self.last_poll = self.executed
            self.polled_frame = False
            if self.rx is None and not self.eof:
                self._next_frame(IDLE_WAIT_S)
            if self.rx is None:
                if self.eof:
                    uc.emu_stop()
                return 0
            self.polled_frame = True
            return 1
        if reg in (RX_ID, RX_DLC, RX_DATA_LO, RX_DATA_HI):
            if self.rx is None:
                return 0
            return self.rx[(reg - RX_ID) // 4]
        if reg == TX_STATUS:
            return 1  # always free: the frame is printed at once
        if reg in (TX_ID, TX_DLC, TX_DATA_LO, TX_DATA_HI):
            return self.tx[(reg - TX_ID) // 4]
        return 0

    def _repaint_after_boot(self, uc):
        """At the main loop's first receive poll: the boot's mark, then the
        paint renewed below the live stack, so the exit mark tells the main
        loop's own depth apart (nothing below SP is live: no interrupts)."""
        self.boot_stack = self.stack_high_water()
        sp = uc.reg_read(UC_ARM_REG_SP) & ~3
        uc.mem_write(self.stack_floor, PAINT.to_bytes(4, "little") * ((sp - self.stack_floor) // 4))

    def _can_write(self, _uc, offset, _size, value, _data):
        reg = offset
        if reg == RX_STATUS and value & 1:
            self.rx = None
        elif reg in (TX_ID, TX_DLC, TX_DATA_LO, TX_DATA_HI):
            self.tx[(reg - TX_ID) // 4] = value
        elif reg == TX_STATUS and value & 1:
            self._print_tx()

    def _print_tx(self):
        raw, dlc, lo, hi = self.tx
        ident = raw & 0x1FFF_FFFF
        text = f"{ident:08X}" if raw & ID_EXTENDED else f"{ident & 0x7FF:03X}"
        if raw & ID_REMOTE:
            body = "R" + (str(dlc) if dlc else "")
        else:
            body = (lo.to_bytes(4, "little") + hi.to_bytes(4, "little"))[:min(dlc & 0xF, 8)].hex()
        stamp = time.monotonic() - self.start
        sys.stdout.write(f"({stamp:.6f}) {self.interface} {text}#{body.upper()}\n")
        sys.stdout.flush()
        self.frames_out += 1

    # ---- running -----------------------------------------------------
    def _read_stdin(self):
        for line in sys.stdin:
            self.inbox.put(line)
        self.inbox.put(None)

    def _watchdog(self):
        while not self.done:
            time.sleep(0.25)
            if time.monotonic() - self.last_mmio > WATCHDOG_S:
                self.failure = f"no peripheral access for {WATCHDOG_S:.0f} s (halted?)"
                self.uc.emu_stop()
                return

    def _halfword(self, addr):
        off = addr - self.flash_base
        if 0 <= off < len(self.flash) - 1:
            return self.flash[off] | self.flash[off + 1] << 8
        return None

    def symbol_at(self, pc):
        for start, size, name in self.functions:
            if start <= pc < start + max(size, 1):
                return name
        return "?"

    def run(self):
        sp = int.from_bytes(self.flash[0:4], "little")
        reset = int.from_bytes(self.flash[4:8], "little")
        self.uc.reg_write(UC_ARM_REG_SP, sp)
        self.done = False
        threading.Thread(target=self._read_stdin, daemon=True).start()
        threading.Thread(target=self._watchdog, daemon=True).start()
        pc = reset | 1
        while True:
            try:
                self.uc.emu_start(pc, 0xFFFF_FFFF)
                break
            except UcError as e:
                # unicorn stops at YIELD (the hint core::hint::spin_loop
                # emits) as an invalid instruction: step over it, as the
                # hardware does (a panic's `loop` of it ends by the watchdog).
                pc = self.uc.reg_read(UC_ARM_REG_PC)
                if self.failure is None and self._halfword(pc) == YIELD:
                    pc = (pc + 2) | 1
                    self.yields += 1
                    continue
                self.failure = self.failure or f"CPU fault: {e}"
                break
        self.done = True
        self.elapsed = time.monotonic() - self.start
        return self.failure is None

    def stack_high_water(self):
        """Bytes of stack used at most (from the paint)."""
        ram = bytes(self.uc.mem_read(self.stack_floor, self.stack_top - self.stack_floor))
        pattern = PAINT.to_bytes(4, "little")
        for off in range(0, len(ram), 4):
            if ram[off:off + 4] != pattern:
                return self.stack_top - (self.stack_floor + off)
        return 0

    def summary(self):
        pc = self.uc.reg_read(UC_ARM_REG_PC)
        running = self.stack_high_water()
        stack = max(running, self.boot_stack or 0)
        phases = (f"boot {self.boot_stack}, main loop {running}" if self.boot_stack is not None
                  else "in boot: the main loop never polled the mailbox")
        statics = self.stack_floor - self.ram_base  # .data + .bss
        state = self.sizes.get(STATE_SYMBOL[self.node], 0)
        lines = [
            f"emulate: {self.node}: {self.frames_in} frames in, {self.frames_out} out "
            f"in {self.elapsed:.2f} s, {self.executed} instructions",
            f"emulate: stack high-water mark {stack} bytes ({phases}); .data+.bss {statics} bytes "
            f"(node state {state}); RAM used {statics + stack} of {self.ram_len} "
            f"({'fits' if statics + stack <= self.ram_len else 'DOES NOT FIT'})",
        ]
        if self.per_frame and self.counting:
            lines.append(f"emulate: instructions per received frame: mean "
                         f"{sum(self.per_frame) // len(self.per_frame)}, "
                         f"max {max(self.per_frame)} ({len(self.per_frame)} frames)")
        if self.idle[0] and self.counting:
            lines.append(f"emulate: instructions per main loop turn without a frame: mean "
                         f"{self.idle[1] // self.idle[0]}, least {self.idle[2]} "
                         f"({self.idle[0]} turns)")
        if self.yields:
            lines.append(f"emulate: YIELD stepped over {self.yields} times")
        if self.node == "charger":
            lines.append(f"emulate: OUTPUT_STOP writes: {len(self.stop_writes)}"
                         f" (last {self.stop_writes[-1]})" if self.stop_writes else
                         "emulate: OUTPUT_STOP writes: 0")
        if self.failure:
            lines.append(f"emulate: FAILED: {self.failure} at PC {pc:08X} ({self.symbol_at(pc)})")
        return "\n".join(lines), stack


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n", 1)[0])
    ap.add_argument("elf")
    ap.add_argument("--stack-report", metavar="FILE",
                    help="append a `node stack_bytes` line to FILE at exit")
    ap.add_argument("--interface", metavar="NAME", default="can0", help="interface name in the output lines")
    ap.add_argument("--no-count", action="store_true",
                    help="do not count instructions (the block hook costs about half the speed)")
    ap.add_argument("--profile", metavar="N", type=int,
                    help="also print the N functions that run the most instructions after boot")
    args = ap.parse_args()
    fw = Firmware(args.elf, args.interface, count=not args.no_count, profile=bool(args.profile))
    ok = fw.run()
    text, stack = fw.summary()
    if args.profile:
        text += "\n" + "\n".join(fw.profile_lines(args.profile))
    print(text, file=sys.stderr, flush=True)
    if args.stack_report:
        with open(args.stack_report, "a", encoding="utf-8") as f:
            f.write(f"{fw.node} {stack}\n")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
