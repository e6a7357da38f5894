"""The independent 5-axis check's own geometry (tests/freecad/five_axis_check.py),
in plain Python: the intervals where random lines meet a flat end and a bull
nose against a brute-force membership test of points along each line (the
flat end: inside the cylinder; the bull nose: the cylinder of radius R from
rc up, or within rc of the core disc of radius R - rc at rc above the tip).
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


if __name__ == "__main__":
    unittest.main()
