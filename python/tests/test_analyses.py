"""gmotion.moves, design, response and radius_error: closed forms and the command line."""

import json
import math
import os
import subprocess
import unittest

import numpy as np

import gmotion

SRC = os.environ.get("GMOTION_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("GMOTION_BIN", os.path.join(SRC, "build", "bin", "gmotion"))
PROGRAMS = os.path.join(SRC, "programs")
SIM = "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis"


def cli_json_lines(*args):
    out = subprocess.run([BIN, *args], check=True, capture_output=True, text=True).stdout
    return [json.loads(l) for l in out.splitlines() if l.strip()]


class Moves(unittest.TestCase):
    def test_square_by_hand(self):
        m = gmotion.moves(os.path.join(PROGRAMS, "square.nc"))
        feeds = [r for r in m if r["kind"] == "line"]
        # G1 Z0 F300, then the 20 mm square at 1200 mm/min.
        self.assertEqual(feeds[0]["end"], [0.0, 0.0, 0.0])
        self.assertEqual(feeds[0]["feed"], 300.0)
        self.assertEqual([f["end"][:2] for f in feeds[1:5]],
                         [[20.0, 0.0], [20.0, 20.0], [0.0, 20.0], [0.0, 0.0]])
        self.assertEqual({f["feed"] for f in feeds[1:5]}, {1200.0})
        self.assertEqual(feeds[1]["line"], 7)

    def test_equal_to_the_cli_on_every_bundled_program(self):
        for name in sorted(os.listdir(PROGRAMS)):
            if not name.endswith(".nc"):
                continue
            with self.subTest(program=name):
                path = os.path.join(PROGRAMS, name)
                self.assertEqual(gmotion.moves(path), cli_json_lines("moves", path))

    def test_machine_axes_and_an_ini(self):
        nine = os.path.join(SRC, "tests", "ini", "nine-axis.ngc")
        m = gmotion.moves(nine, axes="XYZABCUVW")
        self.assertEqual(m, cli_json_lines("moves", nine, "--axes", "XYZABCUVW"))
        # G20: 1 in = 25.4 mm; A, B, C in degrees.
        first = [r for r in m if r["kind"] == "line"][0]
        self.assertAlmostEqual(first["end"][0], 25.4)
        self.assertEqual(first["axes"]["A"], 30.0)
        self.assertAlmostEqual(first["axes"]["U"], 5.08)
        ini = os.path.join(SIM, "axis_9axis.ini")
        if not os.path.exists(ini):
            self.skipTest(f"{ini} is absent (linuxcnc-uspace ships it)")
        self.assertEqual(gmotion.moves(nine, machine=ini), m)

    def test_a_program_error_is_an_input_error(self):
        with self.assertRaises(gmotion.InputError) as e:
            gmotion.moves(os.path.join(SRC, "tests", "bad", "arc_zero_radius.nc"))
        self.assertIn("arc_zero_radius.nc:", str(e.exception))


class Design(unittest.TestCase):
    def test_linear_taps_are_a_box(self):
        d = gmotion.design("linear", tau=0.04, period=0.004)
        np.testing.assert_allclose(d.taps, np.full(10, 0.1))
        np.testing.assert_array_equal(d.taps_int, np.ones(10, dtype=np.int64))
        self.assertEqual((d.N, d.b_s, d.tau), (9, 10, 0.04))

    def test_the_papers_example_meets_its_limits(self):
        d = gmotion.design()  # blackman, tau 0.164, T 0.004, the paper's section 6 limits
        self.assertTrue(d.ok)
        self.assertEqual(d.N, 40)
        self.assertAlmostEqual(d.taps.sum(), 1.0, places=12)
        # Eq. 7 from the applied taps: V * max(b_i) / (T * b_s).
        self.assertAlmostEqual(d.peak_accel, 0.1 * d.taps_int.max() / (0.004 * d.b_s), places=9)
        # Eq. 29: F = m a + c V, P = F V.
        self.assertAlmostEqual(d.peak_force, 500 * d.peak_accel + 500 * 0.1, places=6)
        self.assertAlmostEqual(d.peak_power, d.peak_force * 0.1, places=6)
        cli = json.loads(subprocess.run([BIN, "design", "--json"], check=True,
                                        capture_output=True, text=True).stdout)
        np.testing.assert_array_equal(d.taps, np.array(cli["taps"]))
        self.assertEqual(d.b_s, cli["b_s"])

    def test_tight_force_limit_grows_tau(self):
        d = gmotion.design("linear", tau=0.04, period=0.004, f_max=1000.0)
        # Box of n taps: a = V/(n T); F = 500 a + 50 <= 1000  ->  n >= 500*0.1/(950*0.004) = 13.2
        self.assertEqual(len(d.taps), 14)
        self.assertEqual(len(d.attempts), 5)
        self.assertFalse(d.attempts[0]["ok"])


class Analyses(unittest.TestCase):
    def test_box_response_is_the_dirichlet_kernel(self):
        r = gmotion.response("linear", tau=0.04, period=0.004, points=101)
        w = np.pi * r.f_norm[1:]
        n = 10
        expected = np.abs(np.sin(n * w / 2) / (n * np.sin(w / 2)))
        np.testing.assert_allclose(r.amplitude[1:], expected, atol=1e-12)
        self.assertEqual(r.amplitude[0], 1.0)
        np.testing.assert_allclose(r.f_hz, r.f_norm * 125.0)

    def test_radius_error_linear_closed_forms(self):
        feeds = [30000.0, 6000.0, 600.0]
        e = gmotion.radius_error("linear", tau=0.041, period=0.001, radius=150.0, feeds=feeds)
        for f, cont, approx, sampled in zip(feeds, e.continuous_linear_um, e.approx_linear_um,
                                            e.sampled_um):
            v = f / 60.0
            u = 0.041 * (v / 150.0) / 2
            self.assertAlmostEqual(cont, 1000 * 150 * (1 - math.sin(u) / u), places=9)
            self.assertAlmostEqual(approx, 1000 * (0.041 * v) ** 2 / (24 * 150), places=9)
            # The sampled box of 41 taps: R (1 - |D|), D the Dirichlet kernel at w T.
            wt = v / 150.0 * 0.001
            d = abs(math.sin(41 * wt / 2) / (41 * math.sin(wt / 2)))
            self.assertAlmostEqual(sampled, 1000 * 150 * (1 - d), places=6)
        # Eq. 19 at 30 m/min: (0.041 * 500)^2 / (24 * 150) mm = 116.7 um.
        self.assertAlmostEqual(e.approx_linear_um[0], 116.736, places=3)


if __name__ == "__main__":
    unittest.main()
