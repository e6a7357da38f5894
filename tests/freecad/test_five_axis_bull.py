"""5-Axis Strip Finish with a bull nose (issue 13), measured from outside: a
6 mm bull nose of corner radius 1 mm on the tilted plane (flat), the
cylinder patch (convex), a trough (concave: a groove of radius 15) and the
B-spline saddle (concave across one way),
posted, read back by rs274 and swept by five_axis_check.py as an exact torus
and cylinder (sharing nothing with the core): material left and overcut
within the op's GuaranteedScallop and GuaranteedOvercut. The strip on flat
ground is the core disc's ellipse offset by the corner: wider than the ball
of the corner radius, narrower than the flat end's.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_five_axis_bull.py
"""

import math
import unittest

import FreeCAD
import Part
from freecad_ext import compat

from test_five_axis_finish import (
    FiveAxisFinishTest,
    cylinder_face,
    cylinder_patch,
    saddle,
    tilted_plane,
    top_face,
)

CORNER = 1.0


def trough():
    """A 16 x 8 block whose top has a groove of radius 15 (axis along Y,
    13 mm above the top): a concave cylindrical face about 15 mm wide and
    2 mm deep (across it -kappa (R - rc) / (1 - rc / 15) = 0.14 > sin 5
    deg: the lead is raised)."""
    V = FreeCAD.Vector
    block = Part.makeBox(16, 8, 6, V(-8, -4, -6))
    return block.cut(Part.makeCylinder(15.0, 8.0, V(0, -4, 13), V(0, 1, 0)))


class BullNoseTest(FiveAxisFinishTest):
    # Only the cases below (the base class's tests run in their own file).
    test_tilted_plane = None
    test_ball_end_refused_by_name = None
    test_saved_document_reopens = None
    test_low_links_beside_a_tower = None
    test_lag_on_return = None

    def test_bull_nose_tilted_plane(self):
        built, op, _left, _over = self.run_case(
            "BullTilted", tilted_plane(), top_face, corner=CORNER
        )
        tool = built.job.Operations.Group[0].ToolController.Tool
        self.assertAlmostEqual(compat.corner_radius(tool), CORNER)
        h = op.ScallopHeight.Value
        lead = math.radians(op.LeadAngle.Value)
        ball = 2 * math.sqrt(2 * CORNER * h - h * h)
        flat = 2 * 3.0 * math.sqrt(1 - (1 - h / (3.0 * math.sin(lead))) ** 2)
        self.assertGreater(op.StripWidth.Value, ball)
        self.assertLess(op.StripWidth.Value, flat)

    def test_bull_nose_cylinder_patch(self):
        self.run_case("BullCylinder", cylinder_patch(), cylinder_face, corner=CORNER)

    def test_bull_nose_trough(self):
        _built, op, _left, _over = self.run_case(
            "BullTrough", trough(), cylinder_face, corner=CORNER
        )
        self.assertGreater(op.MaxLeadUsed, op.LeadAngle.Value)

    def test_bull_nose_bspline_saddle(self):
        self.run_case("BullSaddle", Part.Shape(saddle()), lambda s: 1, corner=CORNER)

    def test_ball_shaped_bull_nose_is_refused_by_name(self):
        # The corner is the whole radius, a ball (FlatRadius 0 on 0.20 and
        # 1.0, CornerRadius 3 on 1.1): refused naming the core's argument and
        # the property this FreeCAD's tool sets it by.
        from test_five_axis_finish import Built
        from freecad_ext import scripting

        built = Built("BullBall", tilted_plane())
        self.addCleanup(built.close)
        tc = scripting.make_bull_nose_tool_controller(built.job, 6.0, 3.0)
        op = built.op([top_face(built.clone.Shape)], tc=tc)
        self.assertIn("Invalid", op.State)
        self.assertIn("corner_radius", op.getStatusString())
        self.assertIn(compat.corner_radius_property(tc.Tool), op.getStatusString())
        self.assertEqual(len(op.Path.Commands), 0)


del FiveAxisFinishTest  # not collected twice

if __name__ == "__main__":
    unittest.main()
