"""Measuring a posted Job with the independent simulator (tests/sim, the
isocam_gcode_sim program): shared by the test_*sim*.py files (a helper, not a
test file).

The simulator shares nothing with the core: it runs LinuxCNC's rs274 on the
posted G-code, sweeps the ball along its canonical moves and measures the
material left above, and the overcut below, points sampled on the model's
faces. The tests assert those measurements against what the op states,
through stated_bounds() alone.
"""

import json
import math
import os
import subprocess
import sys
import unittest

import FreeCAD

import fc_test_support as support

_TESTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(_TESTS, "sim"))
sys.path.append(_TESTS)
import expected_figures  # noqa: E402  (tests/: the figures of tests/data/expected.txt)
import sim_command  # noqa: E402  (tests/sim: the simulator's command line)
from freecad_ext import adaptive_isocurve, scripting


def stated_bounds(op):
    """(most material left, deepest overcut) in mm that `op` states its posted
    path keeps: the two numbers every simulation test asserts. They are the
    op's certificate (GuaranteedScallop, GuaranteedOvercut: chords, the
    clearance check's tolerance and the post's rounding included), which the
    op keeps within ScallopHeight and OvercutTolerance; the test checks that
    too, so a certificate that grew past the user's budget fails here."""
    left = op.GuaranteedScallop.Value
    overcut = op.GuaranteedOvercut.Value
    # 1e-12 mm: the op's properties hold the core's doubles; only the
    # Quantity round trip may add rounding.
    assert left <= op.ScallopHeight.Value + 1e-12, (left, op.ScallopHeight.Value)
    assert overcut <= op.OvercutTolerance.Value + 1e-12, (overcut, op.OvercutTolerance.Value)
    return left, overcut


def simulator_or_fail(testcase):
    build = os.environ.get("ISOCAM_BUILD_DIR") or os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "build"
    )
    path = os.path.join(build, "tests", "sim", "isocam_gcode_sim")
    if not os.access(path, os.X_OK):
        testcase.fail("simulator not built: %s (cmake --build the tree)" % path)
    return path


def picked_faces(op):
    """FreeCAD's face numbers (1-based) of the op's Base."""
    numbers = []
    for _obj, subs in op.Base:
        numbers += [int(s[4:]) for s in subs if s.startswith("Face")]
    return numbers


# Sample spacing on the design (mm). The residual has a kink at each cusp, so
# a measured cusp may be low by up to its slope times spacing / 2: 0.0015 mm
# for a 0.4 mm stepover of a 4 mm ball.
SPACING = 0.03


def measure(testcase, job, op, tool_diameter, spacing=SPACING, extra=(), edit=None):
    """Post `job`, simulate it on the Job's model and return the simulator's
    JSON summary (a dict); the G-code, B-rep and a residual map stay in a
    temporary folder for the length of the test. `edit`, if given, maps the
    posted G-code text to the text simulated (to check the check)."""
    rs274 = support.rs274_or_fail(testcase)
    sim = simulator_or_fail(testcase)
    # ISOCAM_SIM_KEEP=<folder>: keep the G-code, model and map there to look at.
    keep = os.environ.get("ISOCAM_SIM_KEEP")
    if keep:
        tmp = os.path.join(keep, testcase.id().split(".")[-1])
        os.makedirs(tmp, exist_ok=True)
    else:
        tmp = support.temp_dir(testcase)
    ngc = os.path.join(tmp, "job.ngc")
    gcode = scripting.post_job(job, ngc)
    if edit is not None:
        with open(ngc, "w") as out:
            out.write(edit(gcode))
    brep = os.path.join(tmp, "model.brep")
    job.Model.Group[0].Shape.exportBrep(brep)
    table = os.path.join(tmp, "tool.tbl")
    tc = op.ToolController
    sim_command.write_tool_table(table, tc.ToolNumber, tool_diameter)
    cmd = sim_command.command(
        sim,
        brep,
        picked_faces(op),
        tool_diameter / 2,
        ngc,
        rs274=rs274,
        tool_table=table,
        spacing=spacing,
        scallop=op.ScallopHeight.Value,
        extra=["--map", os.path.join(tmp, "residual.txt"), "--threads", "2"] + list(extra),
    )
    proc = subprocess.run(cmd, capture_output=True, text=True)
    testcase.assertEqual(proc.returncode, 0, proc.stderr)
    return json.loads(proc.stdout)


def shift_feeds_z(gcode, dz):
    """The G-code with every G1's Z moved by dz (mm): a program that cuts
    dz too deep (dz < 0) or leaves dz more (dz > 0) everywhere."""
    import re

    def shift(line):
        if not line.startswith("G1 "):
            return line
        return re.sub(r"Z(-?[0-9.]+)", lambda m: "Z%.3f" % (float(m.group(1)) + dz), line)

    return "\n".join(shift(line) for line in gcode.splitlines()) + "\n"


def describe(name, op, result):
    """One line for the test log: measured against stated."""
    left_bound, overcut_bound = stated_bounds(op)
    return (
        "%s: left %.5f (stated %.5f) at %s face %d, overcut %.5f (stated %.5f) at %s "
        "face %d, rapid overcut %.5f, reachable %.3f, within ScallopHeight %.4f, "
        "%d samples, %d moves"
        % (
            name,
            result["left"]["max"],
            left_bound,
            result["left"]["at"],
            result["left"]["face"],
            result["overcut"]["max"],
            overcut_bound,
            result["overcut"]["at"],
            result["overcut"]["face"],
            result["rapid_overcut"]["max"],
            result["reachable_fraction"],
            result["coverage"],
            result["picked_samples"],
            result["moves"]["total"],
        )
    )


def check_measured(testcase, name, op, result, model=None):
    """The measurement saw the part: enough samples and reachable area (the
    model's figure GcodeSim/<model or name> reachable_fraction,
    tests/data/expected.txt), and every reachable point near the path (none
    left uncovered)."""
    print(describe(name, op, result))
    # 10000: the measurement sampled the picked faces at all (each job of
    # the tests gives 3.5e5 to 2.4e6 samples at its spacing).
    testcase.assertGreater(result["picked_samples"], 10000, name)
    expected_figures.check(
        testcase, "GcodeSim/" + (model or name), "reachable_fraction", result["reachable_fraction"]
    )
    testcase.assertEqual(result["uncovered_samples"], 0, name)
    # The fed length the machine runs, as the sim measured it, is the op's:
    # its passes and links (CuttingLength) and its fed entries, plunged or
    # ramped along the pass (PlungeLength).
    fed = op.CuttingLength.Value + op.PlungeLength.Value
    # The sim reads the posted G-code (3 decimals: each move's length off by
    # up to ~1e-3 mm) and its arcs as chords: 1e-3 relative plus 1 mm.
    testcase.assertAlmostEqual(result["lengths"]["feed"], fed, delta=1e-3 * fed + 1)


def assert_left_within_stated(testcase, name, op, result):
    testcase.assertLessEqual(
        result["left"]["max"], stated_bounds(op)[0], describe(name, op, result)
    )


def assert_overcut_within_stated(testcase, name, op, result):
    """Overcut by any move within the bound, and no rapid cutting at all."""
    testcase.assertLessEqual(
        result["overcut"]["max"], stated_bounds(op)[1], describe(name, op, result)
    )
    testcase.assertEqual(result["rapid_overcut"]["max"], 0.0, describe(name, op, result))


def assert_within_stated(testcase, name, op, result):
    """The op's promise, measured: material left and overcut within
    stated_bounds(op), no rapid cutting, on a measurement that saw the part."""
    check_measured(testcase, name, op, result)
    assert_left_within_stated(testcase, name, op, result)
    assert_overcut_within_stated(testcase, name, op, result)


def mat_piece():
    """MAT's B-spline cut to the parameter square [0.35, 0.6]^2 of its range
    (about 20 x 20 mm of ridges and valleys)."""
    surf = support.load_shape("MAT.brep").Faces[0].Surface.copy()
    u0, u1, v0, v1 = surf.bounds()
    surf.segment(
        u0 + 0.35 * (u1 - u0),
        u0 + 0.6 * (u1 - u0),
        v0 + 0.35 * (v1 - v0),
        v0 + 0.6 * (v1 - v0),
    )
    return surf.toShape()


class MeasuredJob(unittest.TestCase):
    """One model, one Adaptive Isocurve job of PATTERN on all its faces,
    posted and simulated once for the class; each test checks one promise.
    A test file subclasses it per model; unittest collects only the
    subclasses (this base is reached as sim_support.MeasuredJob, never
    imported into a test module's names)."""

    NAME = SHAPE = None
    PATTERN = "Adaptive"
    BALL_DIAMETER = SCALLOP = SPACING = None
    # The least reachable fraction of the picked area of each model:
    # GcodeSim/<MODEL> in tests/data/expected.txt (MODEL: NAME unless set;
    # the reach depends on the model, not on the pattern).
    MODEL = None

    @classmethod
    def setUpClass(cls):
        cls.doc = FreeCAD.newDocument(cls.NAME)
        model = cls.doc.addObject("Part::Feature", "Model")
        model.Shape = cls.SHAPE()
        cls.job = scripting.make_job(model)
        tc = scripting.make_ball_end_tool_controller(cls.job, cls.BALL_DIAMETER)
        cls.op = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME, parentJob=cls.job, toolController=tc
        )
        clone = cls.job.Model.Group[0]
        cls.op.Base = [(clone, ["Face%d" % (i + 1) for i in range(len(clone.Shape.Faces))])]
        cls.op.ScallopHeight = cls.SCALLOP
        cls.op.Pattern = cls.PATTERN
        cls.doc.recompute()
        cls.result = None

    @classmethod
    def tearDownClass(cls):
        FreeCAD.closeDocument(cls.doc.Name)

    def measured(self):
        if self.__class__.result is None:
            self.assertNotIn("Invalid", self.op.State, self.op.getStatusString())
            self.__class__.result = measure(
                self, self.job, self.op, self.BALL_DIAMETER, spacing=self.SPACING
            )
            print(describe(self.NAME, self.op, self.__class__.result))
        return self.__class__.result

    def test_measured(self):
        check_measured(self, self.NAME, self.op, self.measured(), model=self.MODEL)

    def test_left_within_stated(self):
        assert_left_within_stated(self, self.NAME, self.op, self.measured())

    def test_overcut_within_stated(self):
        assert_overcut_within_stated(self, self.NAME, self.op, self.measured())
