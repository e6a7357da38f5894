"""Shared glue of the pocketing operations (Spiral Pocket, Z-level Roughing).

Maps FreeCAD's depth properties to the core's z levels; op_base runs the
core (worker thread, progress and cancel) and turns its flat move arrays --
with G2/G3 arcs -- into ``Path.Command``s, feeds by FreeCAD's setFeedRate.
No geometry here.
"""

from freecad_ext import compat, op_base
from freecad_ext.compat import QT_TRANSLATE_NOOP, PathOp, translate
from freecad_ext.op_base import IsoCAMError, IsoCAMOp

DIRECTIONS = ("Climb", "Conventional")


def __getattr__(name):
    # MOVE_RAPID, MOVE_ARC_CW, ...: the core's move kinds (op_base).
    if name.startswith("MOVE_"):
        return getattr(op_base, name)
    raise AttributeError("module %r has no attribute %r" % (__name__, name))


def depth_levels(obj):
    """The z levels of the op, top to bottom, from FreeCAD's StartDepth,
    FinalDepth and StepDown (PathUtils.depth_params, as FreeCAD's own ops)."""
    step = obj.StepDown.Value
    if step <= 0:
        raise IsoCAMError(translate("IsoCAM", "property StepDown must be > 0 (it is %g mm)") % step)
    start, final = obj.StartDepth.Value, obj.FinalDepth.Value
    if final > start:
        raise IsoCAMError(
            translate("IsoCAM", "property FinalDepth (%g mm) is above StartDepth (%g mm)")
            % (final, start)
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
    """``proxy.run_core`` (op_base): the call in a worker thread, with
    progress and cancel."""
    return proxy.run_core(core, call, name)


def picked_faces(obj):
    """[(model object, [0-based face indices])] from obj.Base, in pick order."""
    return op_base.picked_faces(obj, translate("IsoCAM", "floor faces"))


def write_outputs(obj, outputs, metrics):
    op_base.write_outputs(obj, outputs, metrics)


# Metrics every pocketing op reports (type, property, metrics attribute, tip).
OUTPUTS = (
    (
        "App::PropertyLength",
        "CuttingLength",
        "cutting_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Length of the cutting moves (G1, G2, G3)",
        ),
    ),
    (
        "App::PropertyLength",
        "RapidLength",
        "rapid_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Length of the rapid moves",
        ),
    ),
    (
        "App::PropertyInteger",
        "Retracts",
        "retracts",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Number of retracts to SafeHeight",
        ),
    ),
    (
        "App::PropertyInteger",
        "FeedLinks",
        "feed_links",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Loop-to-loop links cut without a retract",
        ),
    ),
    (
        "App::PropertyInteger",
        "Loops",
        "loops",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Number of offset profiles cut (all levels)",
        ),
    ),
    (
        "App::PropertyInteger",
        "Levels",
        "levels",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Number of z levels",
        ),
    ),
    (
        "App::PropertyInteger",
        "CLPoints",
        "cl_points",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Number of cutting moves (CL points)",
        ),
    ),
    (
        "App::PropertyInteger",
        "Arcs",
        "arcs",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Number of G2/G3 arcs",
        ),
    ),
    (
        "App::PropertyLength",
        "MinInterval",
        "min_interval",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Smallest path interval used",
        ),
    ),
    (
        "App::PropertyLength",
        "MaxInterval",
        "max_interval",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Largest path interval used",
        ),
    ),
)


def arrays_from_path(path, start=(0.0, 0.0, 0.0)):
    """The moves of a ``Path.Path`` (G0/G1/G2/G3 in the XY plane) as the
    core's flat arrays (kind, xyz, centre), e.g. to check FreeCAD's own
    operations with ``isocam_core.pocket_coverage``. A G1 that only goes
    down counts as a plunge; modal coordinates are filled in.
    """
    import numpy as np

    core = compat.import_core()
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
            k = core.RAPID
        elif name in ("G1", "G01"):
            k = core.PLUNGE if (nx, ny) == (x, y) and nz < z else core.FEED
        else:
            k = core.ARC_CW if name in ("G2", "G02") else core.ARC_CCW
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
    """Base of the pocketing operations: FreeCAD's depth features, the
    shared certificate OUTPUTS, feeds by FreeCAD's setFeedRate (the same
    feeds as the core's move kinds on these paths: straight-down plunges,
    no zero-length moves), and the subclass's opPropertyDefinitions()."""

    OUTPUTS = OUTPUTS
    ENUMERATIONS = {
        "Direction": tuple(QT_TRANSLATE_NOOP("IsoCAM", d) for d in DIRECTIONS),
    }
    FEEDS_BY_SET_FEED_RATE = True

    def opFeatures(self, obj):
        return super().opFeatures(obj) | PathOp.FeatureDepths | PathOp.FeatureStepDown
