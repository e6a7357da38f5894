"""The parallel-plane baseline seen from Python, on MAT against adaptive
isocurves with the same scallop height.

Elber & Cohen's point about contouring (Figure 3b) is that equally spaced
planes are too sparse where the surface is nearly parallel to them: with the
flat-ground stepover the passes on MAT's steep walls are several deltas
apart, so the plane path is SHORTER than the adaptive one but does not give
the scallop height there. Spaced densely enough to bring its worst pass
distance down to about delta, the plane path is several times longer. Both
facts are checked here; the measured numbers are printed.
"""

import math
import os
import sys
import unittest

sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import numpy as np  # noqa: E402

import expected_figures  # noqa: E402  (tests/: the figures of tests/data/expected.txt)

import isocam_core as core  # noqa: E402

DATA = os.environ.get("ISOCAM_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))
R, H = 3.0, 0.05


def params(**kw):
    p = core.IsoParams()
    p.ball_radius = R
    p.scallop_height = H
    p.safe_z = 100.0
    for k, v in kw.items():
        setattr(p, k, v)
    return p


def describe(name, res):
    m = res.metrics
    return (
        f"{name}: cutting {m.cutting_length:.0f} mm, {m.retracts} retracts, "
        f"{m.sub_isocurves} pieces, largest pass distance {m.max_iso_distance:.3f} mm "
        f"(delta {m.delta:.3f}), unreachable {m.unreachable_length:.0f} mm"
    )


class ParallelPlanesOnMat(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(os.path.join(DATA, "MAT.brep")) as f:
            cls.mat = f.read()
        cls.adaptive = core.adaptive_isocurve(cls.mat, [0], params())
        cls.planes = core.adaptive_isocurve(
            cls.mat, [0], params(pattern=core.IsoPattern.ParallelPlanes)
        )
        print("\n" + describe("adaptive", cls.adaptive))
        print(describe("planes  ", cls.planes) + f", axis {cls.planes.plane_axis}")

    def test_result_fields(self):
        res = self.planes
        self.assertIn(res.plane_axis, (core.IsoPlaneAxis.X, core.IsoPlaneAxis.Y))
        self.assertEqual(res.face_direction, ["Auto"])
        self.assertEqual(len(res.curves), 0)
        expected_figures.check(
            self, "ParallelPlanes/MAT", "sub_isocurves", res.metrics.sub_isocurves
        )
        kind, xyz = res.kind, res.xyz
        seg = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
        # 1e-6 mm: the same segment lengths summed in another order.
        self.assertAlmostEqual(
            seg[kind[1:] == core.FEED].sum(), res.metrics.cutting_length, delta=1e-6
        )
        # Entries: plunges down and ramps (a plunge up is a fed lift).
        dz = np.diff(xyz[:, 2])
        entries = ((kind[1:] == core.PLUNGE) & (dz < 0)) | (kind[1:] == core.RAMP)
        self.assertEqual(int(entries.sum()), res.metrics.retracts)

    def test_every_cutting_point_is_in_a_plane_delta_apart(self):
        res = self.planes
        axis = 0 if res.plane_axis == core.IsoPlaneAxis.X else 1
        c = res.xyz[res.kind == core.FEED][:, axis]
        k = (c - c.min()) / res.metrics.delta
        # 1e-9 mm: each plane is the first plus an integer times delta, in
        # doubles; nothing but rounding may move a point off its plane.
        self.assertLess(np.abs(k - np.round(k)).max() * res.metrics.delta, 1e-9)

    def test_planes_are_too_sparse_on_steep_walls(self):
        # Figure 3b: same h, fewer and sparser passes than the adaptive path.
        a, p = self.adaptive.metrics, self.planes.metrics
        self.assertLessEqual(a.max_iso_distance, a.delta_max)
        expected_figures.check(
            self, "ParallelPlanes/MAT", "pass_distance_over_delta", p.max_iso_distance / p.delta
        )
        self.assertGreater(p.guaranteed_scallop, H)
        self.assertLess(p.cutting_length, a.cutting_length)

    def test_planes_dense_enough_are_longer(self):
        # Planes spaced delta^2 / (largest pass distance) apart, so that the
        # steepest pass distance comes down to about delta.
        a, p = self.adaptive.metrics, self.planes.metrics
        spacing = p.delta * p.delta / p.max_iso_distance
        h = R - math.sqrt(R * R - spacing * spacing / 4)
        dense = core.adaptive_isocurve(
            self.mat,
            [0],
            params(
                pattern=core.IsoPattern.ParallelPlanes,
                plane_axis=self.planes.plane_axis,
                scallop_height=h,
            ),
        )
        print(describe(f"planes h={h:.5f}", dense))
        expected_figures.check(
            self,
            "ParallelPlanes/MAT",
            "dense_pass_distance_over_delta",
            dense.metrics.max_iso_distance / a.delta,
        )
        expected_figures.check(
            self,
            "ParallelPlanes/MAT",
            "dense_over_adaptive_length",
            dense.metrics.cutting_length / a.cutting_length,
        )

    def test_axis_is_an_enum_of_the_params(self):
        p = params(plane_axis=core.IsoPlaneAxis.Y)
        self.assertEqual(p.plane_axis, core.IsoPlaneAxis.Y)
        with self.assertRaises(TypeError):
            p.plane_axis = 1


if __name__ == "__main__":
    unittest.main()
