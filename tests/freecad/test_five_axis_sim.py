"""5-Axis Strip Finish measured from outside on curved faces (issue 13): a
convex cylinder patch (its passes cross the pole of the A/C machine, A = 0,
where C turns by half a turn) and a B-spline saddle (concave across one way:
the lead is raised there), the saddle also with Strategy NormalIsocurves;
and a valley z = c x^4 whose sides steepen faster than the curvature at
the contact tells, where the exact check raises the lead and the op traces
the paths again with the strips narrowed there; and a floor beside a block,
whose walls (not picked) the cutting end must not cut into. As
test_five_axis_finish.py's tilted plane: the
posted G-code read back by rs274 and swept by five_axis_check.py, which
shares nothing with the core; material left and overcut within the op's
GuaranteedScallop and GuaranteedOvercut. Its own file, small cases as
there (a few seconds each).

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_five_axis_sim.py
"""

import unittest

import FreeCAD
import numpy as np
import Part

import fc_test_support as support
import five_axis_check as check
from freecad_ext import scripting
from test_five_axis_finish import (
    SIM_OVER,
    Built,
    FiveAxisFinishTest,
    cylinder_face,
    cylinder_patch,
    saddle,
    sim_left,
)


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


def floor_and_block():
    """A 30 x 30 mm floor (the top of a 6 mm slab, z = 0) with an 8 x 8 mm
    block standing 10 mm high in its middle."""
    base = Part.makeBox(30, 30, 6, FreeCAD.Vector(-15, -15, -6))
    block = Part.makeBox(8, 8, 10, FreeCAD.Vector(-4, -4, 0))
    return base.fuse(block).removeSplitter()


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

    def mat_piece(self, name, u_range, v_range):
        """A document with the piece of MAT's face between the fractions
        `u_range` and `v_range` of its parameter ranges (closed with the test)."""
        mat = support.load_shape("MAT.brep").Faces[0]
        u0, u1, v0, v1 = mat.ParameterRange
        piece = mat.Surface.toShape(
            *(u0 + f * (u1 - u0) for f in u_range), *(v0 + f * (v1 - v0) for f in v_range)
        )
        built = Built(name, piece)
        self.addCleanup(built.close)
        return built

    def test_mat_piece_edges_and_swings(self):
        """An 8 x 8 mm piece of MAT (u and v from 0.3 and 0.4 of its range
        to a tenth more; concave ground tighter than the flat bottom at 5
        deg, rising beyond the piece's edges): where the disc
        overhangs an edge, the side standing on its rim reaches under the
        face's edge strip although every point of the disc is nearest the
        surface beyond the edge; the exact check measures the tool below
        the edge there (before it cut 0.108 mm below the face 0.025 mm from
        an edge). And the exact check raises the lead in steps, so the pose
        jumps between neighbouring positions and the halving between them
        ends at its depth limit (UnconvergedMoves): there the machine's
        swing is checked, and the path split where it would dig in
        (SwingsSplit). The posted program, swept with the tool turning at
        most 0.05 deg between instances, cuts no deeper than
        GuaranteedOvercut anywhere on the piece (samples 0.05 mm apart, up
        to 0.025 mm from its edges). Measured with the swing check off: the
        same overcut here (the core's check of the swing is sampled finer
        than the positions'; on a 19 x 20 mm piece, before the edge was
        checked, the unchecked swings cut 0.0063 mm against 0.0046). (The
        piece beside it, u from 0.4, was used until the exact check's
        projections converged: it has 4 such moves now, none split.) Where
        a run ends with the tool beyond the edge the rim crosses the edge
        between two of its samples and may dig in between them: when the
        paths moved (the retracing spaced for the leads raised within two
        radii), this sweep found 0.0198 mm there; the exact check now
        searches the rim between such samples."""
        built = self.mat_piece("MatPiece", (0.3, 0.4), (0.4, 0.5))
        op = built.op([1], Strategy="NormalIsocurves", ScallopHeight=0.01)
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        _gcode, moves = self.post_and_read(built, op)
        tips, axes = check.tool_instances(moves, step=0.02, angle_step=0.05)
        pts, nrm = check.sample_face(built.clone.Shape.Faces[0], 0.05, 0.025)
        _, over = check.measure(pts, nrm, tips, axes, 3.0, op.ToolLength.Value)
        print(
            "MAT piece: %d unconverged moves, %d split; %d samples, overcut max %.5f "
            "(guaranteed %.5f), cutting %.1f mm, unreachable %.1f mm"
            % (
                op.UnconvergedMoves,
                op.SwingsSplit,
                len(over),
                over.max(),
                op.GuaranteedOvercut.Value,
                op.CuttingLength.Value,
                op.UnreachableLength.Value,
            )
        )
        self.assertGreater(op.UnconvergedMoves, 5)
        self.assertGreater(op.SwingsSplit, 0)
        self.assertLess(op.SwingsSplit, op.UnconvergedMoves)
        self.assertLessEqual(over.max(), op.GuaranteedOvercut.Value + SIM_OVER)

    def test_mat_piece_isocurves_where_the_march_folds(self):
        """A 16 x 16 mm piece of MAT (u and v from 0.3 to 0.5 of their
        ranges), h 0.01: where the flat end's strip narrows fast along the
        march's front (concave bumps) the front folds, and StripEvaluation
        takes the adaptive isocurves' paths instead (they are shorter by
        over a tenth), which the op says in IsocurveFaces (0 with
        NormalIsocurves, where nothing is swapped); its cutting length then
        is the isocurves' (within a tenth: the march's cut 2.6 times that
        before) and its certificate within h."""
        built = self.mat_piece("MatFolds", (0.3, 0.5), (0.3, 0.5))
        strip = built.op([1], ScallopHeight=0.01)
        iso = built.op([1], Strategy="NormalIsocurves", ScallopHeight=0.01)
        for op in (strip, iso):
            self.assertNotIn("Invalid", op.State, op.getStatusString())
            self.assertLessEqual(op.GuaranteedScallop.Value, 0.01 + 1e-9)
        print(
            "MAT piece, StripEvaluation: %d isocurve faces, cutting %.1f mm; "
            "NormalIsocurves: %.1f mm"
            % (strip.IsocurveFaces, strip.CuttingLength.Value, iso.CuttingLength.Value)
        )
        self.assertEqual(strip.Strategy, "StripEvaluation")
        self.assertEqual(strip.IsocurveFaces, 1)
        self.assertEqual(iso.IsocurveFaces, 0)
        self.assertLessEqual(strip.CuttingLength.Value, 1.1 * iso.CuttingLength.Value)

    def test_floor_beside_a_block(self):
        """The floor picked, the block's walls not: where the cutting end
        comes near another face of the model (the walls; the slab's sides
        below the floor's outer edge) it is checked against that face as
        against the floor, its side too. Before, only the shank from R
        above the tip was: at the walls' foot the disc's rim cut 0.131 mm
        into them, a pass leaving the wall. Swept from outside, flat end and
        bull nose: no sample of the walls is cut deeper than
        GuaranteedOvercut, nor of the floor, and the floor is finished
        within GuaranteedScallop beyond 7 mm (2 R + 1) from the block and
        0.5 mm from its outer edge (a pass that leaves the block trails the
        tilted disc behind its contact: it starts 2 R out; the places
        nearer are reported in UnreachableLength)."""
        for corner in (0.0, 1.0):
            built = Built("Block%d" % int(corner), floor_and_block())
            self.addCleanup(built.close)
            faces = built.clone.Shape.Faces
            floor = next(
                i
                for i, f in enumerate(faces)
                if abs(f.CenterOfMass.z) < 1e-6 and f.normalAt(0, 0).z > 0.9
            )
            walls = [
                f
                for f in faces
                if abs(f.normalAt(0, 0).z) < 1e-6
                and max(abs(f.CenterOfMass.x), abs(f.CenterOfMass.y)) < 5
            ]
            self.assertEqual(len(walls), 4)
            tc = None
            if corner > 0:
                tc = scripting.make_bull_nose_tool_controller(built.job, 6.0, corner)
                built.doc.recompute()
            op = built.op([floor + 1], tc=tc)
            self.assertNotIn("Invalid", op.State, op.getStatusString())
            _gcode, moves = self.post_and_read(built, op)
            tips, axes = check.tool_instances(moves, step=0.04)
            length = op.ToolLength.Value
            wall_over = 0.0
            for wall in walls:
                # (the cutting end, R high, and the shank's first mm)
                pts, nrm = check.sample_face(wall, 0.1, 0.0)
                low = pts[:, 2] < 4.0
                _, over = check.measure(pts[low], nrm[low], tips, axes, 3.0, length, corner=corner)
                wall_over = max(wall_over, over.max())
            pts, nrm = check.sample_face(faces[floor], 0.3, 0.0)
            _, over = check.measure(pts, nrm, tips, axes, 3.0, length, corner=corner)
            pts_l, nrm_l = check.sample_face(faces[floor], 0.2, 0.5)
            away = np.max(np.abs(pts_l[:, :2]), axis=1) > 11.0
            left, _ = check.measure(
                pts_l[away], nrm_l[away], tips, axes, 3.0, length, corner=corner
            )
            print(
                "Block, corner %.1f: walls overcut max %.5f, floor overcut max %.5f "
                "(guaranteed %.5f); floor away from the block: %d samples, left max %.5f "
                "(guaranteed %.5f); cutting %.1f mm, unreachable %.1f mm"
                % (
                    corner,
                    wall_over,
                    over.max(),
                    op.GuaranteedOvercut.Value,
                    len(left),
                    left.max(),
                    op.GuaranteedScallop.Value,
                    op.CuttingLength.Value,
                    op.UnreachableLength.Value,
                )
            )
            self.assertLessEqual(wall_over, op.GuaranteedOvercut.Value + SIM_OVER)
            self.assertLessEqual(over.max(), op.GuaranteedOvercut.Value + SIM_OVER)
            self.assertLessEqual(left.max(), op.GuaranteedScallop.Value + sim_left(op))
            self.assertGreater(op.UnreachableLength.Value, 0.0)


del FiveAxisFinishTest  # not collected twice

if __name__ == "__main__":
    unittest.main()
