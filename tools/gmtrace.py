#!/usr/bin/env python3
"""Reads gmotion traces (CSV or binary GMTRACE1) with the column schema of
src/trace/trace_columns.def, and prints a binary trace as the equivalent CSV trace.

Usage: tools/gmtrace.py TRACE.bin [> TRACE.csv]

Binary layout (little-endian, no padding): 8-byte magic b"GMTRACE1", uint32 header length, the
header text (the same '#' lines and column line as the CSV trace), then one record per row whose
fields follow the columns, each as its kind in trace_columns.def says (time: int64 sample index
k, t = k*T; line: int32; count: int64; fixed3 and percent: float64).

A trace written with `run --keep-partial` has a fixed-width `# status:` header line, copied like
the others; when it says the trace is partial, an incomplete last record (a killed run) is left
out with a note on stderr instead of being an error.

As a module: schema(), column_kind(name), read_rows(path) -> (header dict, names, row iterator),
read_columns(path) -> (header dict, {name: [values]}).
"""
import os
import re
import struct
import sys

SCHEMA_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src", "trace",
                           "trace_columns.def")
# kind -> (struct code of its binary field, CSV formatter)
KINDS = {
    "time": ("q", lambda v: f"{v:.6f}"),
    "line": ("i", lambda v: str(int(v))),
    "count": ("q", lambda v: str(int(v))),
    "fixed3": ("d", lambda v: f"{v:.3f}"),
    "percent": ("d", lambda v: f"{v:.6g}"),
}
_COLUMN = re.compile(r'^GM_TRACE_COLUMN\((\w+),\s*(\w+),\s*(\w+),\s*(.*),\s*"(.*)",\s*([0-9.e+-]+),\s*(\w+)\)\s*$')


def schema():
    """The columns of trace_columns.def: a list of dicts section, name, kind, unit, resolution,
    when ("always", or the optional set a column belongs to, e.g. "modes": the tool tip)."""
    cols = []
    with open(SCHEMA_FILE) as f:
        for line in f:
            m = _COLUMN.match(line.strip())
            if m:
                cols.append({"section": m[1], "name": m[2], "kind": m[3], "unit": m[5],
                             "resolution": float(m[6]), "when": m[7]})
    if not cols:
        raise SystemExit(f"{SCHEMA_FILE}: no GM_TRACE_COLUMN lines")
    return cols


def column_kind(name, cols=None):
    """The kind of trace column `name` ("x_cmd" is the axis column "cmd"), or None."""
    for c in cols or schema():
        if c["section"] == "axis":
            if len(name) == len(c["name"]) + 2 and name[1] == "_" and name[2:] == c["name"]:
                return c["kind"]
        elif name == c["name"]:
            return c["kind"]
    return None


def _header_dict(lines):
    h = {}
    for l in lines:
        if l.startswith("# ") and ": " in l:
            k, v = l[2:].split(": ", 1)
            h[k] = v
    return h


def read_rows(path):
    """(header text, header dict, column names, iterator of rows of numbers) for a CSV or binary trace."""
    f = open(path, "rb")
    if f.read(8) == b"GMTRACE1":
        (hlen,) = struct.unpack("<I", f.read(4))
        header = f.read(hlen).decode("utf-8")
        lines = header.strip().splitlines()
        names = lines[-1].split(",")
        hd = _header_dict(lines)
        period = float(hd["period_s"])
        partial = hd.get("status", "").startswith("partial")
        cols = schema()
        kinds = [column_kind(n, cols) for n in names]
        if None in kinds:
            raise SystemExit(f"{path}: unknown column {names[kinds.index(None)]}")
        rec = struct.Struct("<" + "".join(KINDS[k][0] for k in kinds))

        def rows():
            with f:
                while True:
                    chunk = f.read(rec.size)
                    if not chunk:
                        return
                    if len(chunk) != rec.size:
                        if partial:
                            print(f"{path}: partial trace: its incomplete last record is left out",
                                  file=sys.stderr)
                            return
                        raise SystemExit(f"{path}: truncated record at the end of the file")
                    v = rec.unpack(chunk)
                    yield [x * period if k == "time" else x for x, k in zip(v, kinds)]
        return header, hd, names, rows()
    f.close()
    t = open(path)
    header, lines = "", []
    for line in t:
        header += line
        if not line.startswith("#"):
            break
        lines.append(line.rstrip("\n"))
    names = header.strip().splitlines()[-1].split(",")

    def rows():
        with t:
            for line in t:
                yield [float(x) for x in line.rstrip("\n").split(",")]
    return header, _header_dict(lines), names, rows()


def read_columns(path):
    """(header dict, {column name: [values]}) for a CSV or binary trace."""
    _, hd, names, rows = read_rows(path)
    cols = {n: [] for n in names}
    for r in rows:
        for n, v in zip(names, r):
            cols[n].append(v)
    if "t_s" not in cols:
        raise SystemExit(f"{path}: not a gmotion trace")
    return hd, cols


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    header, _, names, rows = read_rows(sys.argv[1])
    cols = schema()
    fmts = [KINDS[column_kind(n, cols)][1] for n in names]
    out = sys.stdout
    out.write(header)
    for r in rows:
        out.write(",".join(f(v) for f, v in zip(fmts, r)) + "\n")


if __name__ == "__main__":
    main()
