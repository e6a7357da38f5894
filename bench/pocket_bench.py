"""Benchmark: IsoCAM's Spiral Pocket against FreeCAD's own Pocket Shape
(Offset and ZigZag patterns) and Adaptive, side by side in one run, on the
same floor faces with the same tool, stepover and depths.

Run (after ./run build):
    ISOCAM_ADDON_DIR=build/addon/IsoCAM freecadcmd bench/pocket_bench.py
Writes bench/pocket_results.json and bench/pocket_results.md (the table).

Measured from each op's Path, the same way for all: wall time of the op's
recompute, cutting length (G1/G2/G3, plunges included), rapid length (G0),
retracts (G0 moves straight up), and, on the floor (the last level), the
uncut area from isocam_core.pocket_coverage on a 0.1 mm raster: all of it,
and the part a tool of this radius could reach (the rest are the corners
it cannot reach), plus the tool centre's smallest distance to a wall or
island there. The targets (issue 4): no uncut reachable area, fewer
retracts than Pocket Shape Offset, wall time no worse than 2x Pocket Shape.
"""

import json
import math
import os
import sys
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
ADDON = os.environ.get("ISOCAM_ADDON_DIR") or os.path.join(ROOT, "build", "addon", "IsoCAM")
sys.path.insert(0, ADDON)

import FreeCAD  # noqa: E402
import Part  # noqa: E402
import numpy as np  # noqa: E402

from freecad_ext import compat, pocket_glue, scripting, spiral_pocket  # noqa: E402

TOOL_DIAMETER = 6.0
STEPOVER = 50  # percent of the tool diameter, all ops
STEP_DOWN = 5.0
CELL = 0.1
DATA = os.path.join(ROOT, "tests", "data")


# -- the cases: solids with a pocket whose floor is picked ------------------


def _block_with_pocket(outline_face, depth, margin):
    """A block around `outline_face` (at its z) with the face pocketed
    `depth` deep from the top: the face's holes become islands."""
    bb = outline_face.BoundBox
    z = bb.ZMin
    block = Part.makeBox(
        bb.XLength + 2 * margin,
        bb.YLength + 2 * margin,
        depth + 5,
        FreeCAD.Vector(bb.XMin - margin, bb.YMin - margin, z - 5),
    )
    return (
        block.cut(outline_face.extrude(FreeCAD.Vector(0, 0, depth))).removeSplitter(),
        z,
    )


def case_face_brep():
    shape = Part.Shape()
    shape.read(os.path.join(DATA, "face.brep"))
    return _block_with_pocket(shape.Faces[0], 10.0, 10.0)


def case_islands():
    body = Part.makeBox(120, 80, 20).cut(Part.makeBox(100, 60, 10, FreeCAD.Vector(10, 10, 10)))
    body = body.fuse(Part.makeCylinder(8, 10, FreeCAD.Vector(40, 35, 10)))
    body = body.fuse(Part.makeCylinder(5, 10, FreeCAD.Vector(92, 56, 10)))
    pts = [
        FreeCAD.Vector(
            75 + 9 * (1 + 0.3 * math.sin(3 * t)) * math.cos(t),
            30 + 9 * (1 + 0.3 * math.sin(3 * t)) * math.sin(t),
            10,
        )
        for t in (2 * math.pi * i / 24 for i in range(24))
    ]
    spline = Part.BSplineCurve()
    spline.interpolate(pts, PeriodicFlag=True)
    blob = Part.Face(Part.Wire([spline.toShape()])).extrude(FreeCAD.Vector(0, 0, 10))
    return body.fuse(blob).removeSplitter(), 10.0


def case_merge_lake():
    # Two islands 6 mm apart (their offsets merge) and one 3 mm from a wall
    # (its offsets meet the boundary's: lakes).
    body = Part.makeBox(140, 90, 20).cut(Part.makeBox(120, 70, 10, FreeCAD.Vector(10, 10, 10)))
    for x, y, r in ((50, 50, 12), (80, 50, 12), (115, 26, 13)):
        body = body.fuse(Part.makeCylinder(r, 10, FreeCAD.Vector(x, y, 10)))
    return body.removeSplitter(), 10.0


CASES = (
    ("face.brep pocket (240x60 slot, 2 holes)", case_face_brep),
    ("pocket with round and B-spline islands", case_islands),
    ("merging islands and a lake", case_merge_lake),
)


# -- measuring a Path --------------------------------------------------------


def measure(kind, xyz, centre):
    cut = rapid = 0.0
    retracts = 0
    for i in range(1, len(kind)):
        a, b = xyz[i - 1], xyz[i]
        k = int(kind[i])
        if k in (pocket_glue.MOVE_ARC_CW, pocket_glue.MOVE_ARC_CCW):
            c = centre[i]
            r = math.hypot(a[0] - c[0], a[1] - c[1])
            t0 = math.atan2(a[1] - c[1], a[0] - c[0])
            t1 = math.atan2(b[1] - c[1], b[0] - c[0])
            sweep = (
                (t1 - t0) % (2 * math.pi)
                if k == pocket_glue.MOVE_ARC_CCW
                else (t0 - t1) % (2 * math.pi)
            )
            if sweep == 0.0:
                sweep = 2 * math.pi
            cut += math.hypot(r * sweep, b[2] - a[2])
            continue
        d = float(np.linalg.norm(b - a))
        if k == pocket_glue.MOVE_RAPID:
            rapid += d
            if b[2] > a[2] and abs(b[0] - a[0]) + abs(b[1] - a[1]) < 1e-9:
                retracts += 1
        else:
            cut += d
    return cut, rapid, retracts


def run_op(doc, op, core, profiles, z_floor, radius):
    op.touch()
    started = time.monotonic()
    doc.recompute()
    seconds = time.monotonic() - started
    if "Invalid" in op.State or not op.Path.Commands:
        return {"error": op.getStatusString() or "no path", "seconds": seconds}
    kind, xyz, centre = pocket_glue.arrays_from_path(op.Path)
    cut, rapid, retracts = measure(kind, xyz, centre)
    cov = core.pocket_coverage(profiles, kind, xyz, centre, radius, z_floor, CELL, 1e-3)
    return {
        "seconds": round(seconds, 3),
        "cutting_length": round(cut, 1),
        "rapid_length": round(rapid, 1),
        "retracts": retracts,
        "moves": int(len(kind)),
        "uncut_area": round(cov["uncut_area"], 2),
        "uncut_reachable_area": round(cov["uncut_reachable_area"], 2),
        "unreachable_area": round(cov["unreachable_area"], 2),
        "min_clearance": round(cov["min_clearance"], 4),
        "floor_area": round(cov["region_area"], 1),
    }


def _freecad_op(*names):
    """FreeCAD's own operation module under its 1.0 or 0.20 name."""
    import importlib

    for name in names:
        try:
            return importlib.import_module(name)
        except ModuleNotFoundError:
            continue
    raise ImportError("none of %s found" % ", ".join(names))


def make_ops(doc, job, tc, base, floor_sub):
    ops = {}
    with compat.active_document(doc):
        iso = spiral_pocket.Create("IsoCAM_SpiralPocket", parentJob=job, toolController=tc)
        iso.StepOver = STEPOVER
        ops["IsoCAM Spiral Pocket"] = iso
        PathPocketShape = _freecad_op("Path.Op.PocketShape", "PathScripts.PathPocketShape")
        PathAdaptive = _freecad_op("Path.Op.Adaptive", "PathScripts.PathAdaptive")

        for pattern in ("Offset", "ZigZag"):
            op = PathPocketShape.Create("PocketShape" + pattern, parentJob=job)
            op.OffsetPattern = pattern
            op.StepOver = STEPOVER
            ops["FreeCAD Pocket Shape (%s)" % pattern] = op
        ada = PathAdaptive.Create("Adaptive", parentJob=job)
        ada.OperationType = "Clearing"
        ada.Side = "Inside"
        ada.StepOver = STEPOVER
        ops["FreeCAD Adaptive"] = ada
    for op in ops.values():
        op.ToolController = tc
        op.Base = [(base, [floor_sub])]
        op.StepDown = STEP_DOWN
    return ops


def run_case(title, build):
    core = compat.import_core()
    doc = FreeCAD.newDocument("PocketBench")
    try:
        shape, z_floor = build()
        model = doc.addObject("Part::Feature", "Model")
        model.Shape = shape
        job = scripting.make_job(model)
        tc = scripting.make_tool_controller(job, "endmill.fcstd", TOOL_DIAMETER)
        doc.recompute()
        clone = job.Model.Group[0]
        floor = max(
            (
                (i, f)
                for i, f in enumerate(clone.Shape.Faces)
                if abs(f.BoundBox.ZMin - z_floor) < 1e-6 and abs(f.BoundBox.ZMax - z_floor) < 1e-6
            ),
            key=lambda item: item[1].Area,
        )[0]
        profiles = core.face_region(clone.Shape.exportBrepToString(), floor, 1e-3)
        ops = make_ops(doc, job, tc, clone, "Face%d" % (floor + 1))
        doc.recompute()
        results = {}
        for name, op in ops.items():
            try:
                results[name] = run_op(doc, op, core, profiles, z_floor, TOOL_DIAMETER / 2)
            except Exception as exc:  # a FreeCAD op failing is a result too
                results[name] = {"error": "%s: %s" % (type(exc).__name__, exc)}
        return {
            "case": title,
            "floor_face": "Face%d" % (floor + 1),
            "z_floor": z_floor,
            "ops": results,
        }
    finally:
        FreeCAD.closeDocument(doc.Name)


def table(all_results):
    lines = [
        "| case | operation | time (s) | cutting (mm) | rapid (mm) | retracts | uncut (mm²) | of it reachable (mm²) | min clearance (mm) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for case in all_results["cases"]:
        for name, r in case["ops"].items():
            if "error" in r:
                lines.append(
                    "| %s | %s | failed: %s |||||||" % (case["case"], name, r["error"][:60])
                )
                continue
            lines.append(
                "| %s | %s | %.2f | %.0f | %.0f | %d | %.1f | %.1f | %.3f |"
                % (
                    case["case"],
                    name,
                    r["seconds"],
                    r["cutting_length"],
                    r["rapid_length"],
                    r["retracts"],
                    r["uncut_area"],
                    r["uncut_reachable_area"],
                    r["min_clearance"],
                )
            )
    return "\n".join(lines) + "\n"


def _main():
    status = 0
    try:
        results = {
            "tool_diameter": TOOL_DIAMETER,
            "stepover_percent": STEPOVER,
            "step_down": STEP_DOWN,
            "raster_cell": CELL,
            "freecad": ".".join(FreeCAD.Version()[:3]),
            "cases": [run_case(title, build) for title, build in CASES],
        }
        with open(os.path.join(HERE, "pocket_results.json"), "w") as out:
            json.dump(results, out, indent=2)
        md = table(results)
        with open(os.path.join(HERE, "pocket_results.md"), "w") as out:
            out.write(md)
        print(md)
    except BaseException:
        traceback.print_exc()
        status = 1
    sys.stdout.flush()
    os._exit(status)


_main()
