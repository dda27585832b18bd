#!/usr/bin/env python3
"""canopen-decode --report checked in a real browser (headless Chromium).

For each log: the decoder writes the report; Chromium opens it from a
file (no network), runs its scripts and dumps the rendered DOM; the page's
script publishes what it drew on <body data-*>. The test checks

  * the page rendered (data-rendered="ok") with no script error
    (data-errors="0", window.onerror counts them);
  * it drew one plot per named PDO field, and that number equals the
    distinct (COB-ID, index, sub-index) fields with a value that
    `canopen-decode --json` gives for the same log (an independent path
    through the decoder's JSON writer);
  * it drew one traffic plot per plot in the page's data (the bus load per
    1-second window, frames per second per node, the raw bytes of PDOs
    without a mapping), a bus-load plot among them, and on a foreign trace
    (--generated: random frames on random identifiers, no PDO mapping;
    --python-can: the same kind of trace written by python-can's
    ASCWriter) more than one plot in all;
  * the rendered DOM holds one <canvas> per plot in the page's data
    besides the timeline's (counted in the DOM, not from the page's own
    count), and no timeline row (node entry) is empty: each has a state,
    a mark or a silence;
  * it drew every timeline mark (past a row's cap, counted on the page as
    not drawn), and their number equals what `--json --summary` shows: boot-ups, EMCYs (error resets included), NMT
    commands, SDO transfers, node-guarding requests and heartbeat
    silences;
  * the page is self-contained: no http(s) address, no external script,
    style sheet or image;

and keeps a screenshot of each page in target/report-screenshots/ (a CI
artifact).

Usage: report_browser.py DECODER CHROMIUM OUTDIR [--bundled] [--generated] [--python-can] [LOG ...]
A LOG given as capture:PATH is decoded with --pdo-capture-mapping. A log
that is absent or unreadable (the real captures are third-party data
beside the checkout, not in it) fails the run with CI=true; elsewhere the
script says it skipped that log.
"""
import json
import os
import random
import re
import subprocess
import sys

# Fields that are plotted: every kind with a value or a value marker.
NOT_PLOTTED = {"raw", "padding", "missing", "wrong_width", "chars"}


def generated_trace(path, seed=37, count=400):
    """A foreign trace: candump lines of random frames on random 11- and
    29-bit identifiers over a minute, no PDO mapping known."""
    rng = random.Random(seed)
    t = 1_700_000_000_000_000
    with open(path, "w", encoding="ascii") as f:
        for _ in range(count):
            t += rng.randint(100, 300_000)
            extended = rng.random() < 0.2
            ident = rng.randrange(1 << 29 if extended else 1 << 11)
            data = bytes(rng.randrange(256) for _ in range(rng.randint(0, 8)))
            name = f"{ident:08X}" if extended else f"{ident:03X}"
            f.write(f"({t // 1_000_000}.{t % 1_000_000:06d}) can0 {name}#{data.hex().upper()}\n")


def python_can_trace(path, seed=37, count=600):
    """A foreign trace written by python-can's ASCWriter: random frames on
    random 11- and 29-bit identifiers, no PDO mapping known."""
    import can  # only this trace needs python-can

    rng = random.Random(seed)
    t = 1_700_000_000.0
    w = can.ASCWriter(path)
    for _ in range(count):
        t += rng.uniform(0.0001, 0.2)
        extended = rng.random() < 0.2
        ident = rng.randrange(1 << 29 if extended else 1 << 11)
        dlc = rng.randrange(9)
        data = bytes(rng.randrange(256) for _ in range(dlc))
        w.on_message_received(can.Message(timestamp=t, arbitration_id=ident, is_extended_id=extended, dlc=dlc, data=data))
    w.stop()


def decoder_args(log):
    if log == "bundled":
        return ["--bundled", "session"]
    if log.startswith("capture:"):
        return ["--pdo-capture-mapping", log[len("capture:"):]]
    return [log]


def readable(log):
    """Whether `log` can be read; with CI=true an unreadable one ends the run."""
    if log == "bundled":
        return True
    path = log[len("capture:"):] if log.startswith("capture:") else log
    try:
        with open(path, "rb") as f:
            f.read(1)
        return True
    except OSError as e:
        note = f"{path} is absent or unreadable ({e})"
        if os.environ.get("CI") == "true":
            sys.exit(f"FAIL {note} (CI=true: the shared data must be there)")
        print(f"skipped: {note}")
        return False


def expected(decoder, log):
    out = subprocess.run([decoder, *decoder_args(log), "--json", "--summary"],
                         capture_output=True, text=True, check=False)
    if out.returncode not in (0, 1):
        sys.exit(f"{log}: canopen-decode --json exited {out.returncode}: {out.stderr}")
    fields, marks = set(), 0
    for line in out.stdout.splitlines():
        o = json.loads(line)
        kind = o.get("kind")
        if o.get("error"):
            continue  # a frame that does not decode: no field, no mark
        if kind in ("tpdo", "rpdo"):
            for f in o.get("fields") or []:
                if f["kind"] not in NOT_PLOTTED:
                    fields.add((o["id"], f["index"], f["sub"]))
        elif kind == "heartbeat":
            if o.get("remote"):
                marks += 1  # a node-guarding request
            elif o.get("state") == "boot-up":
                marks += 1
        elif kind in ("emcy", "nmt", "sdo_transfer"):
            marks += 1
        elif kind == "summary":
            marks += sum(len(n["silences"]) for n in o["nodes"])
    return len(fields), marks


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    decoder, chromium, outdir = sys.argv[1:4]
    os.makedirs(outdir, exist_ok=True)
    generated = os.path.abspath(os.path.join(outdir, "generated-foreign.log"))
    python_can = os.path.abspath(os.path.join(outdir, "python-can-foreign.asc"))
    named = {"--bundled": "bundled", "--generated": generated, "--python-can": python_can}
    logs = [named.get(a, a) for a in sys.argv[4:]]
    if not logs:
        sys.exit("no log given")
    if generated in logs:
        generated_trace(generated)
    if python_can in logs:
        python_can_trace(python_can)
    given = len(logs)
    logs = [log for log in logs if readable(log)]
    skipped = f" ({given - len(logs)} log(s) skipped: absent or unreadable)" if len(logs) < given else ""
    os.makedirs(outdir, exist_ok=True)
    failures = 0
    for i, log in enumerate(logs):
        name = "bundled-session" if log == "bundled" else os.path.basename(log).rsplit(".", 1)[0]
        html = os.path.abspath(os.path.join(outdir, f"{name}.html"))
        png = os.path.abspath(os.path.join(outdir, f"{name}.png"))
        run = subprocess.run([decoder, *decoder_args(log), "--report", html],
                             capture_output=True, text=True, check=False)
        if run.returncode not in (0, 1) or not os.path.isfile(html):
            sys.exit(f"{log}: --report failed ({run.returncode}): {run.stderr}")
        page = open(html, encoding="utf-8").read()
        external = re.findall(r'https?://|<script[^>]+src=|<link[^>]+href=|<img[^>]+src=', page)
        browser = [chromium, "--headless", "--no-sandbox", "--disable-gpu",
                   "--hide-scrollbars", "--virtual-time-budget=5000",
                   f"--user-data-dir={os.path.abspath(outdir)}/profile-{i}"]
        dom = subprocess.run(browser + ["--dump-dom", "file://" + html],
                             capture_output=True, text=True, timeout=120, check=False).stdout
        subprocess.run(browser + ["--window-size=1280,1600", f"--screenshot={png}", "file://" + html],
                       capture_output=True, text=True, timeout=120, check=False)
        body = re.search(r"<body([^>]*)>", dom)
        attrs = dict(re.findall(r'data-([a-z]+)="([^"]*)"', body.group(1))) if body else {}
        data = json.loads(re.search(
            r'<script type="application/json" id="report-data">(.*?)</script>', page, re.S
        ).group(1).replace("<\\/", "</"))
        want_series, want_marks = expected(decoder, log)
        # Marks past a row's cap are counted on the page, not drawn.
        not_drawn = sum(n for r in data["rows"] for _, n in r["not_drawn"])
        canvases = len(re.findall(r"<canvas(?![^>]*timeline-canvas)", dom))
        empty_rows = [r["label"] for r in data["rows"] if not (r["states"] or r["marks"] or r["silences"])]
        checks = [
            ("rendered", attrs.get("rendered"), "ok"),
            ("script errors", attrs.get("errors"), "0"),
            ("plots drawn = fields in the data", attrs.get("series"), str(len(data["series"]))),
            ("plots drawn = fields with a value in --json", attrs.get("series"), str(want_series)),
            ("marks drawn = marks in the data", attrs.get("marks"), str(data["marks"])),
            ("marks drawn + counted as not drawn = events in --json --summary",
             int(attrs.get("marks", "-1")) + not_drawn, want_marks),
            ("traffic plots drawn = plots in the data", attrs.get("plots"), str(len(data["plots"]))),
            ("a bus-load plot", sum(p["kind"] == "bus-load" for p in data["plots"]), 1),
            ("timeline rows", attrs.get("rows"), str(len(data["rows"]))),
            ("canvases in the DOM = plots in the data", canvases, len(data["series"]) + len(data["plots"])),
            ("empty node entries", empty_rows, []),
            ("external references", len(external), 0),
            ("screenshot written", os.path.isfile(png) and os.path.getsize(png) > 0, True),
        ]
        if log in (generated, python_can):
            plots = int(attrs.get("plots", "0")) + int(attrs.get("series", "0"))
            checks += [
                ("a foreign trace draws more than one plot", plots > 1, True),
                ("... and its unmapped PDOs' bytes", any(p["kind"] == "pdo-byte" for p in data["plots"]), True),
            ]
        for what, got, want in checks:
            ok = got == want
            failures += not ok
            print(f"{'ok  ' if ok else 'FAIL'} {name}: {what}: {got!r}" + ("" if ok else f", expected {want!r}"))
        print(f"     {name}: {len(page)} bytes, {attrs.get('series')} field plots, "
              f"{attrs.get('plots')} traffic plots, {attrs.get('points')} points, screenshot {png}")
    if failures:
        sys.exit(f"report browser test: {failures} check(s) failed")
    print(f"report browser test: {len(logs)} report(s), all checks passed{skipped}")


if __name__ == "__main__":
    main()
