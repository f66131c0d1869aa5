"""One program run four ways (gmotion run, a golden case, gmotion sweep, gmotion.run) on a machine
file that sets dialect = "fanuc" and tolerance_on = "encoder": the summaries agree. Then the same
with --tolerance-on given as a flag (a case's and a sweep spec's `flags`, a keyword in Python).

Needs GMOTION_BIN, GMOTION_SOURCE_DIR and the gmotion package on PYTHONPATH (as python:unittest).
"""

import json
import os
import subprocess
import sys
import tempfile
import unittest

import gmotion

BIN = os.environ["GMOTION_BIN"]
SRC = os.environ["GMOTION_SOURCE_DIR"]

# M31 (a parts counter) is only passed over in the fanuc dialect; linuxcnc refuses it. G64 without
# P plans the corners for the machine's path tolerance, on the encoder or on the Acc/Dec output.
PROGRAM = """O1234 (SQUARE)
G21 G90 G17 G64
G0 X0 Y0
M31 (parts counter)
G1 X20 F3000
X20 Y20
X0
Y0
M30
"""


def machine_text(tolerance_on):
    """The built-in machine with dialect = "fanuc", a path tolerance and maybe tolerance_on."""
    with open(os.path.join(SRC, "programs", "machines", "default.toml")) as f:
        text = f.read()
    keys = 'name = "fanuc-mill"\ndialect = "fanuc"\npath_tolerance_mm = 0.02\n'
    if tolerance_on:
        keys += f'tolerance_on = "{tolerance_on}"\n'
    return text.replace('name = "default"\n', keys, 1)


def figures(summary):
    """What must agree: samples, cycle time and the worst contour error (BLU)."""
    return (summary["samples"], summary["cycle_time_s"], summary["contour_err_max_blu"]["value"])


class SettingsAgree(unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name
        self.program = self.write("p.nc", PROGRAM)

    def tearDown(self):
        self.dir.cleanup()

    def write(self, name, text):
        path = os.path.join(self.d, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def gmotion(self, *args):
        r = subprocess.run([BIN, *args], capture_output=True, text=True, cwd=self.d)
        self.assertEqual(r.returncode, 0, f"gmotion {' '.join(args)}:\n{r.stdout}\n{r.stderr}")
        return r

    def by_run(self, machine, *flags):
        out = os.path.join(self.d, "run.json")
        self.gmotion("run", self.program, "--machine", machine, *flags, "--summary-json", out)
        with open(out) as f:
            return figures(json.load(f))

    def by_golden(self, machine, flags):
        suite = os.path.join(self.d, "suite")
        os.makedirs(suite, exist_ok=True)
        with open(os.path.join(suite, "suite.toml"), "w") as f:
            f.write(f'[[case]]\nname = "one"\nprogram = {json.dumps(self.program)}\n'
                    f'machine = {json.dumps(machine)}\nflags = {json.dumps(flags)}\n')
        self.gmotion("golden", "record", suite)
        with open(os.path.join(suite, "golden", "one.summary.json")) as f:
            return figures(json.load(f))

    def by_sweep(self, machine, flags=""):
        spec = self.write("spec.toml", f"programs = [{json.dumps(self.program)}]\n"
                                       f"machines = [{json.dumps(machine)}]\n"
                                       f"flags = {json.dumps(flags)}\n")
        table = os.path.join(self.d, "table.json")
        self.gmotion("sweep", spec, "--json", table)
        emitted = self.gmotion("sweep", spec, "--emit", "parallel", "--out-dir", self.d).stdout
        self.assertIn(flags, emitted)  # the emitted `gmotion run` takes the same flags
        with open(table) as f:
            row = json.load(f)[0]
        self.assertEqual(row["status"], "ok", row)
        blu_mm = 0.001  # the built-in machine's contour BLU
        return (row["samples"], row["cycle_time_s"], round(row["contour_max_mm"] / blu_mm, 3))

    def by_python(self, machine, **options):
        return figures(gmotion.run(self.program, machine, **options).summary)

    def test_machine_file_keys_four_ways(self):
        machine = self.write("fanuc.toml", machine_text("encoder"))
        run = self.by_run(machine)
        self.assertEqual(self.by_golden(machine, ""), run)
        self.assertEqual(self.by_python(machine), run)
        sweep = self.by_sweep(machine)
        self.assertEqual(sweep[:2], run[:2])
        self.assertAlmostEqual(sweep[2], run[2], places=2)  # the table's mm, printed to 1e-6
        # tolerance_on matters here: on the Acc/Dec output the corners are planned otherwise.
        acc_dec = self.by_run(self.write("acc_dec.toml", machine_text("")))
        self.assertNotEqual(acc_dec, run)

    def test_tolerance_on_flag_four_ways(self):
        machine = self.write("fanuc.toml", machine_text(""))
        run = self.by_run(machine, "--tolerance-on", "encoder")
        self.assertEqual(self.by_golden(machine, "--tolerance-on encoder"), run)
        self.assertEqual(self.by_python(machine, tolerance_on="encoder"), run)
        sweep = self.by_sweep(machine, "--tolerance-on encoder")
        self.assertEqual(sweep[:2], run[:2])
        self.assertAlmostEqual(sweep[2], run[2], places=2)
        self.assertNotEqual(self.by_run(machine), run)


if __name__ == "__main__":
    sys.exit(unittest.main())
