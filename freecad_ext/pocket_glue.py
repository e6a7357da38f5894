"""Shared glue of the pocketing operations (Spiral Pocket, Z-level Roughing).

Maps FreeCAD's depth properties to the core's z levels and runs a core call
in a worker thread (the core releases the GIL); op_base turns the core's flat
move arrays -- with G2/G3 arcs -- into ``Path.Command``s. No geometry here.
"""

import threading

import FreeCAD

from freecad_ext import compat, op_base
from freecad_ext.compat import PathOp
from freecad_ext.op_base import (
    MOVE_ARC_CCW,
    MOVE_ARC_CW,
    MOVE_FEED,
    MOVE_PLUNGE,
    MOVE_RAPID,
    IsoCAMError,
    IsoCAMOp,
)

DIRECTIONS = ("Climb", "Conventional")


def depth_levels(obj):
    """The z levels of the op, top to bottom, from FreeCAD's StartDepth,
    FinalDepth and StepDown (PathUtils.depth_params, as FreeCAD's own ops)."""
    step = obj.StepDown.Value
    if step <= 0:
        raise IsoCAMError("property StepDown must be > 0 (it is %g mm)" % step)
    start, final = obj.StartDepth.Value, obj.FinalDepth.Value
    if final > start:
        raise IsoCAMError(
            "property FinalDepth (%g mm) is above StartDepth (%g mm)" % (final, start)
        )
    params = compat.PathUtils.depth_params(
        clearance_height=obj.ClearanceHeight.Value,
        safe_height=obj.SafeHeight.Value,
        start_depth=start,
        step_down=step,
        z_finish_step=0.0,
        final_depth=final,
        user_depths=None,
    )
    levels = [float(z) for z in params]
    if not levels:
        levels = [final]
    return levels


def pocket_params(obj, core, radius, tolerance, scallop=None):
    """PocketParams from the op's properties; the core checks the ranges."""
    params = core.PocketParams()
    params.tool_radius = radius
    params.stepover = 2.0 * radius * obj.StepOver / 100.0
    params.tolerance = tolerance
    params.floor_tolerance = tolerance
    if scallop is not None:
        params.scallop_height = scallop
    params.direction = getattr(core.CutDirection, obj.Direction)
    params.safe_z = obj.SafeHeight.Value
    params.max_moves = op_base.max_moves(obj)
    return params


def run_core(proxy, core, call, name):
    """Run ``call(progress)`` in a worker thread and wait for it.

    The Progress object is kept in ``proxy.active_progress`` while the core
    runs, so a task panel can poll its fraction or cancel() it.
    """
    progress = core.Progress()
    outcome = {}

    def work():
        try:
            outcome["result"] = call(progress)
        except BaseException as exc:  # handed to the calling thread
            outcome["error"] = exc

    worker = threading.Thread(target=work, name="isocam-" + name)
    proxy.active_progress = progress
    try:
        worker.start()
        _wait(worker, progress, name)
    finally:
        proxy.active_progress = None
    if "error" in outcome:
        raise outcome["error"]
    return outcome["result"]


def _wait(worker, progress, name):
    """Block until the worker ends; in the GUI keep the window painted."""
    if not FreeCAD.GuiUp:
        worker.join()
        return
    from PySide import QtCore, QtGui  # GUI only

    import FreeCADGui

    bar = FreeCADGui.getMainWindow().statusBar()
    while worker.is_alive():
        worker.join(0.1)
        bar.showMessage("%s: %d %%" % (name, int(100 * progress.fraction)))
        QtGui.QApplication.processEvents(QtCore.QEventLoop.ExcludeUserInputEvents)
    bar.clearMessage()


def picked_faces(obj):
    """[(model object, [0-based face indices])] from obj.Base, in pick order."""
    return op_base.picked_faces(obj, "floor faces")


def add_properties(obj, inputs, outputs, output_group, set_defaults):
    """Add the op's own properties that `obj` does not have yet.

    inputs: (type, name, group, tip, default[, enumeration]);
    outputs: (type, name, metrics attribute, tip), read-only outputs.
    """
    for row in inputs:
        prop_type, name, group, tip, default = row[:5]
        if not hasattr(obj, name):
            obj.addProperty(prop_type, name, group, tip)
            if len(row) > 5:
                setattr(obj, name, list(row[5]))
            if set_defaults:
                setattr(obj, name, default)
    for prop_type, name, _attr, tip in outputs:
        if not hasattr(obj, name):
            obj.addProperty(prop_type, name, output_group, tip)
        obj.setEditorMode(name, 1)  # read-only in the property editor
        if hasattr(obj, "setPropertyStatus"):  # not on a SetupSheet prototype
            obj.setPropertyStatus(name, ["ReadOnly", "Output"])


def write_outputs(obj, outputs, metrics):
    for _type, name, attr, _tip in outputs:
        setattr(obj, name, getattr(metrics, attr))



# Metrics every pocketing op reports (type, property, metrics attribute, tip).
OUTPUTS = (
    (
        "App::PropertyLength",
        "CuttingLength",
        "cutting_length",
        "Length of the cutting moves (G1, G2, G3)",
    ),
    ("App::PropertyLength", "RapidLength", "rapid_length", "Length of the rapid moves"),
    (
        "App::PropertyInteger",
        "Retracts",
        "retracts",
        "Number of retracts to SafeHeight",
    ),
    (
        "App::PropertyInteger",
        "FeedLinks",
        "feed_links",
        "Loop-to-loop links cut without a retract",
    ),
    (
        "App::PropertyInteger",
        "Loops",
        "loops",
        "Number of offset profiles cut (all levels)",
    ),
    ("App::PropertyInteger", "Levels", "levels", "Number of z levels"),
    (
        "App::PropertyInteger",
        "CLPoints",
        "cl_points",
        "Number of cutting moves (CL points)",
    ),
    ("App::PropertyInteger", "Arcs", "arcs", "Number of G2/G3 arcs"),
    (
        "App::PropertyLength",
        "MinInterval",
        "min_interval",
        "Smallest path interval used",
    ),
    (
        "App::PropertyLength",
        "MaxInterval",
        "max_interval",
        "Largest path interval used",
    ),
)
OUTPUT_GROUP = "Result"


def arrays_from_path(path, start=(0.0, 0.0, 0.0)):
    """The moves of a ``Path.Path`` (G0/G1/G2/G3 in the XY plane) as the
    core's flat arrays (kind, xyz, centre), e.g. to check FreeCAD's own
    operations with ``isocam_core.pocket_coverage``. A G1 that only goes
    down counts as a plunge; modal coordinates are filled in.
    """
    import numpy as np

    x, y, z = start
    kinds, pts, centres = [], [], []
    nan = float("nan")
    for c in path.Commands:
        name = c.Name
        if name not in ("G0", "G00", "G1", "G01", "G2", "G02", "G3", "G03"):
            continue
        p = c.Parameters
        nx, ny, nz = p.get("X", x), p.get("Y", y), p.get("Z", z)
        cx = cy = nan
        if name in ("G0", "G00"):
            k = MOVE_RAPID
        elif name in ("G1", "G01"):
            k = MOVE_PLUNGE if (nx, ny) == (x, y) and nz < z else MOVE_FEED
        else:
            k = MOVE_ARC_CW if name in ("G2", "G02") else MOVE_ARC_CCW
            cx, cy = x + p.get("I", 0.0), y + p.get("J", 0.0)
        kinds.append(k)
        pts.append((nx, ny, nz))
        centres.append((cx, cy))
        x, y, z = nx, ny, nz
    return (
        np.array(kinds, dtype=np.uint8),
        np.array(pts, dtype=float).reshape(-1, 3),
        np.array(centres, dtype=float).reshape(-1, 2),
    )


def argument_sources(own):
    """Core argument names -> what the FreeCAD user sets, for a pocketing op
    whose own rows are `own` (listed after stepover and tolerance)."""
    return (
        ("stepover", "property StepOver"),
        ("tolerance", "property Tolerance"),
        *own,
        ("safe_z", "property SafeHeight"),
        ("depths", "properties StartDepth / FinalDepth / StepDown"),
        ("tool_radius", "the tool controller's tool diameter / 2"),
    )


class PocketOp(IsoCAMOp):
    """Base of the pocketing operations: FreeCAD's depth features, and the
    subclass's INPUTS plus the shared certificate OUTPUTS as properties."""

    INPUTS = ()
    OUTPUTS = OUTPUTS

    def opFeatures(self, obj):
        return (
            PathOp.FeatureTool
            | PathOp.FeatureDepths
            | PathOp.FeatureHeights
            | PathOp.FeatureStepDown
            | PathOp.FeatureBaseFaces
            | PathOp.FeatureCoolant
        )

    def add_properties(self, obj):
        add_properties(obj, self.INPUTS, OUTPUTS, OUTPUT_GROUP, True)
