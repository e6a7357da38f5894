"""Bad inputs to the Adaptive Isocurve op: each leaves that op invalid with an
empty path and a message naming the culprit, FreeCAD keeps running and the
other objects keep their values.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_bad_input.py
"""

import unittest

import FreeCAD
import Part

import fc_test_support as support
from freecad_ext import adaptive_isocurve, scripting


class BadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # One valid op, computed once: the bystander every test checks.
        cls.setup = support.JobSetup("IsoBad")
        cls.flat_tc = scripting.make_tool_controller(cls.setup.job, "endmill.fcstd", 6.0)
        cls.good = cls.new_op("Good", cls.setup.ball_tc)
        cls.setup.doc.recompute()
        cls.good_gcode = cls.good.Path.toGCode()

    @classmethod
    def tearDownClass(cls):
        cls.setup.close()

    @classmethod
    def new_op(cls, label, tc, faces=("Face1",)):
        op = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME, parentJob=cls.setup.job, toolController=tc
        )
        op.Label = label
        op.Base = [(cls.setup.clone, list(faces))] if faces else []
        return op

    def setUp(self):
        self.model_brep = self.setup.model.Shape.exportBrepToString()

    def recompute_expecting_error(self, op, *fragments):
        """Recompute; `op` must end invalid, empty, with all `fragments` in its message."""
        self.setup.doc.recompute()  # must not raise: FreeCAD keeps going
        message = op.getStatusString()
        self.assertIn("Invalid", op.State, message)
        for fragment in fragments:
            self.assertIn(fragment, message)
        self.assertEqual(len(op.Path.Commands), 0)
        self.assertEqual(op.SubIsocurves, 0)
        self.assertEqual(op.CuttingLength.Value, 0.0)
        self.assert_bystanders_unchanged()
        return message

    def assert_bystanders_unchanged(self):
        good = self.setup.doc.getObject(self.good.Name)
        self.assertNotIn("Invalid", good.State)
        self.assertEqual(good.Path.toGCode(), self.good_gcode)
        self.assertEqual(self.setup.model.Shape.exportBrepToString(), self.model_brep)
        self.assertGreater(len(FreeCAD.listDocuments()), 0)

    def test_flat_end_tool_is_refused_by_name(self):
        op = self.new_op("FlatTool", self.flat_tc)
        self.assertIs(op.ToolController, self.flat_tc)
        message = self.recompute_expecting_error(
            op, "FlatTool", self.flat_tc.Tool.Label, "not a ball end", "endmill"
        )
        self.assertIn(self.flat_tc.Label, message)

    def test_scallop_not_below_ball_radius_names_scallop_height(self):
        op = self.new_op("BigScallop", self.setup.ball_tc)
        for scallop in (3.0, 5.0):  # r = 3 mm
            op.ScallopHeight = scallop
            self.recompute_expecting_error(op, "scallop_height", "ScallopHeight")
            self.assertEqual(op.ScallopHeight.Value, scallop)  # not rewritten

    def test_chord_tolerance_over_the_overcut_budget_names_both(self):
        op = self.new_op("BigChord", self.setup.ball_tc)
        op.ChordTolerance = 0.01  # > OvercutTolerance 0.005 - gouge - rounding
        self.recompute_expecting_error(op, "ChordTolerance", "OvercutTolerance")

    def test_overcut_tolerance_under_its_fixed_parts_names_it(self):
        op = self.new_op("TinyOvercut", self.setup.ball_tc)
        op.OvercutTolerance = 0.001  # under gouge 0.001 + posted rounding
        self.recompute_expecting_error(op, "overcut_tolerance", "OvercutTolerance")

    def test_safe_height_below_the_path_names_safe_height(self):
        op = self.new_op("LowSafe", self.setup.ball_tc)
        op.setExpression("SafeHeight", None)
        op.SafeHeight = 10.0  # the terrain reaches 33 mm
        self.recompute_expecting_error(op, "safe_z", "SafeHeight")

    def test_no_faces_picked(self):
        op = self.new_op("NoFaces", self.setup.ball_tc, faces=())
        self.recompute_expecting_error(op, "no faces picked")

    def test_edge_instead_of_face_is_named(self):
        op = self.new_op("EdgePicked", self.setup.ball_tc, faces=("Edge1",))
        self.recompute_expecting_error(op, "Edge1", "not a face")

    def test_face_index_out_of_range_is_named(self):
        op = self.new_op("NoSuchFace", self.setup.ball_tc, faces=("Face7",))
        # FreeCAD itself may drop a stale sub-element from Base; either way
        # the op must not compute.
        self.setup.doc.recompute()
        self.assertIn("Invalid", op.State)
        self.assertEqual(len(op.Path.Commands), 0)
        self.assert_bystanders_unchanged()

    def test_op_recovers_when_the_input_is_fixed(self):
        op = self.new_op("Recovers", self.setup.ball_tc)
        op.ScallopHeight = 4.0
        self.recompute_expecting_error(op, "ScallopHeight")
        op.ScallopHeight = 0.05
        self.setup.doc.recompute()
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        self.assertGreater(op.SubIsocurves, 0)
        support.assert_ball_finishing_invariants(
            self, op, self.setup.clone.Shape.Faces[0], self.setup.ball_diameter / 2
        )
        # 1e-6 relative: the certificate is computed in doubles, not posted.
        self.assertLessEqual(op.GuaranteedScallop.Value, 0.05 * (1 + 1e-6))

    def test_job_without_ball_end_tool_cannot_create_the_op(self):
        setup = support.JobSetup("IsoNoBall")
        self.addCleanup(setup.close)
        # Keep only FreeCAD's default controller (a flat end mill).
        tc = setup.ball_tc
        setup.job.Tools.removeObject(tc)
        setup.doc.removeObject(tc.Tool.Name)
        setup.doc.removeObject(tc.Name)
        self.assertTrue(setup.job.Tools.Group)
        names = sorted(o.Name for o in setup.doc.Objects)
        with self.assertRaises(adaptive_isocurve.IsoCAMError) as caught:
            adaptive_isocurve.Create(adaptive_isocurve.OP_NAME, parentJob=setup.job)
        self.assertIn("no ball-end tool controller", str(caught.exception))
        self.assertEqual(sorted(o.Name for o in setup.doc.Objects), names)
        self.assertEqual(setup.job.Operations.Group, [])


def _bezier_face(poles):
    """The face of a Bezier surface through a square grid of poles."""
    n = len(poles)
    surface = Part.BezierSurface()
    surface.increase(n - 1, n - 1)
    for i, row in enumerate(poles):
        for j, p in enumerate(row):
            surface.setPole(i + 1, j + 1, FreeCAD.Vector(*p))
    return Part.Face(surface)


def _good_and_degenerate():
    """A compound of a 20 x 20 mm saddle (Face1) and a face with all its
    poles on one line, 40 mm below it (Face2: no area)."""
    saddle = _bezier_face(
        [[(10 * i, 10 * j, 2.0 * (i - 1) * (j - 1)) for j in range(3)] for i in range(3)]
    )
    degenerate = _bezier_face([[(10 * i + j, 50, -40) for j in range(3)] for i in range(3)])
    return Part.makeCompound([saddle, degenerate])


class BadFaceBesideGoodTest(unittest.TestCase):
    """Habit 4: a picked face the core cannot machine is a warning in the
    report naming it, the op is not in error and finishes the other face;
    only when every picked face fails is the op in error."""

    @classmethod
    def setUpClass(cls):
        cls.setup = support.JobSetup("IsoBadFace", shape=_good_and_degenerate())

    @classmethod
    def tearDownClass(cls):
        cls.setup.close()

    def new_op(self, label, faces):
        op = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME,
            parentJob=self.setup.job,
            toolController=self.setup.ball_tc,
        )
        op.Label = label
        op.ScallopHeight = 0.05
        op.Base = [(self.setup.clone, list(faces))]
        return op

    def recompute_logging(self):
        """Recompute; the warnings the op sent to the report view."""
        logged = []
        original = adaptive_isocurve.log.warning

        def record(message):
            logged.append(str(message))
            return original(message)

        adaptive_isocurve.log.warning = record
        try:
            self.setup.doc.recompute()
        finally:
            adaptive_isocurve.log.warning = original
        return logged

    def test_the_good_face_is_finished_and_the_bad_one_reported(self):
        op = self.new_op("GoodAndBad", ("Face1", "Face2"))
        logged = self.recompute_logging()
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        naming = [m for m in logged if "Face2" in m]
        self.assertEqual(len(naming), 1, logged)
        for fragment in ("GoodAndBad", "degenerate", "skipped", self.setup.clone.Label):
            self.assertIn(fragment, naming[0])
        self.assertFalse([m for m in logged if "Face1" in m], logged)
        self.assertGreater(op.SubIsocurves, 0)
        support.assert_ball_finishing_invariants(
            self, op, self.setup.clone.Shape.Faces[0], self.setup.ball_diameter / 2
        )
        self.assertLessEqual(op.GuaranteedScallop.Value, 0.05 * (1 + 1e-6))

    def test_only_the_bad_face_is_an_error_naming_it(self):
        op = self.new_op("OnlyBad", ("Face2",))
        self.setup.doc.recompute()
        message = op.getStatusString()
        self.assertIn("Invalid", op.State, message)
        self.assertIn("Face2", message)
        self.assertIn("no picked face could be finished", message)
        self.assertEqual(len(op.Path.Commands), 0)


if __name__ == "__main__":
    unittest.main()
