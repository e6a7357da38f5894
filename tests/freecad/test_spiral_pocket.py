"""A Job with a Spiral Pocket and a Z-level Roughing op, end to end:
op -> Path (G1 and G2/G3) -> linuxcnc post -> rs274, and the invariants on
the posted path: no tool centre closer than r to a wall or island, no
reachable floor area left uncut, stock left on the model by the roughing.

The model: a 120 x 80 x 20 block with a 100 x 60 pocket 10 deep, two round
islands and a B-spline island standing in it (the islands come from the
material above the floor, as in FreeCAD's Pocket Shape).

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_spiral_pocket.py
"""

import math
import os
import unittest

import FreeCAD
import Part

import fc_test_support as support
from freecad_ext import compat, pocket_glue, scripting, spiral_pocket, zlevel_roughing

TOOL_DIAMETER = 6.0
R = TOOL_DIAMETER / 2
TOL = 0.01  # the ops' Tolerance (free curves to arcs)
FLOOR_Z = 10.0


def pocket_model():
    body = Part.makeBox(120, 80, 20).cut(Part.makeBox(100, 60, 10, FreeCAD.Vector(10, 10, FLOOR_Z)))
    body = body.fuse(Part.makeCylinder(8, 10, FreeCAD.Vector(40, 35, FLOOR_Z)))
    body = body.fuse(Part.makeCylinder(5, 10, FreeCAD.Vector(92, 56, FLOOR_Z)))
    blob = [
        FreeCAD.Vector(
            75 + 9 * (1 + 0.3 * math.sin(3 * t)) * math.cos(t),
            30 + 9 * (1 + 0.3 * math.sin(3 * t)) * math.sin(t),
            FLOOR_Z,
        )
        for t in (2 * math.pi * i / 24 for i in range(24))
    ]
    spline = Part.BSplineCurve()
    spline.interpolate(blob, PeriodicFlag=True)
    face = Part.Face(Part.Wire([spline.toShape()]))
    body = body.fuse(face.extrude(FreeCAD.Vector(0, 0, 10)))
    return body.removeSplitter()


class PocketJob:
    def __init__(self, name):
        self.doc = FreeCAD.newDocument(name)
        self.doc_name = self.doc.Name
        model = self.doc.addObject("Part::Feature", "Model")
        model.Shape = pocket_model()
        self.job = scripting.make_job(model)
        self.tc = scripting.make_tool_controller(self.job, "endmill.fcstd", TOOL_DIAMETER)
        self.doc.recompute()
        clone = self.job.Model.Group[0]
        self.clone = clone
        self.floor_index = next(
            i
            for i, f in enumerate(clone.Shape.Faces)
            # The floor is built at FLOOR_Z exactly; 1e-6 mm is the bounding
            # box's margin (OpenCASCADE grows boxes by the tolerance, 1e-7).
            if abs(f.BoundBox.ZMin - FLOOR_Z) < 1e-6 and abs(f.BoundBox.ZMax - FLOOR_Z) < 1e-6
        )
        self.pocket = spiral_pocket.Create(
            spiral_pocket.OP_NAME, parentJob=self.job, toolController=self.tc
        )
        self.pocket.Base = [(clone, ["Face%d" % (self.floor_index + 1)])]
        self.pocket.StepDown = 4
        self.rough = zlevel_roughing.Create(
            zlevel_roughing.OP_NAME, parentJob=self.job, toolController=self.tc
        )
        self.rough.StepDown = 5
        self.doc.recompute()

    def close(self):
        if self.doc_name in FreeCAD.listDocuments():
            FreeCAD.closeDocument(self.doc_name)


class SpiralPocketJobTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.setup = PocketJob("SpiralPocketJob")
        cls.core = compat.import_core()

    @classmethod
    def tearDownClass(cls):
        cls.setup.close()

    def floor_profiles(self):
        brep = self.setup.clone.Shape.exportBrepToString()
        return self.core.face_region(brep, self.setup.floor_index, TOL / 50)

    def test_ops_are_valid_with_their_results(self):
        for op in (self.setup.pocket, self.setup.rough):
            self.assertNotIn("Invalid", op.State, op.getStatusString())
            self.assertGreater(op.Loops, 0)
            self.assertGreater(op.CuttingLength.Value, 0)
            self.assertEqual(op.getPropertyStatus("Loops")[:2], ["ReadOnly", "Output"])
        op = self.setup.pocket
        self.assertAlmostEqual(op.FinalDepth.Value, FLOOR_Z, places=9)
        self.assertEqual(op.Levels, len(pocket_glue.depth_levels(op)))
        self.assertGreater(op.Arcs, 0)  # round islands -> G2/G3
        names = {c.Name for c in op.Path.Commands}
        self.assertTrue({"G2"} <= names or {"G3"} <= names, names)

    def test_pocket_path_is_the_core_path(self):
        op = self.setup.pocket
        params = pocket_glue.pocket_params(op, self.core, R, TOL, op.ScallopHeight.Value)
        res = self.core.pocket_faces(
            self.setup.clone.Shape.exportBrepToString(),
            [self.setup.floor_index],
            params,
            pocket_glue.depth_levels(op),
            False,
        )
        self.assertEqual(op.CLPoints, res.metrics.cl_points)
        self.assertEqual(op.Retracts, res.metrics.retracts)
        kind, xyz, _ = pocket_glue.arrays_from_path(op.Path)
        # The op adds the move to clearance height and across, and the final
        # retract; the rest is the core's moves.
        self.assertEqual(len(kind) - 3, len(res.kind))
        for a, b in zip(xyz[2:-1].tolist(), res.xyz.tolist()):
            for u, v in zip(a, b):
                # The glue copies the core's doubles into Path.Commands and
                # back: 1e-9 mm is rounding of that round trip only.
                self.assertAlmostEqual(u, v, delta=1e-9)
        # Feeds by FreeCAD's setFeedRate, which on this path gives what the
        # core's move kinds say (the posted G-code of the kinds): plunges at
        # VertFeed, every other cutting move at HorizFeed; G0 gets the tool
        # controller's rapid rate (not posted by linuxcnc).
        tc = op.ToolController
        horiz, vert = tc.HorizFeed.Value, tc.VertFeed.Value
        self.assertNotEqual(horiz, vert)
        moves = [c for c in op.Path.Commands if c.Name in ("G0", "G1", "G2", "G3")]
        rapids = (tc.HorizRapid.Value, tc.VertRapid.Value)
        plunges = 0
        for command, k in zip(moves[2:-1], res.kind.tolist()):
            feed = command.Parameters["F"]
            if k == self.core.RAPID:
                self.assertIn(feed, rapids)
            elif k == self.core.PLUNGE:
                self.assertEqual(feed, vert)
                plunges += 1
            else:
                self.assertEqual(feed, horiz, command.toGCode())
        self.assertGreater(plunges, 0)

    def test_pocket_clears_the_islands_and_the_whole_floor(self):
        kind, xyz, centre = pocket_glue.arrays_from_path(self.setup.pocket.Path)
        report = self.core.pocket_coverage(
            self.floor_profiles(), kind, xyz, centre, R, FLOOR_Z, 0.2, 2 * TOL
        )
        FreeCAD.Console.PrintMessage("spiral pocket coverage: %s\n" % report)
        self.assertEqual(report["outside_samples"], 0)
        self.assertGreaterEqual(report["min_clearance"], R - 1.05 * TOL)
        self.assertEqual(report["uncut_reachable_area"], 0.0)
        # Only the four corners of the 100 x 60 pocket are out of reach.
        corners = 4 * R * R * (1 - math.pi / 4)
        self.assertLess(report["uncut_area"], 1.5 * corners + 1.0)

    def test_roughing_leaves_stock_on_the_model(self):
        op = self.setup.rough
        model = self.setup.clone.Shape
        stl = op.StockToLeave.Value
        checked = 0
        for name, x, y, z in support.path_points(op.Path)[::7]:
            if name != "G1" or z > 19.0:
                continue
            # The flat end mill's disk at the tip: nothing of the model at
            # or above z may come closer than r + StockToLeave to its axis.
            above = model.common(Part.makeBox(400, 400, 40, FreeCAD.Vector(-150, -150, z + 1e-3)))
            if above.isNull() or not above.Solids:
                continue
            axis = Part.LineSegment(FreeCAD.Vector(x, y, z), FreeCAD.Vector(x, y, 60)).toShape()
            d = axis.distToShape(above)[0]
            self.assertGreaterEqual(d, R + stl - 2 * TOL, (x, y, z))
            checked += 1
            if checked >= 40:
                break
        self.assertGreater(checked, 10)

    def test_linuxcnc_post_passes_rs274(self):
        rs274 = support.rs274_or_fail(self)
        tmp = support.temp_dir(self)
        ngc = os.path.join(tmp, "pocket.ngc")
        gcode = scripting.post_job(self.setup.job, ngc)
        lines = [line.strip() for line in gcode.splitlines()]
        arcs = sum(1 for line in lines if line.startswith(("G2 ", "G3 ")))
        self.assertGreater(arcs, 0)
        run = scripting.run_rs274(ngc, {self.setup.tc.ToolNumber: TOOL_DIAMETER}, rs274=rs274)
        self.assertEqual(run.returncode, 0, run.errors)
        self.assertEqual(run.errors, [])
        # Every G2/G3 reached the interpreter as an arc.
        self.assertEqual(sum(1 for line in run.canon if "ARC_FEED(" in line), arcs)


class BadInputTest(unittest.TestCase):
    def test_no_floor_face_makes_the_op_invalid_with_a_message(self):
        setup = PocketJob("SpiralPocketBad")
        self.addCleanup(setup.close)
        op = setup.pocket
        op.Base = []
        setup.doc.recompute()
        self.assertIn("Invalid", op.State)
        self.assertIn("no faces picked", op.getStatusString())
        self.assertEqual(len(op.Path.Commands), 0)

    def test_out_of_range_tolerance_names_the_property(self):
        setup = PocketJob("SpiralPocketTol")
        self.addCleanup(setup.close)
        op = setup.pocket
        op.Tolerance = 5.0  # > r / 4
        setup.doc.recompute()
        self.assertIn("Invalid", op.State)
        self.assertIn("property Tolerance", op.getStatusString())


if __name__ == "__main__":
    unittest.main()
