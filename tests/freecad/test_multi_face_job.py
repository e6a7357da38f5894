"""A multi-face Job (shell1: 99 trimmed B-spline faces, all picked) with an
Adaptive Isocurve op: the certificate properties agree with the core, the
Pattern property selects a yardstick with the same guarantee, and the
posted G-code of both ops passes LinuxCNC's rs274.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_multi_face_job.py
"""

import os
import unittest

import Path

import fc_test_support as support
from freecad_ext import adaptive_isocurve, scripting

BALL_DIAMETER = 4.0  # mm
SCALLOP = 0.05  # mm


def make_op(setup, label, pattern, count=None):
    op = adaptive_isocurve.Create(
        adaptive_isocurve.OP_NAME, parentJob=setup.job, toolController=setup.ball_tc
    )
    op.Label = label
    op.ScallopHeight = SCALLOP
    op.Pattern = pattern
    count = count or len(setup.clone.Shape.Faces)
    op.Base = [(setup.clone, ["Face%d" % (i + 1) for i in range(count)])]
    return op


class MultiFaceJobTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.setup = support.JobSetup("MultiFace", "shell1.brep", BALL_DIAMETER)
        cls.adaptive = make_op(cls.setup, "Adaptive", "Adaptive")
        cls.uniform = make_op(cls.setup, "Uniform", "Uniform")
        cls.some = make_op(cls.setup, "FiveFaces", "Adaptive", count=5)
        cls.setup.doc.recompute()

    @classmethod
    def tearDownClass(cls):
        cls.setup.close()

    def test_ops_are_valid_on_99_faces(self):
        for op in (self.adaptive, self.uniform, self.some):
            self.assertNotIn("Invalid", op.State, op.getStatusString())
            self.assertEqual(len(op.DirectionUsed.split(", ")), 5 if op is self.some else 99)

    def test_certificate(self):
        for op in (self.adaptive, self.uniform):
            # The scallop promise holds, and the ratio is what it says (1e-6
            # relative and places=9: rounding of doubles, nothing else).
            self.assertLessEqual(op.GuaranteedScallop.Value, SCALLOP * (1 + 1e-6))
            self.assertGreater(op.LowerBoundLength.Value, 0)
            self.assertAlmostEqual(
                op.LengthRatio,
                op.CuttingLength.Value / op.LowerBoundLength.Value,
                places=9,
            )
            self.assertGreater(op.LengthRatio, 1.0)  # L* is a lower bound
            self.assertLessEqual(op.MaxIsoDistance.Value, op.IsoDistanceToleranceMax.Value)
            # Linking: far fewer retracts than pieces.
            self.assertLess(op.Retracts, op.SubIsocurves)
        self.assertAlmostEqual(
            self.adaptive.LowerBoundLength.Value, self.uniform.LowerBoundLength.Value
        )

    def test_unpicked_faces_are_protected_by_default(self):
        # Five faces picked: the other 94 are kept clear of the ball too
        # (ProtectModel, on by default), as the core does when asked.
        from freecad_ext import compat

        core = compat.import_core()
        self.assertTrue(self.some.ProtectModel)
        params = core.IsoParams()
        params.ball_radius = BALL_DIAMETER / 2
        params.scallop_height = SCALLOP
        params.safe_z = self.some.SafeHeight.Value
        brep = self.setup.clone.Shape.exportBrepToString()
        params.protect_unpicked_faces = True
        res = core.adaptive_isocurve(brep, list(range(5)), params)
        # The op stores the core's doubles: places=6 on lengths of metres is
        # rounding only.
        self.assertAlmostEqual(self.some.CuttingLength.Value, res.metrics.cutting_length, places=6)
        self.assertAlmostEqual(
            self.some.UnreachableLength.Value, res.metrics.unreachable_length, places=6
        )

    def test_linuxcnc_post_passes_rs274(self):
        rs274 = support.rs274_or_fail(self)
        ngc = os.path.join(support.temp_dir(self), "shell1.ngc")
        scripting.post_job(self.setup.job, ngc)
        run = scripting.run_rs274(ngc, {self.setup.ball_tc.ToolNumber: BALL_DIAMETER}, rs274=rs274)
        self.assertEqual(run.returncode, 0, run.errors)
        self.assertEqual(run.errors, [])
        # The interpreter's motions end with exactly the two ops' moves.
        both = Path.Path(
            self.adaptive.Path.Commands + self.uniform.Path.Commands + self.some.Path.Commands
        )
        support.assert_motions_end_with(self, run, both)


if __name__ == "__main__":
    unittest.main()
