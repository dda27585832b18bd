#!/usr/bin/env python3
"""Signals and DBC interop: canopen-decode's --signals and --dbc outputs
read by independent tools and compared with its own --json output.

For the bundled session and each real capture given:
- `--signals FILE.csv` read with Python's csv module: a row per PDO frame
  with fields, in order; every signal cell equal to the JSON field's value
  (numbers as numbers, words as words, the raw integer for an unnamed
  object, empty for null);
- `--dbc FILE.dbc` loaded with cantools: every PDO frame of the log decoded
  by it (scaling on, choices off) gives, signal by signal, the JSON value
  of a number and the JSON raw of a bit field or code;
- with a decoder built with the `parquet` feature, `--signals FILE.parquet`
  read with pyarrow and with DuckDB: the same cells, typed (DOUBLE for a
  signal that is numbers only, VARCHAR otherwise, nulls for empty cells);
  and the captures given in one run (`--signals DIR.parquet LOG...`) as one
  dataset partitioned by log, read by DuckDB as one table whose `log`
  column tells each log's rows, equal to each log's own JSON.

usage: signals_interop.py PATH/TO/canopen-decode [CAPTURE.log...]
A capture that is absent or unreadable fails under CI (CI=true), after the
other runs; elsewhere it is skipped with a message.
"""

import csv
import gzip
import json
import os
import shutil
import subprocess
import sys
import tempfile

import cantools

DECODER = sys.argv[1]
CAPTURES = sys.argv[2:]
FAILS = []


def fail(what):
    FAILS.append(what)
    print("FAIL", what)


def decode(args):
    out = subprocess.run([DECODER, *args], capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise SystemExit(f"canopen-decode {args}: exit {out.returncode}: {out.stderr}")
    return out


def frames_of(args):
    """The JSON frames with PDO fields, padding left out."""
    lines = decode([*args, "--json"]).stdout.splitlines()
    frames = []
    for line in lines:
        v = json.loads(line)
        if isinstance(v.get("fields"), list):
            v["fields"] = [f for f in v["fields"] if f["kind"] != "padding"]
            frames.append(v)
    return frames


def want(field):
    """The cell a JSON field gives: a float, a str, or None."""
    value = field["value"]
    if value is None:
        if field["kind"] in ("raw", "wrong_width"):
            return float(field["raw"])
        return None
    if isinstance(value, str):
        return value
    return float(value)


def header_of(field, cob_id):
    """The headers a field's column may have (unit absent in JSON for an
    invalid value: then the header's unit is not checked)."""
    if field["name"] == "unknown object":
        base = f"{field['index']:04X}h:{field['sub']:02X} raw"
    elif "unit" in field:
        base = f"{field['name']} [{field['unit']}]"
    else:
        base = field["name"]
    return base, f" ({cob_id:03X}h)"


def column_of(headers, field, cob_id):
    base, suffix = header_of(field, cob_id)
    found = []
    for i, h in enumerate(headers):
        plain = h[: -len(suffix)] if h.endswith(suffix) else h
        if plain == base or (
            "unit" not in field and plain.startswith(base + " [") and plain.endswith("]")
        ):
            found.append(i)
    own = [i for i in found if headers[i].endswith(suffix)]
    if len(own) == 1:
        return own[0]
    if len(found) == 1:
        return found[0]
    raise SystemExit(f"no single column for {base} on {cob_id:03X}h in {headers}")


def check_table(label, headers, rows, frames):
    """rows: lists of cells (float, str or None), time and cob_id first."""
    if len(rows) != len(frames):
        fail(f"{label}: {len(rows)} rows, {len(frames)} PDO frames")
        return 0
    compared = 0
    for row, frame in zip(rows, frames):
        if f"{frame['id']:03X}" != row[1]:
            fail(f"{label}: cob_id {row[1]} for frame {frame['id']:03X}")
        t = frame.get("t")
        if (t is None) != (row[0] is None) or (t is not None and abs(row[0] - t) > 1e-7):
            fail(f"{label}: time {row[0]} for {t}")
        filled = set()
        for f in frame["fields"]:
            c = column_of(headers, f, frame["id"])
            filled.add(c)
            if row[c] != want(f):
                fail(f"{label}: {headers[c]} = {row[c]!r}, JSON {want(f)!r} at t={t}")
            compared += 1
        for c in range(2, len(headers)):
            if c not in filled and row[c] is not None:
                fail(f"{label}: {headers[c]} filled on a frame that does not map it")
    return compared


def check_csv(args, frames, tmp):
    path = os.path.join(tmp, "signals.csv")
    decode([*args, "--signals", path])
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        headers = next(reader)
        rows = []
        for r in reader:
            if len(r) != len(headers):
                fail(f"csv: a row of {len(r)} cells under {len(headers)} headers")
            cells = [float(r[0]) if r[0] else None, r[1]]
            for cell in r[2:]:
                if cell == "":
                    cells.append(None)
                else:
                    try:
                        cells.append(float(cell))
                    except ValueError:
                        cells.append(cell)
            rows.append(cells)
    return check_table("csv", headers, rows, frames)


def check_dbc(args, frames, tmp):
    path = os.path.join(tmp, "signals.dbc")
    decode([*args, "--dbc", path])
    db = cantools.database.load_file(path)
    compared = 0
    for frame in frames:
        msg = db.get_message_by_frame_id(frame["id"])
        data = bytes.fromhex(frame["data"])
        if len(data) < msg.length:
            continue
        got = msg.decode(data, decode_choices=False, scaling=True)
        if len(msg.signals) != len(frame["fields"]):
            fail(f"dbc: {msg.name} has {len(msg.signals)} signals, JSON {len(frame['fields'])}")
            continue
        for sg, f in zip(msg.signals, frame["fields"]):
            value = got[sg.name]
            expect = f["value"] if isinstance(f["value"], (int, float)) else f["raw"]
            if float(value) != float(expect):
                fail(f"dbc: {msg.name}.{sg.name} = {value}, JSON {expect}")
            if isinstance(f["value"], (int, float)) and (sg.unit or "") != f.get("unit", ""):
                fail(f"dbc: {msg.name}.{sg.name} unit {sg.unit!r}, JSON {f.get('unit')!r}")
            compared += 1
    return compared


def parquet_supported():
    out = subprocess.run(
        [DECODER, "--bundled", "session", "--signals", os.devnull + ".parquet"],
        capture_output=True,
        text=True,
        check=False,
    )
    return "feature" not in out.stderr


def check_parquet(args, frames, tmp):
    import duckdb
    import pyarrow.parquet as pq

    path = os.path.join(tmp, "signals.parquet")
    decode([*args, "--signals", path])
    table = pq.read_table(path)
    headers = table.column_names
    columns = [table.column(i).to_pylist() for i in range(len(headers))]
    rows = [list(r) for r in zip(*columns)] if columns else []
    for r in rows:
        r[1] = f"{r[1]:03X}"
        for i in range(2, len(r)):
            if isinstance(r[i], (int, float)):
                r[i] = float(r[i])
    n = check_table("pyarrow", headers, rows, frames)
    con = duckdb.connect()
    result = con.execute(f"SELECT * FROM read_parquet('{path}')")
    d_headers = [d[0] for d in result.description]
    d_rows = []
    for r in result.fetchall():
        r = list(r)
        r[1] = f"{r[1]:03X}"
        for i in range(2, len(r)):
            if isinstance(r[i], (int, float)):
                r[i] = float(r[i])
        d_rows.append(r)
    n += check_table("duckdb", d_headers, d_rows, frames)
    return n


def check_dataset(captures):
    """All captures in one run: one dataset, one table in DuckDB."""
    import duckdb

    with tempfile.TemporaryDirectory() as tmp:
        root = os.path.join(tmp, "fleet.parquet")
        decode(["--pdo-capture-mapping", "--signals", root, *captures])
        con = duckdb.connect()
        result = con.execute(
            f"SELECT * FROM read_parquet('{root}/*/*.parquet', hive_partitioning = true, "
            "union_by_name = true, file_row_number = true) ORDER BY log, file_row_number"
        )
        headers = [d[0] for d in result.description]
        all_rows = result.fetchall()
        log = headers.index("log")
        number = headers.index("file_row_number")
        n = 0
        for c in captures:
            name = os.path.splitext(os.path.basename(c))[0]
            frames = frames_of(["--pdo-capture-mapping", c])
            rows = []
            for r in all_rows:
                if r[log] != name:
                    continue
                r = [x for i, x in enumerate(r) if i not in (log, number)]
                r[1] = f"{r[1]:03X}"
                for i in range(2, len(r)):
                    if isinstance(r[i], (int, float)):
                        r[i] = float(r[i])
                rows.append(r)
            signal_headers = [h for h in headers if h not in ("log", "file_row_number")]
            n += check_table(f"dataset {name}", signal_headers, rows, frames)
        print(f"dataset of {len(captures)} logs: {len(all_rows)} rows in one table, {n} cells compared")
    check_fleet_folder(captures)
    check_files_and_glob(captures)


def check_files_and_glob(captures):
    """Three logs named as files (the captures and a gzip-compressed copy
    of the first, `truck-3.log.gz`) and the captures by a glob
    (`logs/*.log`, which the copy does not match): DuckDB's
    `read_parquet('ROOT/**/*.parquet', hive_partitioning = true)` and
    pyarrow's hive dataset count each log's mapped PDO frames under its
    NAME (the copy's without `.log.gz`), and every part has the schema
    docs/DECODER.md gives: `time` an optional DOUBLE, `cob_id` a required
    INT32, each signal an optional DOUBLE or string."""
    import duckdb
    import pyarrow as pa
    import pyarrow.dataset as ds
    import pyarrow.parquet as pq

    with tempfile.TemporaryDirectory() as tmp:
        logs = os.path.join(tmp, "logs")
        os.mkdir(logs)
        want = {}
        for c in captures:
            shutil.copy(c, logs)
            want[os.path.splitext(os.path.basename(c))[0]] = len(frames_of(["--pdo-capture-mapping", c]))
        copy = os.path.join(logs, "truck-3.log.gz")
        with open(captures[0], "rb") as f, gzip.open(copy, "wb") as g:
            g.write(f.read())
        first = os.path.splitext(os.path.basename(captures[0]))[0]
        three = dict(want, **{"truck-3": want[first]})
        files = [os.path.join(logs, os.path.basename(c)) for c in captures] + [copy]
        for label, named, expected in (
            (f"{len(files)} logs as files", files, three),
            ("a glob of the logs", [os.path.join(logs, "*.log")], want),
        ):
            root = os.path.join(tmp, f"{len(expected)}-{label[0]}.parquet")
            decode(["--pdo-capture-mapping", "--signals", root, *named])
            counted = dict(
                duckdb.connect()
                .execute(
                    f"SELECT log, count(*) FROM read_parquet('{root}/**/*.parquet', "
                    "hive_partitioning = true, union_by_name = true) GROUP BY log"
                )
                .fetchall()
            )
            table = ds.dataset(root, format="parquet", partitioning="hive").to_table()
            column = [str(x) for x in table.column("log").to_pylist()]
            by_pyarrow = {name: column.count(name) for name in set(column)}
            if counted != expected or by_pyarrow != expected:
                fail(f"{label}: rows per log duckdb {counted}, pyarrow {by_pyarrow}, mapped PDO frames {expected}")
            for name in expected:
                schema = pq.read_schema(os.path.join(root, f"log={name}", "part-0.parquet"))
                time, cob_id = schema.field("time"), schema.field("cob_id")
                wrong = [
                    f.name
                    for f in schema
                    if f.name not in ("time", "cob_id")
                    and not (f.nullable and (f.type == pa.float64() or f.type == pa.string()))
                ]
                if time.type != pa.float64() or not time.nullable or cob_id.type != pa.int32() or cob_id.nullable or wrong:
                    fail(f"{label}: log={name}'s schema is not the documented one: {schema}")
            print(f"dataset of {label}: {sum(counted.values())} rows in {len(counted)} partitions (duckdb **, pyarrow), schema as documented")


def check_fleet_folder(captures):
    """A folder of logs with `--dataset parquet` into a folder not named
    .parquet: pyarrow's hive dataset and DuckDB's hive_partitioning count
    each log's PDO frames under its name, the total their sum."""
    import duckdb
    import pyarrow.dataset as ds

    want = {}
    with tempfile.TemporaryDirectory() as tmp:
        logs = os.path.join(tmp, "logs")
        os.mkdir(logs)
        for c in captures:
            shutil.copy(c, logs)
            name = os.path.splitext(os.path.basename(c))[0]
            want[name] = len(frames_of(["--pdo-capture-mapping", c]))
        root = os.path.join(tmp, "fleet")
        decode(["--pdo-capture-mapping", "--dataset", "parquet", "--signals", root, logs])
        table = ds.dataset(root, format="parquet", partitioning="hive").to_table()
        logs_column = [str(x) for x in table.column("log").to_pylist()]
        got = {name: logs_column.count(name) for name in set(logs_column)}
        if got != want or table.num_rows != sum(want.values()):
            fail(f"pyarrow hive dataset: rows per log {got}, PDO frames per log {want}")
        con = duckdb.connect()
        counted = dict(
            con.execute(
                f"SELECT log, count(*) FROM read_parquet('{root}/*/*.parquet', "
                "hive_partitioning = true, union_by_name = true) GROUP BY log"
            ).fetchall()
        )
        if counted != want:
            fail(f"duckdb hive_partitioning: rows per log {counted}, PDO frames per log {want}")
        print(
            f"fleet folder of {len(captures)} logs (--dataset parquet): "
            f"pyarrow {table.num_rows} rows, duckdb {sum(counted.values())}, "
            f"PDO frames {sum(want.values())}"
        )


def unreadable(path):
    """Why `path` cannot be read as a file, or None when it can."""
    try:
        with open(path, "rb") as f:
            f.read(1)
    except OSError as e:
        return e.strerror or str(e)
    return None


def main():
    runs = [("bundled session", ["--bundled", "session"])]
    present = []
    for c in CAPTURES:
        problem = unreadable(c)
        if problem:
            message = f"shared test data missing or unreadable: capture {c}: {problem}"
            if os.environ.get("CI") == "true":
                fail(f"{message} (CI=true: every capture given must be there)")
            else:
                print(f"skipped: {message}")
            continue
        present.append(c)
        runs.append((os.path.basename(c), ["--pdo-capture-mapping", c]))
    parquet = parquet_supported()
    if not parquet:
        print("note: the decoder was built without the parquet feature: Parquet not checked")
    for label, args in runs:
        frames = frames_of(args)
        with tempfile.TemporaryDirectory() as tmp:
            n_csv = check_csv(args, frames, tmp)
            n_dbc = check_dbc(args, frames, tmp)
            n_pq = check_parquet(args, frames, tmp) if parquet else 0
        print(
            f"{label}: {len(frames)} PDO frames; cells compared: csv {n_csv}, "
            f"cantools {n_dbc}, parquet (pyarrow + duckdb) {n_pq}"
        )
    if parquet and len(present) > 1:
        check_dataset(present)
    if FAILS:
        print(f"{len(FAILS)} failure(s)")
        sys.exit(1)
    print("signals interop: all equal")


main()
