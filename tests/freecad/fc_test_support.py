"""Shared set-up for the headless FreeCAD tests (a helper, not a test file)."""

import os
import shutil
import tempfile

import FreeCAD
import Part

from freecad_ext import scripting

DATA_DIR = os.environ.get("ISOCAM_TEST_DATA") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "data"
)


def load_shape(filename):
    shape = Part.Shape()
    shape.read(os.path.join(DATA_DIR, filename))
    return shape


class JobSetup:
    """A new document with `filename`'s model (or `shape`), a Job on it and a 6 mm
    ball-end tool controller (the Job also brings FreeCAD's default flat
    end mill controller, "TC: Default Tool")."""

    def __init__(self, name, filename="MAT.brep", ball_diameter=6.0, shape=None):
        self.doc = FreeCAD.newDocument(name)
        self.doc_name = self.doc.Name
        self.model = self.doc.addObject("Part::Feature", "Model")
        self.model.Shape = shape if shape is not None else load_shape(filename)
        self.job = scripting.make_job(self.model)
        self.ball_diameter = ball_diameter
        self.ball_tc = scripting.make_ball_end_tool_controller(self.job, ball_diameter)
        self.doc.recompute()

    @property
    def clone(self):
        """The Job's copy of the model: faces are picked from it."""
        return self.job.Model.Group[0]

    def close(self):
        if self.doc_name in FreeCAD.listDocuments():
            FreeCAD.closeDocument(self.doc_name)


def path_points(path):
    """[(G-code name, x, y, z)] of a Path's moves, with modal coordinates
    filled in (a G0 Z... keeps the previous x and y)."""
    x = y = z = 0.0
    points = []
    for c in path.Commands:
        if c.Name not in ("G0", "G1"):
            continue
        p = c.Parameters
        x, y, z = p.get("X", x), p.get("Y", y), p.get("Z", z)
        points.append((c.Name, x, y, z))
    return points


# Path coordinates are the core's doubles (the glue converts exactly), and
# OpenCASCADE's distToShape on a B-spline face converges to about 1e-7 mm:
# 1e-6 mm is above both and far below any tolerance the op states.
DISTANCE_TOL = 1e-6  # mm


def assert_ball_finishing_invariants(testcase, op, face, ball_radius, samples=60):
    """What a ball-end finishing op on `face` must give, read from its Path
    alone (nothing shared with the core):

    - the first move is a rapid straight up to ClearanceHeight, the second a
      rapid across at that height, the last a rapid back up to it;
    - there are feed moves (G1), and each one's tip is within the face's box
      grown by the ball radius in x and y, and never above the face's top;
    - at `samples` feed moves spread along the path, the ball centre (tip + r)
      is at least r - OvercutTolerance from the face: the path cuts the
      design by no more than the overcut the op states.
    Returns the feed moves [(name, x, y, z)]."""
    points = path_points(op.Path)
    clear = op.ClearanceHeight.Value
    testcase.assertGreaterEqual(len(points), 3)
    first, second, last = points[0], points[1], points[-1]
    testcase.assertEqual(first[0], "G0")
    testcase.assertAlmostEqual(first[3], clear, delta=DISTANCE_TOL)
    testcase.assertEqual(second[0], "G0")
    testcase.assertAlmostEqual(second[3], clear, delta=DISTANCE_TOL)
    testcase.assertEqual(last[0], "G0")
    testcase.assertAlmostEqual(last[3], clear, delta=DISTANCE_TOL)
    feeds = [p for p in points if p[0] == "G1"]
    testcase.assertTrue(feeds, "no feed move")
    bb, r, tol = face.BoundBox, ball_radius, DISTANCE_TOL
    for _name, x, y, z in feeds:
        testcase.assertTrue(bb.XMin - r - tol <= x <= bb.XMax + r + tol, (x, y, z))
        testcase.assertTrue(bb.YMin - r - tol <= y <= bb.YMax + r + tol, (x, y, z))
        testcase.assertLessEqual(z, bb.ZMax + tol, (x, y, z))
    keep = r - op.OvercutTolerance.Value - tol
    step = max(1, len(feeds) // samples)
    for _name, x, y, z in feeds[::step]:
        centre = Part.Vertex(FreeCAD.Vector(x, y, z + r))
        d = centre.distToShape(face)[0]
        testcase.assertGreaterEqual(d, keep, (x, y, z))
    return feeds


def assert_motions_end_with(testcase, run, path):
    """The rs274 run's motions end with exactly `path`'s moves (to the
    posted G-code's 3 decimals)."""
    expected = path_points(path)
    motions = run.motions()[-len(expected) :]
    testcase.assertEqual(len(motions), len(expected))
    for got, want in zip(motions, expected):
        testcase.assertEqual(got[0], want[0])
        for a, b in zip(got[1:], want[1:]):
            testcase.assertAlmostEqual(a, b, delta=0.0005 + 1e-9)


def rs274_or_fail(testcase):
    """Path of LinuxCNC's rs274 (package linuxcnc-uspace) or fail the test."""
    rs274 = shutil.which("rs274")
    if rs274 is None:
        testcase.fail("rs274 not found: install linuxcnc-uspace (./run does)")
    return rs274


def temp_dir(testcase):
    """A temporary folder removed after the test."""
    path = tempfile.mkdtemp(prefix="isocam-")
    testcase.addCleanup(shutil.rmtree, path, True)
    return path
