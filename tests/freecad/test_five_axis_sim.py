"""5-Axis Strip Finish measured from outside on curved faces (issue 13): a
convex cylinder patch (its passes cross the pole of the A/C machine, A = 0,
where C turns by half a turn) and a B-spline saddle (concave across one way:
the lead is raised there), the saddle also with Strategy NormalIsocurves;
and a valley z = c x^4 whose sides steepen faster than the curvature at
the contact tells, where the exact check raises the lead and the op traces
the paths again with the strips narrowed there. As test_five_axis_finish.py's tilted plane: the
posted G-code read back by rs274 and swept by five_axis_check.py, which
shares nothing with the core; material left and overcut within the op's
GuaranteedScallop and GuaranteedOvercut. Its own file, small cases as
there (a few seconds each).

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_five_axis_sim.py
"""

import unittest

import FreeCAD
import Part

from test_five_axis_finish import FiveAxisFinishTest, cylinder_face, cylinder_patch, saddle


def quartic_valley(c=0.001, a=6.0):
    """z = c x^4 over x in [-a, a], y in [0, 10]: a degree-4 Bezier in x
    (ordinates c a^4 (+-1), the polar form of x^4)."""
    surf = Part.BezierSurface()
    surf.increase(4, 1)
    for i in range(5):
        for j in range(2):
            z = c * a**4 * (1 if (4 - i) % 2 == 0 else -1)
            surf.setPole(i + 1, j + 1, FreeCAD.Vector(-a + 2 * a * i / 4.0, 10.0 * j, z))
    return Part.Face(surf)


class CurvedFacesTest(FiveAxisFinishTest):
    # Only the cases below (the base class's tests run in their own file).
    test_tilted_plane = None
    test_ball_end_refused_by_name = None
    test_saved_document_reopens = None
    test_low_links_beside_a_tower = None
    test_lag_on_return = None

    def test_cylinder_patch(self):
        self.run_case("Cylinder", cylinder_patch(), cylinder_face)

    def test_bspline_saddle(self):
        self.run_case("Saddle", Part.Shape(saddle()), lambda s: 1)

    def test_bspline_saddle_normal_isocurves(self):
        _built, iso, _left, _over = self.run_case(
            "SaddleIso", Part.Shape(saddle()), lambda s: 1, Strategy="NormalIsocurves"
        )
        self.assertEqual(iso.Strategy, "NormalIsocurves")
        self.assertGreater(iso.MaxLeadUsed, iso.LeadAngle.Value)  # raised on the concave side

    def test_valley_traced_again_for_raised_leads(self):
        built, op, _left, _over = self.run_case(
            "Valley",
            Part.Shape(quartic_valley()),
            lambda s: 1,
            step=0.005,  # the sweep's sawtooth is step / 2 x tan(lead), the lead up to 45 deg
            Direction="U",
            ScallopHeight=0.02,
        )
        self.assertGreater(op.MaxLeadUsed, 10.0)


del FiveAxisFinishTest  # not collected twice

if __name__ == "__main__":
    unittest.main()
