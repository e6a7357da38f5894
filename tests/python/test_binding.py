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

DATA = os.environ.get("ISOCAM_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))


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
        # 1e-6 mm on lengths of some 10^4 mm: numpy and the core add the same
        # segments in another order (rounding ~1e-12 relative), nothing more.
        self.assertAlmostEqual(seg[kind[1:] == core.FEED].sum(), m.cutting_length, delta=1e-6)
        self.assertAlmostEqual(seg[kind[1:] == core.RAPID].sum(), m.rapid_length, delta=1e-6)
        self.assertAlmostEqual(
            seg[(kind[1:] == core.PLUNGE) | (kind[1:] == core.RAMP)].sum(),
            m.plunge_length,
            delta=1e-6,
        )
        # Entries (plunges down, ramps) and lifts (retracts: a plunge up is a
        # lift fed where a rapid would pass nearer than r to the model).
        dz = np.diff(xyz[:, 2])
        entries = ((kind[1:] == core.PLUNGE) & (dz < 0)) | (kind[1:] == core.RAMP)
        self.assertEqual(int(entries.sum()), m.retracts)
        self.assertLessEqual(m.max_iso_distance, m.delta_max)
        # The certificate is at most the request in exact arithmetic; 1e-9
        # relative is the rounding of the doubles it is computed in.
        self.assertLessEqual(m.guaranteed_scallop, 0.05 * (1 + 1e-9))
        self.assertLessEqual(m.guaranteed_overcut, 0.005 * (1 + 1e-9))
        # The flat stepover for the cusp the budget leaves: the centres may
        # be off the offset by e = chord + posted rounding.
        e = m.chord_tolerance + 0.5 * math.sqrt(3.0) * 0.001
        r, h = 3.0 - e, 0.05 - e
        # The same formula in doubles: equal to rounding (places=12 on ~1 mm).
        self.assertAlmostEqual(m.delta, 2 * math.sqrt(2 * r * h - h**2), places=12)
        seconds = 60 * (
            seg[(kind[1:] == core.FEED) | (kind[1:] == core.RAMP)].sum() / 1200.0
            + seg[kind[1:] == core.PLUNGE].sum() / 400.0
            + seg[kind[1:] == core.RAPID].sum() / 5000.0
        )
        # Same sums in another order: 1e-9 relative is rounding only.
        self.assertAlmostEqual(m.machine_time, seconds, delta=1e-9 * seconds)
        self.assertEqual(self.res.face_direction[0] in ("U", "V"), True)

    def test_stepover_formula(self):
        self.assertAlmostEqual(core.stepover_for_scallop(3.0, 0.01), 2 * math.sqrt(0.06 - 1e-4))
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
            with self.assertRaises(core.InvalidArgumentError) as ctx:
                core.adaptive_isocurve(self.mat, [0], params(**kw))
            self.assertIsInstance(ctx.exception, ValueError)
            self.assertIn(needle, str(ctx.exception))
            self.assertEqual(ctx.exception.arguments[0], needle)
        with self.assertRaisesRegex(ValueError, "out of range"):
            core.adaptive_isocurve(self.mat, [3], params())
        with self.assertRaisesRegex(ValueError, "brep"):
            core.adaptive_isocurve("", [0], params())
        with self.assertRaisesRegex(ValueError, "brep"):
            core.adaptive_isocurve("not a brep at all", [0], params())

    def test_invalid_argument_error_names_the_arguments_it_is_about(self):
        # Whole names of the module's parameters and arguments, in the
        # message's order; words of the text that are none are not listed.
        with self.assertRaises(core.InvalidArgumentError) as ctx:
            core.adaptive_isocurve(self.mat, [0], params(chord_tolerance=0.01))
        self.assertEqual(ctx.exception.arguments[:2], ("chord_tolerance", "overcut_tolerance"))
        self.assertNotIn("tolerance", ctx.exception.arguments)
        with self.assertRaises(core.InvalidArgumentError) as ctx:
            core.adaptive_isocurve(self.mat, [3], params())
        self.assertEqual(ctx.exception.arguments, ("faces",))
        with self.assertRaises(core.InvalidArgumentError) as ctx:
            core.adaptive_isocurve(self.mat, [0], params(max_moves=10.0))
        self.assertIn("max_moves", ctx.exception.arguments)

    def test_recursion_guard_is_a_runtime_error(self):
        with self.assertRaisesRegex(RuntimeError, "max_depth"):
            core.adaptive_isocurve(self.mat, [0], params(max_depth=2))

    def test_cancel_raises_cancelled_error(self):
        prog = core.Progress()
        prog.cancel()
        with self.assertRaises(core.CancelledError):
            core.adaptive_isocurve(self.mat, [0], params(), prog)

    def run_polled(self, cancel_midway):
        """adaptive_isocurve on a worker thread, its progress polled from this
        one until the worker ends; with cancel_midway, cancel() as soon as a
        fraction strictly between 0 and 1 is seen (the core has started and
        not finished). Returns (what the worker got: "result" or
        "cancelled", the fractions seen in order, the final fraction)."""
        prog = core.Progress()
        out = {}

        def work():
            try:
                core.adaptive_isocurve(self.mat, [0], params(scallop_height=0.02), prog)
                out["got"] = "result"
            except core.CancelledError:
                out["got"] = "cancelled"

        worker = threading.Thread(target=work)
        worker.start()
        seen = []
        while worker.is_alive():
            f = prog.fraction
            seen.append(f)
            if cancel_midway and 0.0 < f < 1.0:
                prog.cancel()
                break
            time.sleep(0.001)
        worker.join()
        return out.get("got"), seen, prog.fraction

    def test_progress_stays_in_range_and_ends_at_one(self):
        # However many polls the scheduler allows (none is counted): the
        # fractions seen stay in [0, 1] and the last is exactly 1. (Not
        # asserted yet: that they never go back, as progress.h promises; the
        # two directions planned at once report into their own slices, and a
        # poll may see 0.30 then 0.04.)
        got, seen, final = self.run_polled(cancel_midway=False)
        self.assertEqual(got, "result")
        self.assertEqual(final, 1.0)
        self.assertTrue(all(0.0 <= f <= 1.0 for f in seen), seen)

    def test_cancel_lands_midway_while_the_gil_is_released(self):
        # This thread can only read a fraction strictly between 0 and 1 and
        # cancel while the core runs if the binding released the GIL: with
        # the GIL held it would run again only after the call returned (at
        # 1), and the worker would get its result instead of CancelledError.
        got, seen, final = self.run_polled(cancel_midway=True)
        self.assertEqual(got, "cancelled", seen)
        self.assertTrue(0.0 < seen[-1] < 1.0, seen)
        self.assertLess(final, 1.0)


if __name__ == "__main__":
    unittest.main()
