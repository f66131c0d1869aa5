"""The Python bindings against the command line: the same run gives the same numbers."""

import csv
import json
import os
import subprocess
import tempfile
import threading
import unittest

import numpy as np

import gmotion

SRC = os.environ.get("GMOTION_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("GMOTION_BIN", os.path.join(SRC, "build", "bin", "gmotion"))
SQUARE = os.path.join(SRC, "programs", "square.nc")
HELIX = os.path.join(SRC, "programs", "helix.nc")
BAD_ARC = os.path.join(SRC, "tests", "bad", "arc_zero_radius.nc")


def cli_run(program, *flags):
    """The CLI's CSV trace (header lines, column names, rows as floats) and summary JSON."""
    with tempfile.TemporaryDirectory() as d:
        trace, summary = os.path.join(d, "t.csv"), os.path.join(d, "s.json")
        subprocess.run([BIN, "run", program, "--trace", trace, "--summary-json", summary, *flags],
                       check=True, stdout=subprocess.DEVNULL)
        with open(trace) as f:
            lines = f.read().splitlines()
        header = [l[2:] for l in lines if l.startswith("# ")]
        body = [l for l in lines if not l.startswith("#")]
        rows = list(csv.reader(body))
        with open(summary) as f:
            return header, rows[0], [[float(v) for v in r] for r in rows[1:]], json.load(f)


class RunMatchesTheCli(unittest.TestCase):
    def test_trace_and_summary_equal_the_cli_csv(self):
        for program, flags, options in [
            (SQUARE, [], {}),
            (HELIX, ["--profile", "scurve1", "--tau", "0.1", "--override", "150"],
             {"profile": "scurve1", "tau": 0.1, "override": 150}),
        ]:
            with self.subTest(program=os.path.basename(program)):
                header, columns, rows, summary = cli_run(program, *flags)
                r = gmotion.run(program, **options)
                self.assertTrue(r.finished)
                self.assertEqual(r.columns, columns)
                self.assertEqual(r.summary, summary)
                expected = np.array(rows)
                for i, c in enumerate(columns):
                    got = r.trace[c]
                    self.assertEqual(got.dtype, np.float64)
                    self.assertEqual(len(got), len(rows), c)
                    # The CSV prints t_s to 1 us and contour_err to 0.001 BLU: equal at that print.
                    if c == "t_s":
                        np.testing.assert_allclose(got, expected[:, i], rtol=0, atol=5e-7)
                    elif c == "contour_err":
                        np.testing.assert_allclose(got, expected[:, i], rtol=0, atol=5e-4)
                    else:
                        np.testing.assert_array_equal(got, expected[:, i], err_msg=c)

    def test_hand_checked_values(self):
        r = gmotion.run(SQUARE)
        t = r.trace["t_s"]
        # T = 4 ms (the built-in machine): t = k T exactly as printed.
        np.testing.assert_allclose(np.diff(t), 0.004, atol=1e-9)
        # The square ends at X0 Y0 Z1 (mm), BLU 0.001 mm: the command ends at (0, 0, 1000).
        self.assertEqual((r.trace["x_cmd"][-1], r.trace["y_cmd"][-1], r.trace["z_cmd"][-1]),
                         (0.0, 0.0, 1000.0))
        # Feed moves of 4 x 20 mm at 1200 mm/min take 4 s; the summary's sample count is the rows'.
        self.assertEqual(r.summary["samples"], len(t))
        self.assertGreater(r.summary["program_time_s"], 4.0)
        self.assertIn("blu_mm: 0.001,0.001,0.001", r.header)

    def test_servo_off_the_encoder_reads_the_accdec_output(self):
        r = gmotion.run(SQUARE, servo=False)
        for a in "xyz":
            np.testing.assert_array_equal(r.trace[a + "_enc"], r.trace[a + "_ref"])
            self.assertFalse(np.any(r.trace[a + "_ferr"]))

    def test_decimate_keeps_every_nth_sample(self):
        full = gmotion.run(SQUARE)
        every10 = gmotion.run(SQUARE, decimate=10)
        np.testing.assert_array_equal(every10.trace["x_enc"], full.trace["x_enc"][::10])

    def test_runs_in_threads_give_the_same_results(self):
        results = [None] * 4

        def work(i):
            results[i] = gmotion.run(HELIX, tau=(0.048, 0.1)[i % 2])  # 12 and 25 periods

        threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        np.testing.assert_array_equal(results[0].trace["y_enc"], results[2].trace["y_enc"])
        np.testing.assert_array_equal(results[1].trace["y_enc"], results[3].trace["y_enc"])
        self.assertNotEqual(results[0].summary["cycle_time_s"], results[1].summary["cycle_time_s"])


class Errors(unittest.TestCase):
    def test_check_raises_program_error_where_the_cli_points(self):
        with self.assertRaises(gmotion.ProgramError) as cm:
            gmotion.check(BAD_ARC)
        e = cm.exception
        # `gmotion check` prints tests/bad/arc_zero_radius.nc:3:7 and the file says code 303.
        self.assertEqual((e.line, e.column, e.code), (3, 7, 303))
        self.assertEqual(e.file, BAD_ARC)
        self.assertIn("zero radius arc", e.message)
        self.assertIn("^", str(e))
        cli = subprocess.run([BIN, "check", BAD_ARC], capture_output=True, text=True)
        self.assertIn(f"{BAD_ARC}:3:7: error: {e.message}", cli.stdout + cli.stderr)

    def test_run_of_a_bad_program_raises_before_running(self):
        with self.assertRaises(gmotion.ProgramError) as cm:
            gmotion.run(BAD_ARC)
        self.assertEqual(cm.exception.line, 3)

    def test_check_of_a_good_program(self):
        c = gmotion.check(SQUARE)
        # square.nc: 4 sides of 20 mm, 1 mm down, 1 mm up; the first rapid starts at Z1 from 0.
        self.assertAlmostEqual(c.path_length_mm, 80 + 1 + 1 + 1, places=9)
        self.assertEqual(c.moves, 7)

    def test_bad_options(self):
        with self.assertRaises(TypeError):
            gmotion.run(SQUARE, tua=0.1)
        with self.assertRaises(gmotion.InputError):
            gmotion.run(SQUARE, override=500)
        with self.assertRaises(gmotion.InputError):
            gmotion.run(SQUARE, profile="no-such-profile")
        with self.assertRaises(gmotion.InputError):
            gmotion.run(os.path.join(SRC, "no-such-program.nc"))


class LanguageOptions(unittest.TestCase):
    """The `--subroutine-path`, `--dialect` and parameter-file flags, as keyword options."""

    LIB = os.path.join(SRC, "tests", "diff", "subfiles", "lib")

    def program(self, d, text):
        path = os.path.join(d, "p.ngc")
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_subroutine_path_finds_a_sub_file(self):
        with tempfile.TemporaryDirectory() as d:
            prog = self.program(d, "G0 X0 Y0\no<frame> call [40] [30] [5]\nM2\n")
            with self.assertRaises(gmotion.ProgramError):
                gmotion.check(prog)  # no path: frame.ngc is not found
            c = gmotion.check(prog, subroutine_path=self.LIB)
            # In from X0 to X5, then 40 x 30 with r = 5 corners: 2 (40 - 10) + 2 (30 - 10) + 2 pi 5.
            self.assertAlmostEqual(c.path_length_mm, 105 + 10 * np.pi, places=9)
            ends = [m["end"][:2] for m in gmotion.moves(prog, subroutine_path=self.LIB)]
            self.assertEqual(ends[-1], [5.0, 0.0])
            self.assertTrue(gmotion.run(prog, subroutine_path=self.LIB, servo=False).finished)

    def test_dialect(self):
        with tempfile.TemporaryDirectory() as d:
            prog = self.program(d, "O1234 (PART)\nG0 X1\nM31 (parts counter)\nM30\n")
            with self.assertRaises(gmotion.ProgramError):
                gmotion.check(prog)
            self.assertEqual(gmotion.check(prog, dialect="fanuc").moves, 1)
            self.assertEqual(gmotion.check(prog, dialect="haas").moves, 1)
            with self.assertRaises(gmotion.InputError):
                gmotion.check(prog, dialect="heidenhain")

    def test_parameter_file_read_and_written_or_not(self):
        with tempfile.TemporaryDirectory() as d:
            prog = self.program(d, "G0 X1\nG10 L2 P1 X3\nM2\n")
            var = os.path.join(d, "p.var")
            with open(var, "w") as f:
                f.write("5221\t10\n")  # G54 X = 10
            self.assertEqual(gmotion.moves(prog, parameter_file=var)[0]["end"], [11.0, 0.0, 0.0])
            with open(var) as f:
                self.assertIn("5221\t3.000000\n", f.read())  # written after the program
            r = gmotion.run(prog, parameter_file=var, servo=False)
            self.assertEqual(r.trace["x_cmd"][-1], 4000.0)  # G54 X3 + 1 mm, in 1 um counts
            with open(var, "w") as f:
                f.write("5221\t10\n")
            self.assertEqual(gmotion.moves(prog, no_parameter_file=True)[0]["end"], [1.0, 0.0, 0.0])
            with open(var) as f:
                self.assertEqual(f.read(), "5221\t10\n")
            with self.assertRaises(TypeError):
                gmotion.check(prog, parameter_flie=var)
            with self.assertRaises(gmotion.InputError):
                gmotion.check(prog, parameter_file=var, no_parameter_file=True)

    def test_an_inch_configuration_starts_in_g20(self):
        with tempfile.TemporaryDirectory() as d:
            ini = os.path.join(d, "inch.ini")
            with open(ini, "w") as f:
                f.write("[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = inch\n"
                        "[AXIS_X]\nMAX_VELOCITY = 1\nMAX_ACCELERATION = 10\n")
            prog = self.program(d, "G0 X1\nM2\n")
            self.assertEqual(gmotion.moves(prog, machine=ini)[0]["end"], [25.4, 0.0, 0.0])
            self.assertEqual(gmotion.moves(prog)[0]["end"], [1.0, 0.0, 0.0])


if __name__ == "__main__":
    unittest.main()
