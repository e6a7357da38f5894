"""One FreeCAD fuzz case, run by freecadcmd (see fuzz_freecad.py). Prints
FUZZ-RESULT {"class": ..., "why": ...}."""

import json
import os
import sys
import traceback

import FreeCAD
import Part

sys.path.insert(0, os.environ["ISOCAM_ADDON_DIR"])

from freecad_ext import adaptive_isocurve, scripting, spiral_pocket, zlevel_roughing  # noqa: E402

OPS = {
    "AdaptiveIsocurve": adaptive_isocurve,
    "SpiralPocket": spiral_pocket,
    "ZLevelRoughing": zlevel_roughing,
}


def model_shape():
    """A 100 x 80 x 10 plate with a dome of radius 20 on it."""
    plate = Part.makeBox(100, 80, 10)
    dome = Part.makeSphere(20, FreeCAD.Vector(50, 40, 10))
    return plate.fuse(dome).removeSplitter()


def bad_shape(kind):
    if kind == "vertex":
        return Part.Vertex(FreeCAD.Vector(0, 0, 0))
    if kind == "edge":
        return Part.makeLine(FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(10, 0, 0))
    if kind == "wire":
        return Part.makePolygon(
            [FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(10, 0, 0), FreeCAD.Vector(10, 10, 0)]
        )
    if kind == "empty":
        return Part.Compound([])
    return Part.makePlane(100, 80)  # a face, not a solid


def invalid(obj):
    return "Invalid" in obj.State


def result(cls, why):
    sys.stdout.write("FUZZ-RESULT " + json.dumps({"class": cls, "why": why}) + "\n")
    sys.stdout.flush()


def main():
    with open(os.environ["ISOCAM_FUZZ_CASE"]) as f:
        case = json.load(f)
    doc = FreeCAD.newDocument("Fuzz")
    model = doc.addObject("Part::Feature", "Model")
    model.Shape = model_shape()
    job = scripting.make_job(model)
    ball = scripting.make_ball_end_tool_controller(job, 6.0)
    mill = scripting.make_tool_controller(job, "endmill.fcstd", 6.0)
    doc.recompute()
    clone = job.Model.Group[0]
    faces = clone.Shape.Faces
    dome = next(i for i, f in enumerate(faces) if f.Surface.__class__.__name__ == "Sphere")
    top = next(
        i
        for i, f in enumerate(faces)
        if abs(f.BoundBox.ZMin - 10) < 1e-6 and abs(f.BoundBox.ZMax - 10) < 1e-6
    )
    ops = {}
    ops["AdaptiveIsocurve"] = adaptive_isocurve.Create(parentJob=job, toolController=ball)
    ops["AdaptiveIsocurve"].Base = [(clone, ["Face%d" % (dome + 1)])]
    ops["AdaptiveIsocurve"].ScallopHeight = 0.05
    ops["SpiralPocket"] = spiral_pocket.Create(parentJob=job, toolController=mill)
    ops["SpiralPocket"].Base = [(clone, ["Face%d" % (top + 1)])]
    ops["SpiralPocket"].StepDown = 10
    ops["ZLevelRoughing"] = zlevel_roughing.Create(parentJob=job, toolController=mill)
    ops["ZLevelRoughing"].StepDown = 10
    doc.recompute()
    for name, op in ops.items():
        if invalid(op):
            return result("WRONG", "the good %s is in error: %s" % (name, op.getStatusString()))
    good_paths = {name: op.Path.toGCode() for name, op in ops.items()}

    if "shape" in case:
        model.Shape = bad_shape(case["shape"])
        clone.Shape = model.Shape
        for op in ops.values():
            op.touch()
        doc.recompute()
        # Roughing needs a solid; the others fail or (on a face) finish it.
        bad = ["ZLevelRoughing"]
        if not invalid(ops["ZLevelRoughing"]):
            return result("WRONG", "ZLevelRoughing accepted a model that is a %s" % case["shape"])
    else:
        op = ops[case["op"]]
        try:
            if case["property"] == "Base":
                op.Base = [(clone, [case["value"]])]
            else:
                # Heights and depths follow the SetupSheet's expressions
                # until the user types a value, as here.
                op.setExpression(case["property"], None)
                setattr(op, case["property"], case["value"])
        except Exception as exc:  # FreeCAD's own property refuses the value
            return result("OK", "FreeCAD refused the value: %s" % exc)
        doc.recompute()
        bad = [case["op"]]
        if not invalid(op):
            return result(
                "WRONG",
                "%s.%s = %r accepted (%d commands)"
                % (case["op"], case["property"], case["value"], len(op.Path.Commands)),
            )
        message = op.getStatusString()
        missing = [w for w in case["expect"] if w not in message]
        if missing:
            return result("UNCLEAR", "message does not name %s: %s" % (missing, message))
        for name, other in ops.items():
            if name in bad:
                continue
            if invalid(other) or other.Path.toGCode() != good_paths[name]:
                return result("WRONG", "bystander %s changed" % name)
    for name in bad:
        if not invalid(ops[name]) and len(ops[name].Path.Commands) > 0:
            return result("WRONG", "%s computed a path on a bad model" % name)
    # The document saves and reopens.
    path = os.path.join(os.environ["ISOCAM_FUZZ_DIR"], "fuzz.FCStd")
    op_names = {name: op.Name for name, op in ops.items()}
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(path)
    doc.recompute()
    names = [o.Name for o in doc.Objects]
    for name in ops:
        again = doc.getObject(op_names[name])
        if again is None:
            return result("WRONG", "%s is missing after reopening" % name)
        if "shape" not in case and name not in bad and invalid(again):
            return result(
                "WRONG", "%s is in error after reopening: %s" % (name, again.getStatusString())
            )
    FreeCAD.closeDocument(doc.Name)
    result("OK", "error named as expected; saved and reopened (%d objects)" % len(names))


try:
    main()
except Exception:
    result("UNCLEAR", "the case script failed: " + traceback.format_exc()[-400:])
