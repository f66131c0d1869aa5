#!/usr/bin/env python3
"""The report page in a real browser: headless Chromium renders `gmotion report` of a program to
a PNG and dumps the DOM after the page's script ran. Passes when the PNG is not blank (many
colours, the contour-error and path colours present), the script built the summary table with
the run's values, and the time cursor (placed by the address's #t=1.8) shows the source line. Exits 77 (skipped) when chromium is not installed.

Usage: render_check.py GMOTION_BIN PROGRAM [PNG_OUT]"""
import collections
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib


def decode_png(data):
    """(width, height, Counter of (r, g, b) -> pixels) of an 8-bit RGB or RGBA PNG."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour in (2, 6) and interlace == 0, (depth, colour, interlace)
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * bpp
    assert len(raw) == height * (stride + 1), "truncated image data"
    pixels = collections.Counter()
    prev = [0] * stride
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = list(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif f == 2:
            line = [(x + u) & 255 for x, u in zip(line, prev)]
        elif f == 3:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((a + prev[i]) >> 1)) & 255
        elif f == 4:
            for i in range(stride):
                if i >= bpp:
                    a, b, c = line[i - bpp], prev[i], prev[i - bpp]
                else:
                    a, b, c = 0, prev[i], 0
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        else:
            assert f == 0, f"bad filter {f}"
        pixels.update(zip(line[0::bpp], line[1::bpp], line[2::bpp]))
        prev = line
    return width, height, pixels


def near(p, q, tol=40):
    return sum(abs(a - b) for a, b in zip(p, q)) <= tol


def main():
    gmotion, program = sys.argv[1], sys.argv[2]
    png_out = sys.argv[3] if len(sys.argv) > 3 else None
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        print("SKIP: chromium is not installed (tools/install-deps.sh --with-browser)")
        return 77
    with tempfile.TemporaryDirectory(prefix="gmotion-report-") as tmp:
        page = os.path.join(tmp, "report.html")
        summary = os.path.join(tmp, "summary.json")
        png = png_out or os.path.join(tmp, "report.png")
        subprocess.run([gmotion, "report", program, "-o", page, "--summary-json", summary],
                       check=True, stdout=subprocess.DEVNULL)
        t0 = time.monotonic()
        # Chromium keeps its profile in HOME: give it a fresh one.
        env = dict(os.environ, HOME=tmp)
        dom = subprocess.run(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             "--no-first-run", "--disable-extensions", "--disable-background-networking",
             "--user-data-dir=" + os.path.join(tmp, "profile"), "--window-size=1000,1300",
             "--screenshot=" + png, "--dump-dom", "file://" + page + "#t=1.8"],
            check=True, capture_output=True, text=True, timeout=90, env=env).stdout
        print(f"chromium: {time.monotonic() - t0:.1f} s")
        width, height, pixels = decode_png(open(png, "rb").read())
        assert (width, height) == (1000, 1300), (width, height)
        non_white = width * height - pixels[(255, 255, 255)]
        red = sum(n for p, n in pixels.items() if near(p, (0xd6, 0x27, 0x28)))  # contour error
        path_blue = sum(n for p, n in pixels.items() if near(p, (0x2c, 0x7b, 0xb6)))  # XY path
        colours = pixels
        print(f"png {width}x{height}: {len(colours)} colours, {non_white} non-white pixels, "
              f"{red} contour-red, {path_blue} path-blue")
        assert len(colours) >= 50, "the screenshot has almost no colours: blank?"
        assert non_white >= 0.02 * width * height, "the screenshot is nearly all white"
        assert red >= 200, "the contour error plot is not drawn"
        assert path_blue >= 500, "the XY path is not drawn"
        # The script ran: the summary table has the run's values.
        values = json.load(open(summary))
        cells = dict(re.findall(r"<tr><td>([^<]+)</td><td>([^<]*)</td></tr>", dom))
        print(f"summary table: {len(cells)} rows")
        assert cells.get("samples") == str(values["samples"]), cells.get("samples")
        assert float(cells["contour_err_max_blu.value"]) == values["contour_err_max_blu"]["value"]
        assert float(cells["axes.x.velocity_max_mm_s.value"]) == \
            values["axes"]["x"]["velocity_max_mm_s"]["value"]
        # The cursor placed at t = 1.8 s by the address: square.nc's interpolator is then in
        # line 8 ("Y20": line 7's 20 mm at 20 mm/s run from about 0.3 s to 1.3 s, line 8's from
        # 1.3 s to 2.3 s); the read-out names the file, the line and its text.
        info = re.search(r'<div id="cursor-info">(.*?)</div></div>', dom, re.S)
        assert info, "no cursor read-out"
        text = info.group(1)
        print("cursor read-out:", re.sub(r"<[^>]+>", " ", text))
        assert "t = 1.8000 s" in text, text
        assert program + ":8" in text, text
        assert "<code>Y20</code>" in text, text
    return 0


if __name__ == "__main__":
    sys.exit(main())
