"""The constant-scallop pattern seen from Python: the enum value, the
result's fields (no isocurves, a U or V start per face, the cutting length
the sum of the feed moves) and a measured certificate, on face.brep (a plate
with two holes, so the clipping to the wires is on the way)."""

import os
import sys
import unittest

sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))
import numpy as np  # noqa: E402

import isocam_core as core  # noqa: E402

DATA = os.environ.get("ISOCAM_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))


def params(**kw):
    p = core.IsoParams()
    p.ball_radius = 3.0
    p.scallop_height = 0.05
    p.safe_z = 100.0
    for k, v in kw.items():
        setattr(p, k, v)
    return p


class ConstantScallopOnPlate(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(os.path.join(DATA, "face.brep")) as f:
            cls.brep = f.read()
        cls.res = core.adaptive_isocurve(
            cls.brep, [0], params(pattern=core.IsoPattern.ConstantScallop)
        )
        m = cls.res.metrics
        print(
            f"\nconstant scallop: cutting {m.cutting_length:.0f} mm "
            f"(L* {m.lower_bound_length:.0f}), {m.sub_isocurves} pieces, "
            f"max spacing {m.max_iso_distance:.3f}, scallop {m.guaranteed_scallop:.4f}"
        )

    def test_result_fields(self):
        res = self.res
        self.assertEqual(len(res.curves), 0)
        self.assertIn(res.face_direction[0], ("U", "V"))
        kind, xyz = res.kind, res.xyz
        seg = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
        # 1e-6 mm: the same segment lengths summed in another order.
        self.assertAlmostEqual(
            seg[kind[1:] == core.FEED].sum(), res.metrics.cutting_length, delta=1e-6
        )

    def test_certificate_is_measured(self):
        m = self.res.metrics
        # Not the intent: on the plate the passes are the flat stepover apart,
        # and next to the holes' wires farther (the clipped pass is missing).
        # (1 - 1e-6): the measured distance is sampled and computed in
        # doubles; a pass exactly delta apart may measure a hair under it.
        self.assertGreaterEqual(m.max_iso_distance, m.delta * (1 - 1e-6))
        self.assertGreater(m.guaranteed_scallop, 0.05 * (1 - 1e-6))
        self.assertLess(m.guaranteed_scallop, 3.0)
        self.assertGreater(m.cutting_length, m.lower_bound_length)


if __name__ == "__main__":
    unittest.main()
