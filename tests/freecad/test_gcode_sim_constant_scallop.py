"""ConstantScallop's promise measured from outside (issues 10 and 12,
habit 15): the same bundled models as test_gcode_sim_bundled.py (a 20 x 20 mm
piece of the MAT terrain, Ball, shell1), each finished by an Adaptive
Isocurve job with Pattern = "ConstantScallop", posted with FreeCAD's linuxcnc
post, read back by rs274 and simulated by tests/sim's isocam_gcode_sim. The
measured material left and overcut must stay within what the op states
(GuaranteedScallop, GuaranteedOvercut; sim_support.stated_bounds), with no
rapid cutting and no reachable point left uncovered.

The pattern's own certificate (the pair cusps and the face's samples,
finishing/scallop_coverage) is computed by the core; this test shares
nothing with it: it sweeps a ball along the posted program.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_gcode_sim_constant_scallop.py
"""

import unittest

import fc_test_support as support
import sim_support


class MatPieceConstantScallopTest(sim_support.MeasuredJob):
    NAME, MODEL, SHAPE = "MATPieceCS", "MATPiece", staticmethod(sim_support.mat_piece)
    PATTERN = "ConstantScallop"
    BALL_DIAMETER, SCALLOP, SPACING = 6.0, 0.01, 0.03


class BallConstantScallopTest(sim_support.MeasuredJob):
    NAME, MODEL = "BallCS", "Ball"
    SHAPE = staticmethod(lambda: support.load_shape("Ball.brep"))
    PATTERN = "ConstantScallop"
    BALL_DIAMETER, SCALLOP, SPACING = 2.0, 0.05, 0.05


class Shell1ConstantScallopTest(sim_support.MeasuredJob):
    NAME, MODEL = "Shell1CS", "Shell1"
    SHAPE = staticmethod(lambda: support.load_shape("shell1.brep"))
    PATTERN = "ConstantScallop"
    BALL_DIAMETER, SCALLOP, SPACING = 4.0, 0.01, 0.04


if __name__ == "__main__":
    unittest.main()
