"""A Job with an Adaptive Isocurve op on the MAT terrain, end to end:
op -> Path -> linuxcnc post -> rs274, and save / close / reopen / recompute.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_adaptive_isocurve_job.py
"""

import os
import unittest

import FreeCAD

import fc_test_support as support
from freecad_ext import adaptive_isocurve, compat, scripting

SCALLOP = 0.01  # mm, the op's default
BALL_DIAMETER = 6.0  # mm
COORD_TOL = 1e-9  # mm, glue conversions are exact
STORED_TOL = 1e-6  # mm, a saved Path keeps 6 decimals (its G-code text)


def make_op(setup, label="AdaptiveIsocurve"):
    op = adaptive_isocurve.Create(
        adaptive_isocurve.OP_NAME, parentJob=setup.job, toolController=setup.ball_tc
    )
    op.Label = label
    op.Base = [(setup.clone, ["Face1"])]
    setup.doc.recompute()
    return op


def expected_core_result(op, clone):
    """What the op must have asked the core for (the documented mapping)."""
    core = compat.import_core()
    params = core.IsoParams()
    params.ball_radius = BALL_DIAMETER / 2
    params.scallop_height = op.ScallopHeight.Value
    params.chord_tolerance = op.ChordTolerance.Value
    params.overcut_tolerance = op.OvercutTolerance.Value
    params.posted_resolution = 10.0**-op.PostPrecision
    params.air_clearance = op.AirClearance.Value
    tc = op.ToolController
    params.feed_rate = tc.HorizFeed.Value * 60 if tc.HorizFeed.Value > 0 else 1200.0
    params.plunge_rate = tc.VertFeed.Value * 60 if tc.VertFeed.Value > 0 else 400.0
    params.rapid_rate = op.RapidRate
    params.direction = core.IsoDirection.Auto
    params.safe_z = op.SafeHeight.Value
    return core.adaptive_isocurve(clone.Shape.exportBrepToString(), [0], params)


class AdaptiveIsocurveJobTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.setup = support.JobSetup("IsoJob")
        cls.op = make_op(cls.setup)

    @classmethod
    def tearDownClass(cls):
        cls.setup.close()

    def test_op_is_valid_with_defaults(self):
        op = self.op
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        self.assertAlmostEqual(op.ScallopHeight.Value, SCALLOP)
        self.assertAlmostEqual(op.ChordTolerance.Value, 0.0)  # derived
        self.assertAlmostEqual(op.OvercutTolerance.Value, 0.005)
        self.assertAlmostEqual(op.RapidRate, 5000.0)  # mm/min
        self.assertEqual(op.Direction, "Auto")
        self.assertIs(op.ToolController, self.setup.ball_tc)

    def test_path_is_the_core_path_with_entry_and_exit(self):
        op, tc = self.op, self.setup.ball_tc
        res = expected_core_result(op, self.setup.clone)
        clear, safe = op.ClearanceHeight.Value, op.SafeHeight.Value
        x0, y0 = res.xyz[0][0], res.xyz[0][1]
        self.assertAlmostEqual(res.xyz[0][2], safe, delta=COORD_TOL)
        expected = [("G0", {"Z": clear}), ("G0", {"X": x0, "Y": y0, "Z": clear})]
        feed = {0: None, 1: tc.HorizFeed.Value, 2: tc.VertFeed.Value, 5: tc.HorizFeed.Value}
        for k, (x, y, z) in zip(res.kind.tolist(), res.xyz.tolist()):
            params = {"X": x, "Y": y, "Z": z}
            if feed[k] is not None:
                params["F"] = feed[k]
            expected.append(("G0" if k == 0 else "G1", params))
        expected.append(("G0", {"Z": clear}))

        commands = op.Path.Commands
        self.assertEqual(commands[0].Name, "(%s)" % op.Label)
        self.assertEqual(len(commands) - 1, len(expected))
        for i, (command, (name, params)) in enumerate(zip(commands[1:], expected)):
            self.assertEqual(command.Name, name, "command %d" % (i + 1))
            self.assertEqual(sorted(command.Parameters), sorted(params))
            for key, value in params.items():
                self.assertAlmostEqual(
                    command.Parameters[key],
                    value,
                    delta=COORD_TOL,
                    msg="%d %s" % (i, key),
                )

    def test_certificate_matches_the_core(self):
        op = self.op
        m = expected_core_result(op, self.setup.clone).metrics
        # The op stores the core's doubles in Quantities: equal to rounding.
        # places=6 on lengths of metres and 9 on tolerances of a few
        # hundredths of a mm are both about 1e-12 relative.
        self.assertAlmostEqual(op.CuttingLength.Value, m.cutting_length, places=6)
        self.assertAlmostEqual(op.RapidLength.Value, m.rapid_length, places=6)
        self.assertAlmostEqual(op.PlungeLength.Value, m.plunge_length, places=6)
        self.assertEqual(op.SubIsocurves, m.sub_isocurves)
        self.assertEqual(op.Retracts, m.retracts)
        self.assertAlmostEqual(op.IsoDistanceTolerance.Value, m.delta, places=9)
        self.assertAlmostEqual(op.MaxIsoDistance.Value, m.max_iso_distance, places=9)
        self.assertAlmostEqual(op.GuaranteedScallop.Value, m.guaranteed_scallop, places=9)
        self.assertAlmostEqual(op.GuaranteedOvercut.Value, m.guaranteed_overcut, places=9)
        self.assertAlmostEqual(op.ChordToleranceUsed.Value, m.chord_tolerance, places=9)
        self.assertAlmostEqual(op.CuttingTime, m.cutting_time, places=6)
        self.assertIn(op.DirectionUsed, ("U", "V"))
        # The certificates the op exists for: within the requests (1e-6 and
        # 1e-9 relative: rounding of the doubles they are computed in).
        self.assertLessEqual(op.GuaranteedScallop.Value, SCALLOP * (1 + 1e-6))
        self.assertLessEqual(op.GuaranteedOvercut.Value, op.OvercutTolerance.Value * (1 + 1e-9))

    def test_machine_time_agrees_with_the_posted_commands_and_cycle_time(self):
        """Recomputed here from the op's commands (each G1 at its own F,
        FreeCAD's mm/s; G0 at RapidRate; the two lead-in moves from the
        unknown start left out): MachineTime, and FreeCAD's CycleTime."""
        op = self.op
        rapid = op.RapidRate / 60.0  # mm/s
        seconds, pos, moves = 0.0, None, 0
        for c in op.Path.Commands:
            if c.Name not in ("G0", "G1"):
                continue
            moves += 1
            p = c.Parameters
            nxt = [p.get(a, pos[i] if pos else 0.0) for i, a in enumerate("XYZ")]
            if pos is not None and moves > 2:
                d = sum((u - v) ** 2 for u, v in zip(pos, nxt)) ** 0.5
                seconds += d / (rapid if c.Name == "G0" else p["F"])
            pos = nxt
        # 1e-6 relative: the same moves summed here in Python, in another
        # order; CycleTime below is whole seconds, so 1 s.
        self.assertAlmostEqual(op.MachineTime, seconds, delta=1e-6 * seconds)
        h, m, s = (int(v) for v in op.CycleTime.split(":"))
        self.assertLessEqual(abs(h * 3600 + m * 60 + s - seconds), 1.0)
        # The core's estimate differs only by the op's rapids between
        # ClearanceHeight and SafeHeight, down at the start and up at the end.
        core = expected_core_result(op, self.setup.clone).metrics
        lead = 2 * (op.ClearanceHeight.Value - op.SafeHeight.Value) / rapid
        self.assertAlmostEqual(op.MachineTime, core.machine_time + lead, delta=1e-6 * seconds)
        self.assertGreater(op.SubIsocurves, 0)
        self.assertEqual(op.getPropertyStatus("CuttingLength")[:2], ["ReadOnly", "Output"])

    def test_feed_moves_stay_on_the_face_and_reach_its_sides(self):
        # Entry and exit at ClearanceHeight, every feed move within the face's
        # box and no deeper into the face than OvercutTolerance (the support's
        # invariants); and a ball of radius r touching the face with its tip
        # at z has its tip at most r below the face's lowest point.
        face = self.setup.clone.Shape.Faces[0]
        bb, r = face.BoundBox, BALL_DIAMETER / 2
        tol = support.DISTANCE_TOL
        feeds = support.assert_ball_finishing_invariants(self, self.op, face, r)
        for _name, x, y, z in feeds:
            self.assertGreaterEqual(z, bb.ZMin - r - tol, (x, y, z))
        # Every point of the face is touched (Definition 1), those on the
        # sides of its box too; the tip is within r of the contact point in
        # x and y, so the tips reach within r of each side.
        xs, ys = [p[1] for p in feeds], [p[2] for p in feeds]
        self.assertLessEqual(min(xs), bb.XMin + r + tol)
        self.assertGreaterEqual(max(xs), bb.XMax - r - tol)
        self.assertLessEqual(min(ys), bb.YMin + r + tol)
        self.assertGreaterEqual(max(ys), bb.YMax - r - tol)

    def test_user_properties_are_not_rewritten(self):
        op = self.op
        before = (
            op.ScallopHeight.Value,
            op.ChordTolerance.Value,
            op.Direction,
            op.SafeHeight.Value,
            op.ClearanceHeight.Value,
            op.Base,
        )
        op.touch()
        self.setup.doc.recompute()
        after = (
            op.ScallopHeight.Value,
            op.ChordTolerance.Value,
            op.Direction,
            op.SafeHeight.Value,
            op.ClearanceHeight.Value,
            op.Base,
        )
        self.assertEqual(before, after)

    def test_linuxcnc_post_passes_rs274(self):
        rs274 = support.rs274_or_fail(self)
        tmp = support.temp_dir(self)
        ngc = os.path.join(tmp, "job.ngc")
        gcode = scripting.post_job(self.setup.job, ngc)
        self.assertTrue(os.path.isfile(ngc))
        lines = [line.strip() for line in gcode.splitlines()]

        op, tc = self.op, self.setup.ball_tc
        n = tc.ToolNumber
        self.assertIn("M6 T%d" % n, lines)
        self.assertIn("G43 H%d" % n, lines)
        # Each version's own post-processing: FreeCAD 1.0+ moves nothing
        # before the first tool change (no move before G43); 0.20's post
        # command goes to clearance height after the fixture's G54.
        before_m6 = lines[: lines.index("M6 T%d" % n)]
        moves = [line for line in before_m6 if line.split(" ")[0] in ("G0", "G1", "G00", "G01")]
        if compat.version_tuple() >= (1, 0):
            self.assertEqual(moves, [])
        else:
            self.assertEqual(len(moves), 1)
            self.assertTrue(moves[0].startswith("G0 Z"), moves)
        start = lines.index("(%s)" % op.Label)
        clear, safe = op.ClearanceHeight.Value, op.SafeHeight.Value
        _, x0, y0, _ = support.path_points(op.Path)[2]
        _, px, py, pz = support.path_points(op.Path)[3]
        _, qx, qy, qz = support.path_points(op.Path)[4]
        # Down at rapid to near the surface, then the entry fed (a plunge at
        # VertFeed, or a ramp along the pass at HorizFeed).
        entry_feed = op.Path.Commands[5].Parameters["F"] * 60
        self.assertEqual(
            lines[start + 1 : start + 6],
            [
                "G0 Z%.3f" % clear,
                "G0 X%.3f Y%.3f Z%.3f" % (x0, y0, clear),
                "G0 X%.3f Y%.3f Z%.3f" % (x0, y0, safe),
                "G0 X%.3f Y%.3f Z%.3f" % (px, py, pz),
                "G1 X%.3f Y%.3f Z%.3f F%.3f" % (qx, qy, qz, entry_feed),
            ],
        )

        run = scripting.run_rs274(ngc, {n: BALL_DIAMETER}, rs274=rs274)
        self.assertEqual(run.returncode, 0, run.errors)
        self.assertEqual(run.errors, [])
        # The interpreter's motions end with exactly the op's moves.
        support.assert_motions_end_with(self, run, op.Path)


class CancelTest(unittest.TestCase):
    def test_cancel_from_another_thread_leaves_the_op_empty_and_invalid(self):
        import threading
        import time

        setup = support.JobSetup("IsoCancel")
        self.addCleanup(setup.close)
        op = make_op(setup)
        op.ScallopHeight = 0.001  # long enough to be caught while running
        cancelled = []

        def cancel_when_running():
            deadline = time.monotonic() + 30
            while time.monotonic() < deadline:
                progress = getattr(op.Proxy, "active_progress", None)
                if progress is not None:
                    progress.cancel()
                    cancelled.append(progress.fraction)
                    return
                time.sleep(0.001)

        watcher = threading.Thread(target=cancel_when_running)
        watcher.start()
        setup.doc.recompute()
        watcher.join()
        self.assertEqual(len(cancelled), 1)
        self.assertIn("Invalid", op.State)
        self.assertIn("cancelled", op.getStatusString())
        self.assertEqual(len(op.Path.Commands), 0)
        self.assertIsNone(op.Proxy.active_progress)


class SetupSheetTest(unittest.TestCase):
    def test_new_op_takes_the_setup_sheet_default(self):
        setup = support.JobSetup("IsoSheet")
        self.addCleanup(setup.close)
        sheets, name = compat.PathSetupSheet, adaptive_isocurve.OP_NAME
        self.assertIn(name, sheets._RegisteredOps)
        prototype = sheets._RegisteredOps[name].prototype(name)
        for prop in adaptive_isocurve.SetupProperties():
            prototype.getProperty(prop)  # each one exists on the prototype
        prototype.getProperty("ScallopHeight").setupProperty(
            setup.job.SetupSheet,
            sheets.OpPropertyName(name, "ScallopHeight"),
            sheets.OpPropertyGroup(name),
            0.05,
        )
        op = make_op(setup)
        self.assertAlmostEqual(op.ScallopHeight.Value, 0.05)
        # 1e-6 relative: the certificate's rounding, as above.
        self.assertLessEqual(op.GuaranteedScallop.Value, 0.05 * (1 + 1e-6))


class SaveReopenTest(unittest.TestCase):
    def test_saved_document_reopens_and_recomputes_the_same_path(self):
        setup = support.JobSetup("IsoSave")
        self.addCleanup(setup.close)
        op = make_op(setup, label="IsoSaved")
        name, original = op.Name, op.Path.toGCode()
        points = support.path_points(op.Path)
        path = os.path.join(support.temp_dir(self), "isocam.FCStd")
        setup.doc.saveAs(path)
        FreeCAD.closeDocument(setup.doc.Name)

        doc = FreeCAD.openDocument(path)
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        reopened = doc.getObject(name)
        self.assertIsInstance(reopened.Proxy, adaptive_isocurve.ObjectAdaptiveIsocurve)
        self.assertEqual(reopened.getPropertyStatus("SubIsocurves")[:2], ["ReadOnly", "Output"])
        # As stored in the file, then recomputed from scratch.
        self.assert_same_points(support.path_points(reopened.Path), points, STORED_TOL)
        reopened.touch()
        doc.recompute()
        self.assertNotIn("Invalid", reopened.State, reopened.getStatusString())
        self.assertEqual(reopened.Path.toGCode(), original)
        self.assert_same_points(support.path_points(reopened.Path), points, COORD_TOL)

    def assert_same_points(self, got_points, want_points, tol):
        self.assertEqual(len(got_points), len(want_points))
        for got, want in zip(got_points, want_points):
            self.assertEqual(got[0], want[0])
            for a, b in zip(got[1:], want[1:]):
                self.assertAlmostEqual(a, b, delta=tol)


if __name__ == "__main__":
    unittest.main()
