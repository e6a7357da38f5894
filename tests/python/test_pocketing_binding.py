"""The pocketing bindings seen from Python: flat arrays with arc centres,
metrics that agree with the arrays, profiles in and out, the error model,
cancel and progress with the GIL released."""

import math
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))
import numpy as np  # noqa: E402

import isocam_core as core  # noqa: E402

DATA = os.environ.get("ISOCAM_TEST_DATA", os.path.join(os.path.dirname(__file__), "..", "data"))

# A 100 x 60 rectangle and a round island of radius 10 (two half arcs, cw).
BOUNDARY = np.array(
    [[0, 0, 0, 0, 0], [100, 0, 0, 0, 0], [100, 60, 0, 0, 0], [0, 60, 0, 0, 0]], float
)
ISLAND = np.array([[60, 30, 50, 30, -1], [40, 30, 50, 30, -1]], float)


def params(**kw):
    p = core.PocketParams()
    p.tool_radius = 3.0
    p.stepover = 2.4
    p.safe_z = 10.0
    for k, v in kw.items():
        setattr(p, k, v)
    return p


def read(name):
    with open(os.path.join(DATA, name)) as f:
        return f.read()


class PocketBinding(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.res = core.spiral_pocket(BOUNDARY, [ISLAND], params(), [2.0, 0.0])

    def test_arrays(self):
        r = self.res
        n = len(r.kind)
        self.assertEqual(r.kind.dtype, np.uint8)
        self.assertEqual(r.xyz.shape, (n, 3))
        self.assertEqual(r.centre.shape, (n, 2))
        arcs = np.isin(r.kind, (core.ARC_CW, core.ARC_CCW))
        self.assertTrue(np.all(np.isfinite(r.centre[arcs])))
        self.assertTrue(np.all(np.isnan(r.centre[~arcs])))

    def test_metrics_agree_with_the_arrays(self):
        r, m = self.res, self.res.metrics
        cutting = np.isin(r.kind[1:], (core.FEED, core.ARC_CW, core.ARC_CCW))
        self.assertEqual(m.cl_points, int(cutting.sum()))
        self.assertEqual(m.arcs, int(np.isin(r.kind, (core.ARC_CW, core.ARC_CCW)).sum()))
        self.assertEqual(m.levels, 2)
        self.assertGreater(m.arcs, 0)
        up = (r.kind[1:] == core.RAPID) & (r.xyz[1:, 2] > r.xyz[:-1, 2])
        self.assertEqual(m.retracts, int(up.sum()))

    def test_arcs_are_exact(self):
        r = self.res
        for i in np.nonzero(np.isin(r.kind, (core.ARC_CW, core.ARC_CCW)))[0]:
            c = r.centre[i]
            ra = math.dist(r.xyz[i - 1][:2], c)
            rb = math.dist(r.xyz[i][:2], c)
            # The ends are vertices shared with the neighbouring segments,
            # which the contract lets lie within the snapping distance of the
            # exact circle (1e-7 of the region's size, profile2d.h: 1.2e-5 mm
            # here); they come out far closer, and 1e-6 mm, 1000 times under
            # the posted resolution, is kept to catch a change in how the
            # ends are placed.
            self.assertAlmostEqual(ra, rb, delta=1e-6)
            self.assertEqual(r.xyz[i - 1][2], r.xyz[i][2])

    def test_coverage_of_the_result(self):
        r = self.res
        rep = core.pocket_coverage([BOUNDARY, ISLAND], r.kind, r.xyz, r.centre, 3.0, 0.0, 0.2)
        self.assertEqual(rep["uncut_reachable_area"], 0.0)
        self.assertEqual(rep["outside_samples"], 0)
        # The tool runs along the offset r from the walls: the smallest
        # clearance is r, to the rounding of the coverage check's distances.
        self.assertAlmostEqual(rep["min_clearance"], 3.0, delta=1e-6)

    def test_face_region_and_pocket_faces(self):
        brep = read("face.brep")
        profiles = core.face_region(brep, 0, 0.01)
        self.assertEqual(len(profiles), 3)
        self.assertEqual(profiles[0].shape[1], 5)
        z = 0.0
        res = core.pocket_faces(brep, [0], params(safe_z=z + 50), [z], False)
        self.assertEqual(res.warnings, [])
        self.assertGreater(res.metrics.loops, 0)

    def test_bad_arguments_name_themselves(self):
        cases = (
            (
                lambda: core.spiral_pocket(BOUNDARY, [], params(stepover=-1), [0.0]),
                "stepover",
            ),
            (
                lambda: core.spiral_pocket(BOUNDARY, [], params(stepover=7), [0.0]),
                "stepover",
            ),
            (lambda: core.spiral_pocket(BOUNDARY, [], params(), []), "depths"),
            (lambda: core.spiral_pocket(BOUNDARY, [], params(), [0.0, 1.0]), "depths"),
            (
                lambda: core.spiral_pocket(BOUNDARY[:, :3], [], params(), [0.0]),
                "boundary",
            ),
            (
                lambda: core.spiral_pocket(BOUNDARY, [], params(tolerance=0), [0.0]),
                "tolerance",
            ),
            (
                lambda: core.pocket_faces(read("face.brep"), [3], params(), [0.0]),
                "faces",
            ),
            (lambda: core.pocket_faces("", [0], params(), [0.0]), "brep"),
        )
        for call, needle in cases:
            with self.assertRaises(ValueError) as ctx:
                call()
            self.assertIn(needle, str(ctx.exception))
            # The core's errors name the argument for the caller's mapping.
            if isinstance(ctx.exception, core.InvalidArgumentError):
                self.assertIn(needle, ctx.exception.arguments)
        # "tolerance" as a whole word only: not in "floor_tolerance".
        with self.assertRaises(core.InvalidArgumentError) as ctx:
            core.spiral_pocket(BOUNDARY, [], params(tolerance=0), [0.0])
        self.assertEqual(ctx.exception.arguments[0], "tolerance")

    def test_cancel_and_progress_with_the_gil_released(self):
        progress = core.Progress()
        progress.cancel()
        with self.assertRaises(core.CancelledError):
            core.spiral_pocket(BOUNDARY, [ISLAND], params(stepover=0.05), [0.0], progress)
        # A long job in a thread: the main thread keeps running meanwhile.
        progress = core.Progress()
        outcome = {}
        scale = np.array([3, 3, 3, 3, 1], float)  # coordinates, not the dir column

        def work():
            try:
                core.spiral_pocket(
                    BOUNDARY * scale,
                    [ISLAND * scale],
                    params(stepover=0.05),
                    [0.0],
                    progress,
                )
            except core.CancelledError:
                outcome["cancelled"] = True

        worker = threading.Thread(target=work)
        worker.start()
        seen = 0.0
        deadline = time.monotonic() + 30
        while seen <= 0.0 and time.monotonic() < deadline:
            seen = progress.fraction
            time.sleep(0.001)
        # Progress seen here while the core still runs: the GIL was released.
        alive = worker.is_alive()
        progress.cancel()
        worker.join()
        self.assertGreater(seen, 0.0)
        self.assertTrue(alive)
        self.assertTrue(outcome.get("cancelled"))


if __name__ == "__main__":
    unittest.main()
