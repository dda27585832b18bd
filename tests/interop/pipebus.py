"""PipeBus: a python-can bus whose other end is a child process speaking
candump log lines on its stdin/stdout (the crate's example programs),
Cases, the counted cases of one run, and the two waits the scripts share
(frames, wait_until). Shared by the interop scripts in this directory."""

import queue
import re
import subprocess
import sys
import threading
import time

import can

LINE = re.compile(r"^(?:\(\d+(?:\.\d+)?\)\s+)?(?:\S+\s+)?([0-9A-Fa-f]{3})#([0-9A-Fa-f]*)$")


class PipeBus(can.BusABC):
    """A python-can bus whose other end is a child process speaking candump lines."""

    def __init__(self, cmd, **kwargs):
        self.proc = subprocess.Popen(
            cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True, bufsize=1)
        self.rx = queue.Queue()
        self.stderr_lines = []
        self.seen = []  # (time, id, data) of every frame from the node
        self.sent = []  # (time, line) of every frame to the node
        self._send_lock = threading.Lock()  # periodic tasks send from threads
        threading.Thread(target=self._read_stdout, daemon=True).start()
        threading.Thread(target=self._read_stderr, daemon=True).start()
        super().__init__(channel="pipe", **kwargs)

    def _read_stdout(self):
        for line in self.proc.stdout:
            m = LINE.match(line.strip())
            if not m:
                print(f"bridge: unparsed line from node: {line!r}", file=sys.stderr)
                continue
            now = time.time()
            msg = can.Message(arbitration_id=int(m.group(1), 16),
                              data=bytes.fromhex(m.group(2)), is_extended_id=False,
                              timestamp=now)
            self.seen.append((now, msg.arbitration_id, bytes(msg.data)))
            self.rx.put(msg)

    def _read_stderr(self):
        for line in self.proc.stderr:
            self.stderr_lines.append(line.rstrip("\n"))

    def send(self, msg, timeout=None):
        if msg.is_remote_frame:
            # A remote request (e.g. node guarding): candump's `ID#R`.
            line = f"({time.time():.6f}) pipe {msg.arbitration_id:03X}#R\n"
        else:
            line = f"({time.time():.6f}) pipe {msg.arbitration_id:03X}#{bytes(msg.data).hex().upper()}\n"
        with self._send_lock:
            self.sent.append((time.time(), line.split(" ", 2)[-1].strip()))
            self.proc.stdin.write(line)
            self.proc.stdin.flush()

    def command(self, line):
        """Writes one non-frame line to the child (e.g. the firmware
        emulator's `#sensor status 0x101`), in order with the frames."""
        with self._send_lock:
            self.proc.stdin.write(line.rstrip("\n") + "\n")
            self.proc.stdin.flush()

    def _recv_internal(self, timeout):
        try:
            return self.rx.get(timeout=timeout), False
        except queue.Empty:
            return None, False

    def shutdown(self):
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        super().shutdown()

    def lines(self, prefix):
        """The child's stderr lines that start with `prefix`."""
        return [l for l in self.stderr_lines if l.startswith(prefix)]


class Cases:
    """The cases of one interop run: each `check` prints ok or FAIL and is
    counted; `finish` prints the count and exits 1 when any failed."""

    def __init__(self):
        self.cases = 0
        self.failures = []

    def check(self, name, ok, detail=""):
        self.cases += 1
        print(f"{'ok  ' if ok else 'FAIL'} {name}{(': ' + str(detail)) if detail and not ok else ''}")
        if not ok:
            self.failures.append(name)

    def guarded(self, name, fn):
        """Runs one case; an exception is a failure of that case."""
        try:
            fn()
        except Exception as e:  # noqa: BLE001 - every error is a failed case
            self.check(name, False, f"{type(e).__name__}: {e}")

    def finish(self):
        print(f"{self.cases} interop cases, {len(self.failures)} failed")
        sys.exit(1 if self.failures else 0)


def frames(bus, cob_id, since):
    """(time, data) of every frame `cob_id` the node sent at or after `since`."""
    return [(ts, d) for ts, i, d in bus.seen if i == cob_id and ts >= since]


def wait_until(pred, seconds):
    """Polls `pred` every 20 ms for up to `seconds`; returns its last value."""
    end = time.time() + seconds
    while time.time() < end:
        if pred():
            return True
        time.sleep(0.02)
    return pred()
