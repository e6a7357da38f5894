"""Writes tests/data/previous_ops.FCStd and previous_ops.json: a document with
the three IsoCAM operations, computed and saved by the IsoCAM and FreeCAD
versions that run this script, and what it holds (every property of each op:
type, group and value). test_previous_document.py opens it with the current
code: documents saved by an earlier IsoCAM must keep opening.

Not a test. Run with the addon built from the version to record:
    ISOCAM_ADDON_DIR=build/addon/IsoCAM ISOCAM_OUT_DIR=tests/data \\
        freecadcmd tests/freecad/make_previous_document.py
The committed files were written by IsoCAM d6ed807 (before the op base of
issue 14) on FreeCAD 0.20.2.
"""

import json
import os
import subprocess
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))
sys.path.insert(0, HERE)

NAME = "previous_ops"


def _value(obj, prop):
    value = getattr(obj, prop)
    if hasattr(value, "Value"):  # a Quantity
        return value.Value
    if isinstance(value, (bool, int, float, str)):
        return value
    return None  # links, paths, placements: not compared


def _record(obj):
    return {
        prop: [obj.getTypeIdOfProperty(prop), obj.getGroupOfProperty(prop), _value(obj, prop)]
        for prop in obj.PropertiesList
    }


def _isocam_commit():
    try:
        return subprocess.run(
            ["git", "-C", HERE, "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main():
    import FreeCAD

    import test_spiral_pocket as pockets
    from freecad_ext import adaptive_isocurve, scripting

    out_dir = os.environ["ISOCAM_OUT_DIR"]
    setup = pockets.PocketJob(NAME)
    setup.pocket.StepOver = 40
    setup.pocket.Tolerance = 0.02
    setup.rough.StockToLeave = 0.3
    ball = scripting.make_ball_end_tool_controller(setup.job, 6.0)
    top = next(i for i, f in enumerate(setup.clone.Shape.Faces) if abs(f.BoundBox.ZMin - 20) < 1e-6)
    iso = adaptive_isocurve.Create(
        adaptive_isocurve.OP_NAME, parentJob=setup.job, toolController=ball
    )
    iso.Base = [(setup.clone, ["Face%d" % (top + 1)])]
    iso.ScallopHeight = 0.1
    iso.Direction = "U"
    iso.ScallopBound = "Flat"
    setup.doc.recompute()
    ops = (setup.pocket, setup.rough, iso)
    for op in ops:
        if "Invalid" in op.State:
            raise RuntimeError("%s: %s" % (op.Label, op.getStatusString()))
    setup.doc.saveAs(os.path.join(out_dir, NAME + ".FCStd"))
    record = {
        "freecad": ".".join(FreeCAD.Version()[:3]),
        "isocam": _isocam_commit(),
        "ops": {
            op.Name: {"proxy": type(op.Proxy).__name__, "properties": _record(op)} for op in ops
        },
    }
    with open(os.path.join(out_dir, NAME + ".json"), "w") as out:
        json.dump(record, out, indent=1, sort_keys=True)
        out.write("\n")


try:
    main()
except Exception:
    traceback.print_exc()
    os._exit(1)
os._exit(0)
