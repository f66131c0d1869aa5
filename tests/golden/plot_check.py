#!/usr/bin/python3
"""Renders a plot from a golden trace with tools/plot_trace.py and checks the PNG is valid and
not blank. Exit 77 (skipped) when matplotlib is missing. Usage: plot_check.py REPO_DIR GMOTION
(the trace is the lost-motion golden's, run fresh: the stored goldens are zstd-compressed)."""
import os
import subprocess
import sys
import tempfile

try:
    import matplotlib.image as mpimg
except ImportError:
    print("matplotlib is not installed (Debian python3-matplotlib): skipped")
    sys.exit(77)

repo, gmotion = sys.argv[1], sys.argv[2]
with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "path.png")
    trace = os.path.join(tmp, "lost-motion.csv")
    subprocess.run([gmotion, "run", "programs/paper-circle.nc", "--machine",
                    "programs/machines/paper-lost-motion.toml", "--decimate", "4", "--trace", trace],
                   cwd=repo, check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["/usr/bin/python3", os.path.join(repo, "tools", "plot_trace.py"), "path",
                    trace, "-o", out], check=True)
    with open(out, "rb") as f:
        magic = f.read(8)
    if magic != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"FAIL: {out} is not a PNG (magic {magic!r})")
    img = mpimg.imread(out)
    h, w = img.shape[:2]
    if h < 300 or w < 600:
        sys.exit(f"FAIL: image too small: {w}x{h}")
    gray = img[..., :3].mean(axis=2)
    dark = (gray < 0.5).mean()
    if gray.std() < 0.05 or not 0.002 < dark < 0.5:
        sys.exit(f"FAIL: image looks blank (std {gray.std():.4f}, dark fraction {dark:.4f})")
    print(f"ok: {w}x{h} PNG, pixel std {gray.std():.3f}, dark fraction {dark:.4f}")
