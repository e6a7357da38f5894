"""5-Axis Strip Finish (issue 13) headless, measured from outside: on built
faces (a tilted plane, a convex cylinder patch, a B-spline saddle) each job
is posted with FreeCAD's linuxcnc post, read back by rs274 (which must
accept it), and swept by tests/freecad/five_axis_check.py, which shares
nothing with the core: the material left between passes and the overcut on
the face, sampled from OpenCASCADE, must stay within the op's
GuaranteedScallop and GuaranteedOvercut. Also: the G-code header states the
A/C convention, C never jumps by more than half a turn, a ball end is
refused by name, the saved document reopens with the op.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_five_axis_finish.py
"""

import math
import os
import re
import sys
import unittest

import FreeCAD
import Part

import fc_test_support as support
import five_axis_check as check
from freecad_ext import five_axis_finish, scripting

sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import expected_figures  # noqa: E402  (tests/: the figures of tests/data/expected.txt)

V = FreeCAD.Vector
# Small cases (the suite runs three times in CI): a 6 mm flat end and a
# scallop height of SCALLOP, strips about 3 mm wide, a few passes per face.
SCALLOP = 0.05
# The sweep's tool instances are STEP mm of tip travel apart (well below the
# strip width): between two, the disc's bottom, inclined at the lead, stands
# up to STEP / 2 x tan(lead) above where the continuous sweep cuts, so "left"
# may read that much high; "overcut" may read low by the rim's motion
# between instances, tiny. The face is sampled every SPACING mm for "left"
# (OVER_SPACING for the overcut), a few dozen samples across each strip.
STEP = 0.04
SIM_OVER = 0.0002
SPACING = 0.12
OVER_SPACING = 0.2


# The rapids are swept coarser (they only need to cut nothing): a rapid
# through the face is seen at any of these steps.
RAPID_STEP = 0.1
RAPID_ANGLE = 1.0


def sim_left(op, step=STEP):
    return 0.5 * step * math.tan(math.radians(op.MaxLeadUsed)) + 0.0002


def tilted_plane():
    """A 10 x 10 box top tilted by 15 degrees about X."""
    box = Part.makeBox(10, 10, 6, V(-5, -5, -6))
    box.rotate(V(0, 0, 0), V(1, 0, 0), 15)
    return box


def tilted_plane_and_tower():
    """tilted_plane() and, 11 mm beside it, a tower up to z = 20, which sets
    the safe height: the hops between passes go up there, the low links not."""
    tower = Part.makeBox(4, 4, 26, V(16, -2, -6))
    return Part.makeCompound([tilted_plane(), tower])


def tilted_top(shape):
    """1-based index of the highest face whose normal is tilted_plane()'s top's."""
    up = V(0, -math.sin(math.radians(15)), math.cos(math.radians(15)))
    faces = [i for i, f in enumerate(shape.Faces) if f.normalAt(0, 0).sub(up).Length < 1e-6]
    return 1 + max(faces, key=lambda i: shape.Faces[i].CenterOfMass.z)


def cylinder_patch():
    """A solid cylinder of radius 20 (axis along Y, 8 mm long) cut by the
    plane z = -2: its top is a convex cylindrical face about 17 mm wide."""
    cyl = Part.makeCylinder(20.0, 8.0, V(0, -4, -20), V(0, 1, 0))
    return cyl.common(Part.makeBox(40, 8, 20, V(-20, -4, -2)))


def cylinder_face(shape):
    return 1 + next(
        i for i, f in enumerate(shape.Faces) if f.Surface.TypeId == "Part::GeomCylinder"
    )


def saddle():
    """A bicubic B-spline face 10 x 10: z = (x^2 - y^2) / 40 (convex one way,
    concave the other: across the concave way -kappa R = 0.15 > sin 5 deg,
    so the lead is raised there)."""
    n = 6
    poles = [
        [
            V(
                -5 + 10.0 * i / (n - 1),
                -5 + 10.0 * j / (n - 1),
                ((-5 + 10.0 * i / (n - 1)) ** 2 - (-5 + 10.0 * j / (n - 1)) ** 2) / 40.0,
            )
            for j in range(n)
        ]
        for i in range(n)
    ]
    surf = Part.BSplineSurface()
    knots, mults = [0.0, 1.0 / 3, 2.0 / 3, 1.0], [4, 1, 1, 4]
    surf.buildFromPolesMultsKnots(poles, mults, mults, knots, knots, False, False, 3, 3)
    return Part.Face(surf)


class Built:
    def __init__(self, name, shape):
        self.doc = FreeCAD.newDocument(name)
        self.doc_name = self.doc.Name
        self.model = self.doc.addObject("Part::Feature", "Model")
        self.model.Shape = shape
        self.job = scripting.make_job(self.model)
        self.flat = scripting.make_tool_controller(self.job, "endmill.fcstd", 6.0)
        self.doc.recompute()

    @property
    def clone(self):
        return self.job.Model.Group[0]

    def op(self, faces, tc=None, **props):
        op = five_axis_finish.Create(
            five_axis_finish.OP_NAME, parentJob=self.job, toolController=tc or self.flat
        )
        op.Base = [(self.clone, ["Face%d" % f for f in faces])]
        props.setdefault("ScallopHeight", SCALLOP)
        for k, v in props.items():
            setattr(op, k, v)
        self.doc.recompute()
        return op

    def close(self):
        if self.doc_name in FreeCAD.listDocuments():
            FreeCAD.closeDocument(self.doc_name)


def top_face(shape):
    """1-based index of the face whose centre is highest."""
    best = max(range(len(shape.Faces)), key=lambda i: shape.Faces[i].CenterOfMass.z)
    return best + 1


class FiveAxisFinishTest(unittest.TestCase):
    def post_and_read(self, built, op):
        tmp = support.temp_dir(self)
        ngc = os.path.join(tmp, "five.ngc")
        gcode = scripting.post_job(built.job, ngc)
        rs274 = support.rs274_or_fail(self)
        tools = {tc.ToolNumber: 6.0 for tc in built.job.Tools.Group}
        run = scripting.run_rs274(ngc, tools, rs274=rs274)
        self.assertTrue(run.ok, "rs274 refused the program: %s" % run.errors[:5])
        return gcode, check.motions(run.canon)

    def run_case(self, name, shape, pick, corner=0.0, step=STEP, **props):
        """The op on the picked face with the 6 mm flat end, or (corner > 0)
        a 6 mm bull nose of that corner radius; measured from outside, the
        tool swept every `step` mm of tip travel."""
        built = Built(name, shape)
        self.addCleanup(built.close)
        face_no = pick(built.clone.Shape)
        tc = None
        if corner > 0:
            tc = scripting.make_bull_nose_tool_controller(built.job, 6.0, corner)
            built.doc.recompute()
        op = built.op([face_no], tc=tc, **props)
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        gcode, moves = self.post_and_read(built, op)
        # The convention is stated in the posted program.
        self.assertIn("[sin A sin C, -sin A cos C, cos A]", gcode)
        self.assertIn("tool tip = centre of the flat bottom", gcode)
        feeds = [m for m in moves if m[0] == "G1"]
        self.assertGreater(len(feeds), 10)
        for prev, cur in zip(moves, moves[1:]):
            self.assertLessEqual(
                abs(cur[5] - prev[5]), 180.0 + 1e-6, "C jumps: %s -> %s" % (prev, cur)
            )
        for m in moves:
            self.assertGreaterEqual(m[4], op.AMin.Value - 1e-3)
            self.assertLessEqual(m[4], op.AMax.Value + 1e-3)
        tips, axes = check.tool_instances(moves, step=step)
        face = built.clone.Shape.Faces[face_no - 1]
        pts, nrm = check.sample_face(face, SPACING, 0.5)
        left, _ = check.measure(pts, nrm, tips, axes, 3.0, op.ToolLength.Value, corner=corner)
        pts0, nrm0 = check.sample_face(face, OVER_SPACING, 0.0)
        _, over = check.measure(pts0, nrm0, tips, axes, 3.0, op.ToolLength.Value, corner=corner)
        # The rapids swept apart, the whole tool (reach: its far rim at the
        # top): none may cut the face (a retract starts where the tool
        # touches it, within the overcut).
        g0_tips, g0_axes = check.tool_instances(
            moves, step=RAPID_STEP, angle_step=RAPID_ANGLE, kind_swept="G0"
        )
        length = op.ToolLength.Value
        _, rapid_over = check.measure(
            pts0, nrm0, g0_tips, g0_axes, 3.0, length, reach=math.hypot(3.0, length), corner=corner
        )
        reached = left[left < math.inf]
        print(
            "%s: %d samples, %d reached; left max %.5f (guaranteed %.5f), overcut max %.5f "
            "(guaranteed %.5f); rapids: %d instances, overcut max %.5f; strip %.3f mm, "
            "%d passes, cutting %.1f mm, lead up to %.1f deg, machine time %.1f s"
            % (
                name,
                len(left),
                len(reached),
                reached.max() if len(reached) else -1,
                op.GuaranteedScallop.Value,
                over.max(),
                op.GuaranteedOvercut.Value,
                len(g0_tips),
                rapid_over.max(),
                op.StripWidth.Value,
                op.Passes,
                op.CuttingLength.Value,
                op.MaxLeadUsed,
                op.MachineTime,
            )
        )
        # Every sample of the face (away from its edges) is reached ...
        self.assertEqual(len(reached), len(left), "samples no pass comes near")
        # ... and within the guarantees.
        self.assertLessEqual(op.GuaranteedScallop.Value, op.ScallopHeight.Value + 1e-9)
        self.assertLessEqual(reached.max(), op.GuaranteedScallop.Value + sim_left(op, step))
        self.assertLessEqual(over.max(), op.GuaranteedOvercut.Value + SIM_OVER)
        self.assertLessEqual(rapid_over.max(), op.GuaranteedOvercut.Value + SIM_OVER, "a G0 cuts")
        return built, op, left, over

    def test_tilted_plane(self):
        _built, op, left, _over = self.run_case("Tilted", tilted_plane(), top_face)
        # Flat ground: the strip is the tilted disc's, 2 x_h with
        # R sin(lead) (1 - sqrt(1 - x_h^2 / R^2)) = h' (h' = h - errors, at
        # most h: 3.53 mm for h, lead 5 deg, R 3), and the cusps are really
        # there (the check sees material between passes): how near the strip
        # comes to that width and how high the cusps stand are the figures
        # FiveAxisFinish/Tilted of tests/data/expected.txt.
        r, lead = 3.0, math.radians(op.LeadAngle.Value)
        widest = 2 * r * math.sqrt(1 - (1 - op.ScallopHeight.Value / (r * math.sin(lead))) ** 2)
        self.assertLessEqual(op.StripWidth.Value, widest + 1e-6)  # 1e-6 mm: rounding
        expected_figures.check(
            self, "FiveAxisFinish/Tilted", "strip_over_widest", op.StripWidth.Value / widest
        )
        expected_figures.check(
            self, "FiveAxisFinish/Tilted", "left_over_scallop", left.max() / op.ScallopHeight.Value
        )

    def test_low_links_beside_a_tower(self):
        """The passes linked low (LowLinks) where the safe height is far above:
        the rapids swept from the posted program cut nothing (run_case), and
        against LowLinks off the rapid travel and MachineTime drop."""
        built, op, _left, _over = self.run_case("Tower", tilted_plane_and_tower(), tilted_top)
        low = (op.RapidLength.Value, op.MachineTime)
        op.LowLinks = False
        built.doc.recompute()
        hop = (op.RapidLength.Value, op.MachineTime)
        print(
            "Tower: rapid %.1f mm, machine time %.1f s; LowLinks off: %.1f mm, %.1f s" % (low + hop)
        )
        self.assertLess(low[0], 0.5 * hop[0])
        self.assertLess(low[1], hop[1])

    def test_lag_on_return(self):
        """LagOnReturn: the passes the zig-zag runs back keep the forward
        passes' tilt. Posted and swept within the guarantees (run_case); in
        the posted program the tool leans (off the face normal) along the
        feed on some passes and against it on others, with one C throughout;
        with the lead along every pass the axis swings between passes (here,
        passes down the 15 degree slope, A between 10 and 20 degrees). Less
        rotary travel and machine time, the same cutting length."""
        built, op, _left, _over = self.run_case("Lag", tilted_plane(), top_face, LagOnReturn=True)
        _gcode, moves = self.post_and_read(built, op)
        lag = (op.RotaryTravelA + op.RotaryTravelC, op.MachineTime, op.CuttingLength.Value)
        normal = built.clone.Shape.Faces[top_face(built.clone.Shape) - 1].normalAt(0, 0)
        along = against = 0.0  # mm of cutting moves leaning along, against their move
        cs = set()
        for prev, cur in zip(moves, moves[1:]):
            move = V(*[cur[i] - prev[i] for i in (1, 2, 3)])
            if cur[0] != "G1" or move.Length < 0.01:
                continue
            lean = V(*check.axis_of(cur[4], cur[5])).sub(normal)  # the lead, off the normal
            if lean.dot(move) > 0:
                along += move.Length
            else:
                against += move.Length
            cs.add(round(cur[5], 1))
        # 5 passes about 10 mm long: 3 run forward, 2 back.
        self.assertGreater(along, 25.0)
        self.assertGreater(against, 15.0)
        self.assertEqual(len(cs), 1, "C of the cutting moves: %s" % sorted(cs))
        op.LagOnReturn = False
        built.doc.recompute()
        lead = (op.RotaryTravelA + op.RotaryTravelC, op.MachineTime, op.CuttingLength.Value)
        print(
            "Lag: A + C travel %.1f deg, machine time %.1f s, cutting %.1f mm; lead: %.1f, %.1f, %.1f"
            % (lag + lead)
        )
        self.assertLess(lag[0], 0.5 * lead[0])
        self.assertLess(lag[1], lead[1])
        self.assertAlmostEqual(lag[2], lead[2], delta=1e-6 * lead[2])

    def test_ball_end_refused_by_name(self):
        built = Built("FiveBall", tilted_plane())
        self.addCleanup(built.close)
        ball = scripting.make_ball_end_tool_controller(built.job, 6.0)
        op = built.op([top_face(built.clone.Shape)], tc=ball)
        self.assertIn("Invalid", op.State)
        self.assertIn("not a flat end mill", op.getStatusString())
        self.assertEqual(len(op.Path.Commands), 0)

    def test_saved_document_reopens(self):
        built = Built("FiveSave", tilted_plane())
        self.addCleanup(built.close)
        op = built.op([top_face(built.clone.Shape)], LeadAngle=8.0)
        length = op.CuttingLength.Value
        self.assertGreater(length, 0)
        path = os.path.join(support.temp_dir(self), "five.FCStd")
        built.doc.saveAs(path)
        name = op.Name
        FreeCAD.closeDocument(built.doc.Name)
        doc = FreeCAD.openDocument(path)
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        again = doc.getObject(name)
        self.assertEqual(type(again.Proxy).__name__, "ObjectFiveAxisStripFinish")
        self.assertAlmostEqual(again.LeadAngle.Value, 8.0)
        again.touch()
        doc.recompute()
        self.assertNotIn("Invalid", again.State, again.getStatusString())
        self.assertAlmostEqual(again.CuttingLength.Value, length, delta=1e-6 * length)
        self.assertTrue(
            any(re.match(r"G1", c.Name) and "A" in c.Parameters for c in again.Path.Commands)
        )


if __name__ == "__main__":
    unittest.main()
