"""The op's promise measured from outside (issue 10, habit 15) on models the
core's tests never used, built here with Part: a spherical dome cut from a
box, a B-spline bump on a saddle made from poles, the top of a torus. Each
Adaptive Isocurve job is posted with FreeCAD's linuxcnc post, read back by
rs274 and simulated by tests/sim's isocam_gcode_sim; the measured material
left and overcut must stay within sim_support.stated_bounds(op).

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_gcode_sim_built.py
"""

import unittest

import FreeCAD
import Part

import sim_support
from freecad_ext import adaptive_isocurve, scripting

V = FreeCAD.Vector


def dome():
    """A sphere of radius 12 centred 6 below the top of a box: the cap
    z >= 0 (convex, 452 mm^2) on a flat base."""
    sphere = Part.makeSphere(12.0, V(0, 0, -6))
    return sphere.common(Part.makeBox(30, 30, 20, V(-15, -15, 0)))


def bump():
    """A bicubic B-spline face 24 x 24 mm from 7 x 7 poles: a saddle
    z = (x^2 - y^2) / 60 with a bump of 4 mm in the middle (convex top,
    concave ring at its foot)."""
    import math

    n = 7
    poles = []
    for i in range(n):
        row = []
        for j in range(n):
            x, y = -12 + 24.0 * i / (n - 1), -12 + 24.0 * j / (n - 1)
            z = (x * x - y * y) / 60.0 + 4.0 * math.exp(-(x * x + y * y) / 30.0)
            row.append(V(x, y, z))
        poles.append(row)
    surf = Part.BSplineSurface()
    # clamped cubic knots, uniform inside
    knots = [0.0, 0.25, 0.5, 0.75, 1.0]
    mults = [4, 1, 1, 1, 4]
    surf.buildFromPolesMultsKnots(poles, mults, mults, knots, knots, False, False, 3, 3)
    return Part.Face(surf)


def torus_top():
    """The upper half of a torus (R = 10, r = 4): convex outside, saddle on
    the inner side."""
    torus = Part.makeTorus(10.0, 4.0)
    return torus.common(Part.makeBox(40, 40, 10, V(-20, -20, 0)))


class Built:
    def __init__(self, name, shape, ball_diameter):
        self.doc = FreeCAD.newDocument(name)
        self.doc_name = self.doc.Name
        self.model = self.doc.addObject("Part::Feature", "Model")
        self.model.Shape = shape
        self.job = scripting.make_job(self.model)
        self.tc = scripting.make_ball_end_tool_controller(self.job, ball_diameter)
        self.ball_diameter = ball_diameter

    @property
    def clone(self):
        return self.job.Model.Group[0]

    def op(self, faces, scallop):
        op = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME, parentJob=self.job, toolController=self.tc
        )
        op.Base = [(self.clone, ["Face%d" % f for f in faces])]
        op.ScallopHeight = scallop
        self.doc.recompute()
        return op

    def close(self):
        if self.doc_name in FreeCAD.listDocuments():
            FreeCAD.closeDocument(self.doc_name)


def faces_where(shape, test):
    return [i + 1 for i, f in enumerate(shape.Faces) if test(f)]


class BuiltModelsTest(unittest.TestCase):
    def run_case(self, name, shape, ball_diameter, scallop, pick):
        built = Built(name, shape, ball_diameter)
        self.addCleanup(built.close)
        faces = faces_where(built.clone.Shape, pick)
        self.assertTrue(faces, "no face picked on " + name)
        op = built.op(faces, scallop)
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        result = sim_support.measure(self, built.job, op, ball_diameter, spacing=0.03)
        sim_support.assert_within_stated(self, name, op, result)
        return result

    def test_the_check_sees_a_program_off_by_a_little(self):
        # The same chain on the dome's program with every feed 0.03 mm too
        # deep, then 0.03 mm too high: the measurement must follow.
        built = Built("DomeShifted", dome(), 6.0)
        self.addCleanup(built.close)
        faces = faces_where(built.clone.Shape, lambda f: f.Surface.TypeId == "Part::GeomSphere")
        op = built.op(faces, 0.01)
        deep = sim_support.measure(
            self,
            built.job,
            op,
            6.0,
            spacing=0.05,
            edit=lambda g: sim_support.shift_feeds_z(g, -0.03),
        )
        print(sim_support.describe("Dome 0.03 deep", op, deep))
        self.assertGreater(deep["overcut"]["max"], 0.03)
        self.assertLess(deep["overcut"]["max"], 0.03 + sim_support.stated_bounds(op)[1])
        high = sim_support.measure(
            self,
            built.job,
            op,
            6.0,
            spacing=0.05,
            edit=lambda g: sim_support.shift_feeds_z(g, 0.03),
        )
        print(sim_support.describe("Dome 0.03 high", op, high))
        self.assertGreater(high["left"]["max"], 0.03)
        self.assertLess(high["overcut"]["max"], 0.001)

    def test_dome(self):
        self.run_case("Dome", dome(), 6.0, 0.01, lambda f: f.Surface.TypeId == "Part::GeomSphere")

    def test_bspline_bump_on_a_saddle(self):
        self.run_case("Bump", bump(), 4.0, 0.01, lambda f: True)

    def test_torus_top(self):
        self.run_case(
            "Torus", torus_top(), 4.0, 0.01, lambda f: f.Surface.TypeId == "Part::GeomToroid"
        )


if __name__ == "__main__":
    unittest.main()
