"""The pybind11 module seen from Python: flat arrays, metrics that agree with
the arrays, the error model, progress and cancel with the GIL released."""

import math
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))
import numpy as np  # noqa: E402

import isocam_core as core  # noqa: E402

DATA = os.environ.get(
    "ISOCAM_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data")
)


def read(name):
    with open(os.path.join(DATA, name)) as f:
        return f.read()


def params(**kw):
    p = core.IsoParams()
    p.ball_radius = 3.0
    p.scallop_height = 0.05
    p.safe_z = 100.0
    for k, v in kw.items():
        setattr(p, k, v)
    return p


class Binding(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.mat = read("MAT.brep")
        cls.res = core.adaptive_isocurve(cls.mat, [0], params())

    def test_flat_arrays(self):
        kind, xyz = self.res.kind, self.res.xyz
        self.assertEqual(kind.dtype, np.uint8)
        self.assertEqual(xyz.dtype, np.float64)
        self.assertEqual(xyz.shape, (len(kind), 3))
        self.assertTrue(xyz.flags["C_CONTIGUOUS"])
        self.assertTrue(
            set(np.unique(kind)).issubset({core.RAPID, core.FEED, core.PLUNGE, core.RAMP})
        )

    def test_metrics_agree_with_the_arrays(self):
        kind, xyz = self.res.kind, self.res.xyz
        seg = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
        m = self.res.metrics
        self.assertAlmostEqual(
            seg[kind[1:] == core.FEED].sum(), m.cutting_length, delta=1e-6
        )
        self.assertAlmostEqual(
            seg[kind[1:] == core.RAPID].sum(), m.rapid_length, delta=1e-6
        )
        self.assertAlmostEqual(
            seg[(kind[1:] == core.PLUNGE) | (kind[1:] == core.RAMP)].sum(), m.plunge_length, delta=1e-6
        )
        # Entries (plunges down, ramps) and lifts (retracts: a plunge up is a
        # lift fed where a rapid would pass nearer than r to the model).
        dz = np.diff(xyz[:, 2])
        entries = ((kind[1:] == core.PLUNGE) & (dz < 0)) | (kind[1:] == core.RAMP)
        self.assertEqual(int(entries.sum()), m.retracts)
        self.assertLessEqual(m.max_iso_distance, m.delta_max)
        self.assertLessEqual(m.guaranteed_scallop, 0.05 * (1 + 1e-9))
        self.assertLessEqual(m.guaranteed_overcut, 0.005 * (1 + 1e-9))
        # The flat stepover for the cusp the budget leaves: the centres may
        # be off the offset by e = chord + posted rounding.
        e = m.chord_tolerance + 0.5 * math.sqrt(3.0) * 0.001
        r, h = 3.0 - e, 0.05 - e
        self.assertAlmostEqual(m.delta, 2 * math.sqrt(2 * r * h - h**2), places=12)
        seconds = 60 * (
            seg[(kind[1:] == core.FEED) | (kind[1:] == core.RAMP)].sum() / 1200.0
            + seg[kind[1:] == core.PLUNGE].sum() / 400.0
            + seg[kind[1:] == core.RAPID].sum() / 5000.0
        )
        self.assertAlmostEqual(m.machine_time, seconds, delta=1e-9 * seconds)
        self.assertEqual(self.res.face_direction[0] in ("U", "V"), True)

    def test_stepover_formula(self):
        self.assertAlmostEqual(
            core.stepover_for_scallop(3.0, 0.01), 2 * math.sqrt(0.06 - 1e-4)
        )
        self.assertAlmostEqual(
            core.scallop_for_stepover(3.0, core.stepover_for_scallop(3.0, 0.01)), 0.01
        )

    def test_bad_arguments_raise_value_error_naming_them(self):
        cases = [
            (dict(scallop_height=3.0), "scallop_height"),
            (dict(scallop_height=0.0), "scallop_height"),
            (dict(chord_tolerance=-1.0), "chord_tolerance"),
            (dict(safe_z=-50.0), "safe_z"),
        ]
        for kw, needle in cases:
            with self.assertRaises(ValueError) as ctx:
                core.adaptive_isocurve(self.mat, [0], params(**kw))
            self.assertIn(needle, str(ctx.exception))
        with self.assertRaisesRegex(ValueError, "out of range"):
            core.adaptive_isocurve(self.mat, [3], params())
        with self.assertRaisesRegex(ValueError, "brep"):
            core.adaptive_isocurve("", [0], params())
        with self.assertRaisesRegex(ValueError, "brep"):
            core.adaptive_isocurve("not a brep at all", [0], params())

    def test_recursion_guard_is_a_runtime_error(self):
        with self.assertRaisesRegex(RuntimeError, "max_depth"):
            core.adaptive_isocurve(self.mat, [0], params(max_depth=2))

    def test_cancel_raises_cancelled_error(self):
        prog = core.Progress()
        prog.cancel()
        with self.assertRaises(core.CancelledError):
            core.adaptive_isocurve(self.mat, [0], params(), prog)

    def test_progress_is_polled_while_the_gil_is_released(self):
        prog = core.Progress()
        out = {}

        def work():
            out["res"] = core.adaptive_isocurve(
                self.mat, [0], params(scallop_height=0.02), prog
            )

        worker = threading.Thread(target=work)
        worker.start()
        seen, ticks = set(), 0
        while worker.is_alive():
            ticks += 1  # runs only if the worker does not hold the GIL
            seen.add(round(prog.fraction, 2))
            time.sleep(0.001)
        worker.join()
        self.assertIn("res", out)
        self.assertEqual(prog.fraction, 1.0)
        self.assertGreater(ticks, 10)
        self.assertTrue(any(0.0 < f < 1.0 for f in seen), sorted(seen))


if __name__ == "__main__":
    unittest.main()
