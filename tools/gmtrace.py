#!/usr/bin/env python3
"""Reads a gmotion binary trace (GMTRACE1) and prints it as the equivalent CSV trace.

Usage: tools/gmtrace.py TRACE.bin [> TRACE.csv]

Layout (little-endian, no padding): 8-byte magic b"GMTRACE1", uint32 header length, the header
text (the same '#' lines and column line as the CSV trace), then one record per row:
int64 k, int32 line, then per axis int64 cmd, ref, enc, ferr, then float64 contour_err (BLU)
and float64 override (percent).

A trace written with `run --keep-partial` has a fixed-width `# status:` header line, copied like
the others; when it says the trace is partial, an incomplete last record (a killed run) is left
out with a note on stderr instead of being an error.
"""
import struct
import sys


def read_trace(path):
    """Yields the header text, then one tuple per row: (t_s, line, per-axis ints..., contour, override)."""
    with open(path, "rb") as f:
        if f.read(8) != b"GMTRACE1":
            raise SystemExit(f"{path}: not a gmotion binary trace (bad magic)")
        (hlen,) = struct.unpack("<I", f.read(4))
        header = f.read(hlen).decode("utf-8")
        columns = header.strip().splitlines()[-1].split(",")
        axes = (len(columns) - 4) // 4
        period = float(next(l for l in header.splitlines() if l.startswith("# period_s:")).split(":")[1])
        partial = any(l.startswith("# status: partial") for l in header.splitlines())
        rec = struct.Struct("<qi" + "q" * (4 * axes) + "dd")
        yield header
        while True:
            chunk = f.read(rec.size)
            if not chunk:
                return
            if len(chunk) != rec.size:
                if partial:
                    print(f"{path}: partial trace: its incomplete last record is left out", file=sys.stderr)
                    return
                raise SystemExit(f"{path}: truncated record at the end of the file")
            v = rec.unpack(chunk)
            yield (v[0] * period,) + v[1:]


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    rows = read_trace(sys.argv[1])
    out = sys.stdout
    out.write(next(rows))
    for r in rows:
        out.write(f"{r[0]:.6f}," + ",".join(str(x) for x in r[1:-2]) + f",{r[-2]:.3f},{r[-1]:.6g}\n")


if __name__ == "__main__":
    main()
