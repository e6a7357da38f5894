"""The independent 5-axis check's own geometry (tests/freecad/five_axis_check.py),
in plain Python: the intervals where random lines meet a flat end and a bull
nose against a brute-force membership test of points along each line (the
flat end: inside the cylinder; the bull nose: the cylinder of radius R from
rc up, or within rc of the core disc of radius R - rc at rc above the tip);
and that a rapid through the face reads as an overcut.
"""

import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "freecad"))
import five_axis_check as check  # noqa: E402

R, LENGTH = 3.0, 30.0


def inside(p, tip, axis, corner):
    w = p - tip
    h = w @ axis
    rho = np.linalg.norm(w - h * axis)
    if corner <= h <= LENGTH and rho <= R:
        return True
    if corner == 0:
        return False
    hh, core = h - corner, R - corner
    d = abs(hh) if rho <= core else np.hypot(rho - core, hh)
    return d <= corner


class LinesThroughTheTool(unittest.TestCase):
    def test_intervals_match_brute_force(self):
        rng = np.random.default_rng(7)
        ts = np.linspace(-15.0, 15.0, 3001)  # 0.01 mm apart
        for corner in (0.0, 1.0, 2.5):
            wrong = 0
            met = 0
            for _ in range(100):
                axis = rng.normal(size=3)
                axis /= np.linalg.norm(axis)
                tip = rng.normal(size=3) * 2
                s = rng.normal(size=3) * 3
                n = rng.normal(size=3)
                n /= np.linalg.norm(n)
                t0, t1 = check.tool_intervals(s, n, tip[None, :], axis[None, :], R, LENGTH, corner)
                truth = np.array([inside(s + t * n, tip, axis, corner) for t in ts])
                got = np.zeros_like(truth)
                for a, b in zip(t0, t1):
                    if a <= b:
                        got |= (ts >= a) & (ts <= b)
                met += bool(truth.any())
                # At most the samples at the two ends may differ (rounding).
                wrong += int((got != truth).sum() > 2)
            self.assertGreater(met, 25, corner)  # the lines do meet the tool
            self.assertEqual(wrong, 0, corner)


class RapidsSweptApart(unittest.TestCase):
    def test_a_rapid_through_the_face_is_an_overcut(self):
        """The rapids are swept apart from the feeds (kind_swept="G0"): a G0
        across a plane with the tool's bottom 0.2 mm below it reads an
        overcut of 0.2 mm, one 0.2 mm above it none; the feed sweep does not
        see the rapid."""
        # The plane z = 0 sampled every 0.2 mm over 10 x 10 mm, normal up.
        g = np.arange(-5.0, 5.0001, 0.2)
        pts = np.array([(x, y, 0.0) for x in g for y in g])
        nrm = np.tile([0.0, 0.0, 1.0], (len(pts), 1))
        for lift, overcut in ((-0.2, 0.2), (0.2, 0.0)):
            moves = [("G0", -4.0, -4.0, lift, 0.0, 0.0), ("G0", 4.0, 3.0, lift, 0.0, 90.0)]
            tips, axes = check.tool_instances(moves, step=0.1, angle_step=1.0, kind_swept="G0")
            _, over = check.measure(pts, nrm, tips, axes, R, LENGTH, reach=np.hypot(R, LENGTH))
            self.assertAlmostEqual(over.max(), overcut, places=9, msg="lift %g" % lift)
            feeds, _ = check.tool_instances(moves, step=0.1, angle_step=1.0)
            self.assertEqual(len(feeds), 0)


if __name__ == "__main__":
    unittest.main()
