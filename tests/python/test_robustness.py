"""Issue 15 through the Python module: out-of-domain arguments raise
ValueError naming the argument, the B-rep guard gives the byte offset, the
work budget is a parameter the caller can raise."""

import math
import os
import sys
import unittest

sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))
import numpy as np  # noqa: E402

import isocam_core as core  # noqa: E402

DATA = os.environ.get("ISOCAM_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))


def read(name):
    with open(os.path.join(DATA, name)) as f:
        return f.read()


class RobustnessTest(unittest.TestCase):
    def test_scallop_functions_check_their_domain(self):
        with self.assertRaisesRegex(ValueError, "ball_radius = nan"):
            core.stepover_for_scallop(math.nan, 0.1)
        with self.assertRaisesRegex(ValueError, "delta = 7"):
            core.scallop_for_stepover(3.0, 7.0)
        self.assertEqual(core.scallop_for_stepover(3.0, 6.0), 3.0)

    def test_brep_errors_give_the_byte_offset(self):
        text = read("face.brep")
        k = text.index("Surfaces ")
        bad = text[:k] + "Surfaces 999999999" + text[text.index("\n", k) :]
        with self.assertRaisesRegex(
            ValueError, r"Surfaces count 999999999 exceeds .* at byte %d" % (k + 9)
        ):
            core.adaptive_isocurve(bad, [0], core.IsoParams())

    def test_work_budget_is_a_parameter(self):
        p = core.PocketParams()
        p.tool_radius, p.stepover, p.safe_z = 3.0, 2.4, 10.0
        boundary = np.array(
            [[0, 0, 0, 0, 0], [100, 0, 0, 0, 0], [100, 60, 0, 0, 0], [0, 60, 0, 0, 0]], float
        )
        self.assertEqual(p.max_moves, 1e6)
        p.max_moves = 20
        with self.assertRaisesRegex(ValueError, "max_moves = 20"):
            core.spiral_pocket(boundary, [], p, [0.0])
        p.max_moves = 1e6
        res = core.spiral_pocket(boundary, [], p, [0.0])
        self.assertGreater(len(res.kind), 20)
        self.assertTrue(np.isfinite(res.xyz).all())


if __name__ == "__main__":
    unittest.main()
