"""5-Axis Strip Finish measured from outside on curved faces (issue 13): a
convex cylinder patch (its passes cross the pole of the A/C machine, A = 0,
where C turns by half a turn) and a B-spline saddle (concave across one way:
the lead is raised there), the saddle also with Strategy NormalIsocurves. As test_five_axis_finish.py's tilted plane: the
posted G-code read back by rs274 and swept by five_axis_check.py, which
shares nothing with the core; material left and overcut within the op's
GuaranteedScallop and GuaranteedOvercut. Its own file, small cases as
there (a few seconds each).

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_five_axis_sim.py
"""

import unittest

import Part

from test_five_axis_finish import FiveAxisFinishTest, cylinder_face, cylinder_patch, saddle


class CurvedFacesTest(FiveAxisFinishTest):
    # Only the cases below (the base class's tests run in their own file).
    test_tilted_plane = None
    test_ball_end_refused_by_name = None
    test_saved_document_reopens = None
    test_low_links_beside_a_tower = None

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


del FiveAxisFinishTest  # not collected twice

if __name__ == "__main__":
    unittest.main()
