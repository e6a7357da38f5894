"""Runs one fuzz case (a JSON file, argv[1]) against the isocam_core module and
prints one JSON line: {"outcome": "ok" | "error", "type": ..., "message": ...,
"finite": bool}. The parent (fuzz.py) sets the limits and classifies.

A case: {"call": name, "args": {...}}; B-rep arguments are file names
(written by the parent), profiles are lists of rows (x, y, cx, cy, dir).
"""

import json
import math
import os
import sys

sys.path.insert(0, os.environ.get("ISOCAM_ADDON_DIR", ""))

import numpy as np  # noqa: E402

import isocam_core as core  # noqa: E402


def read(path):
    with open(path) as f:
        return f.read()


def set_params(params, values):
    for key, value in values.items():
        if key in ("direction",):
            value = getattr(core.CutDirection, value)
        setattr(params, key, value)
    return params


def finite_result(res):
    """No NaN or inf in a path's points or a metric (arc centres are NaN on
    purpose for moves that are not arcs)."""
    xyz = np.asarray(res.xyz)
    if xyz.size and not np.isfinite(xyz).all():
        return False
    metrics = res.metrics
    for name in dir(metrics):
        if name.startswith("_"):
            continue
        value = getattr(metrics, name)
        if isinstance(value, float) and not math.isfinite(value):
            return False
    return True


def run(case):
    a = case["args"]
    call = case["call"]
    if call == "adaptive_isocurve":
        p = core.IsoParams()
        p.threads = 1
        for key, value in a.get("params", {}).items():
            if key == "direction":
                value = getattr(core.IsoDirection, value)
            elif key == "pattern":
                value = getattr(core.IsoPattern, value)
            setattr(p, key, value)
        return core.adaptive_isocurve(read(a["brep"]), a["faces"], p)
    if call == "pocket_faces":
        p = set_params(core.PocketParams(), a.get("params", {}))
        return core.pocket_faces(
            read(a["brep"]), a["faces"], p, a["depths"], a.get("ball_end", False)
        )
    if call == "zlevel_roughing":
        p = set_params(core.PocketParams(), a.get("params", {}))
        return core.zlevel_roughing(
            read(a["model"]), read(a["stock"]), p, a["depths"], a.get("stock_to_leave", 0.5)
        )
    if call == "spiral_pocket":
        p = set_params(core.PocketParams(), a.get("params", {}))
        boundary = np.array(a["boundary"], dtype=float).reshape(-1, 5)
        islands = [np.array(i, dtype=float).reshape(-1, 5) for i in a.get("islands", [])]
        return core.spiral_pocket(boundary, islands, p, a["depths"])
    if call == "face_region":
        return core.face_region(read(a["brep"]), a["face"], a["tolerance"])
    if call == "stepover_for_scallop":
        return core.stepover_for_scallop(a["r"], a["h"])
    if call == "scallop_for_stepover":
        return core.scallop_for_stepover(a["r"], a["delta"])
    raise SystemExit("unknown call " + call)


def main():
    with open(sys.argv[1]) as f:
        case = json.load(f)
    try:
        res = run(case)
    except MemoryError as exc:
        out = {"outcome": "error", "type": "MemoryError", "message": str(exc)}
    except Exception as exc:  # the parent judges the type and message
        # The type and the types it derives from: the module's
        # InvalidArgumentError is a ValueError.
        kinds = [c.__name__ for c in type(exc).__mro__]
        out = {"outcome": "error", "type": kinds[0], "kinds": kinds, "message": str(exc)}
    else:
        if hasattr(res, "xyz"):
            finite = finite_result(res)
        elif isinstance(res, float):
            finite = math.isfinite(res)
        else:
            finite = True
        out = {"outcome": "ok", "finite": finite}
    sys.stdout.write("FUZZ-RESULT " + json.dumps(out) + "\n")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
