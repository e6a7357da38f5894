"""Adaptive isocurve finishing with a ball-end tool, as a FreeCAD Path operation.

Thin operation (ENGINEERING.md, habit 6): ``opExecute`` maps the op's
properties and its tool controller to ``isocam_core.IsoParams``, runs
``isocam_core.adaptive_isocurve`` on the picked faces in a worker thread and
turns the returned flat move arrays into ``Path.Command``s. It never writes
the user's properties; it only writes the read-only "Certificate" properties
(the core's metrics) after each run and prints them to the report view.

Errors (habit 4, one error model). A bad input -- a tool that is not a ball
end, no face picked, a parameter out of range (the core's ``ValueError``), a
face the core cannot machine (its ``RuntimeError``), a cancel requested through
``op.Proxy.active_progress.cancel()`` -- is logged
with a message that names the tool, property or face; the op's Path is
emptied, its certificate cleared, and :class:`IsoCAMError` is raised out of
``execute``. FreeCAD then marks this object, and only it, invalid (red mark in
the tree; ``obj.getStatusString()`` returns the message). This behaves well
headless too: ``Document.recompute()`` does not raise, the other objects keep
their values and objects depending on the op stay touched. FreeCAD's own ops
log and return normally, which leaves a valid-looking op with a stale or
empty path; we do not copy that.

Cancel from the GUI's progress dialog is not an error of the inputs: the
recompute is aborted and the op keeps its previous path and certificate,
marked to be recomputed (freecad_ext/gui/progress.py).
"""

import math
import threading
import time

import FreeCAD
import Path

from freecad_ext import compat, op_base
from freecad_ext.compat import PathOp
from freecad_ext.op_base import IsoCAMError, IsoCAMOp, picked_faces

__title__ = "IsoCAM Adaptive Isocurve operation"

# Name under which the op is registered with the SetupSheet; Create(name)
# picks up SetupSheet defaults when called with this name.
OP_NAME = "AdaptiveIsocurve"

DIRECTIONS = ("Auto", "U", "V")
# The pattern: Algorithm 1, or one of the two yardsticks with the same
# guarantee (complete isocurves equally spaced; planes of constant X or Y),
# or non-isoparametric passes placed by the strip width (Lee 1998).
PATTERNS = ("Adaptive", "Uniform", "ParallelPlanes", "ConstantScallop")
SCALLOP_BOUNDS = ("Curvature", "Flat")
_ENUMERATIONS = {
    "Direction": DIRECTIONS,
    "Pattern": PATTERNS,
    "ScallopBound": SCALLOP_BOUNDS,
}

# (type, name, group, tooltip, default) of the user's parameters.
_INPUTS = (
    (
        "App::PropertyLength",
        "ScallopHeight",
        "Adaptive Isocurve",
        "Largest scallop height left between adjacent passes; sets the "
        "stepover. Must be smaller than the ball radius.",
        0.01,
    ),
    (
        "App::PropertyEnumeration",
        "Pattern",
        "Adaptive Isocurve",
        "Adaptive: sub-isocurves only where needed (Elber & Cohen, Algorithm 1). "
        "Uniform: complete isocurves equally spaced in parameter. ParallelPlanes: "
        "planes of constant X or Y. All three keep the same scallop guarantee "
        "(the last two are the yardsticks). ConstantScallop: passes that are not "
        "isocurves, each placed from the one before by the width of the strip it "
        "machines (Lee 1998); its certificate is measured between the passes.",
        "Adaptive",
    ),
    (
        "App::PropertyEnumeration",
        "ScallopBound",
        "Adaptive Isocurve",
        "Curvature: the stepover follows the curvature across the feed, so the "
        "scallop stays under ScallopHeight on convex ground too and widens "
        "on concave ground. Flat: the paper's flat-ground stepover, never "
        "wider, narrowed as Curvature on convex ground. Both keep "
        "GuaranteedScallop <= ScallopHeight.",
        "Curvature",
    ),
    (
        "App::PropertyEnumeration",
        "Direction",
        "Adaptive Isocurve",
        "Isocurve direction: U (u constant), V (v constant), or Auto "
        "(per face, the one with the shorter planned path).",
        "Auto",
    ),
    (
        "App::PropertyBool",
        "ProtectModel",
        "Adaptive Isocurve",
        "Keep the ball clear of every face of the model, not only the picked "
        "ones (each face inside its edges). Where another face keeps the ball "
        "from a picked one, material is left (UnreachableLength says how "
        "much). Off: only the picked faces are protected.",
        True,
    ),
    (
        "App::PropertyLength",
        "OvercutTolerance",
        "Adaptive Isocurve",
        "Deepest cut below the design allowed anywhere (chords on convex "
        "ground, clearance check, rounding of the posted coordinates); "
        "GuaranteedOvercut stays within it.",
        0.005,
    ),
    (
        "App::PropertyLength",
        "ChordTolerance",
        "Adaptive Isocurve",
        "Advanced: largest distance between a pass and its linear G1 segments. "
        "0 (default): derived from ScallopHeight and OvercutTolerance; "
        "otherwise it must fit both, and the guarantees include it.",
        0.0,
    ),
    (
        "App::PropertyInteger",
        "PostPrecision",
        "Adaptive Isocurve",
        "Decimals of the coordinates the post-processor writes (linuxcnc: "
        "--precision, default 3); the guarantees include their rounding.",
        3,
    ),
    (
        "App::PropertyLength",
        "AirClearance",
        "Adaptive Isocurve",
        "Gap kept between the ball and the model by rapid moves between "
        "passes, and the height above an entry point from which it is fed.",
        1.0,
    ),
    (
        "App::PropertyFloat",
        "RapidRate",
        "Adaptive Isocurve",
        "Rapid rate of the machine in mm/min, for MachineTime and CycleTime "
        "(and the choice between a feed link and a hop).",
        5000.0,
    ),
)

# (type, property name, core metrics attribute or None, tooltip) of the
# read-only outputs written after every run.
_OUTPUTS = (
    (
        "App::PropertyLength",
        "CuttingLength",
        "cutting_length",
        "Length of the feed moves",
    ),
    ("App::PropertyLength", "RapidLength", "rapid_length", "Length of the rapid moves"),
    ("App::PropertyLength", "PlungeLength", "plunge_length", "Length of the plunges"),
    (
        "App::PropertyInteger",
        "SubIsocurves",
        "sub_isocurves",
        "Number of (sub-)isocurves cut",
    ),
    (
        "App::PropertyInteger",
        "Retracts",
        "retracts",
        "Number of retracts to SafeHeight",
    ),
    (
        "App::PropertyLength",
        "IsoDistanceTolerance",
        "delta",
        "Stepover that leaves ScallopHeight on flat ground (the iso-distance bound)",
    ),
    (
        "App::PropertyLength",
        "IsoDistanceToleranceMax",
        "delta_max",
        "Largest iso-distance tolerance used on any patch (the curvature bound "
        "allows more than the flat one on concave ground, less on convex)",
    ),
    (
        "App::PropertyLength",
        "MaxIsoDistance",
        "max_iso_distance",
        "Largest iso-distance left between adjacent isocurves",
    ),
    (
        "App::PropertyLength",
        "GuaranteedScallop",
        "guaranteed_scallop",
        "The most material left above the design where the ball reaches, "
        "everything included: the cusp of the largest iso-distance of every "
        "pair of adjacent curves on the largest curvature across the feed "
        "there, for centres off the offset by the chords and the rounding of "
        "the posted coordinates, plus that (<= ScallopHeight)",
    ),
    (
        "App::PropertyLength",
        "GuaranteedOvercut",
        "guaranteed_overcut",
        "The deepest cut below the design: chord tolerance + clearance check "
        "tolerance + rounding of the posted coordinates (<= OvercutTolerance)",
    ),
    (
        "App::PropertyLength",
        "ChordToleranceUsed",
        "chord_tolerance",
        "The chord tolerance used (derived from the budgets, or ChordTolerance)",
    ),
    (
        "App::PropertyFloat",
        "MachineTime",
        "machine_time",
        "Estimated machine time (s) of this op's commands at the tool "
        "controller's feeds and RapidRate, no acceleration (also CycleTime)",
    ),
    (
        "App::PropertyFloat",
        "CuttingTime",
        "cutting_time",
        "Estimated time (s) of the feed moves (passes and the links along the surface)",
    ),
    (
        "App::PropertyLength",
        "LowerBoundLength",
        "lower_bound_length",
        "L*: integral over the picked faces of dA / w_max, a lower bound on "
        "the cutting length of any path with this scallop",
    ),
    (
        "App::PropertyFloat",
        "LengthRatio",
        "length_ratio",
        "CuttingLength / LowerBoundLength (1 would be optimal)",
    ),
    (
        "App::PropertyLength",
        "UnreachableLength",
        "unreachable_length",
        "Length of tool-centre path left out because the ball would come "
        "closer than its radius to the model there, or a vertical tool cannot "
        "reach the place from above (material is left)",
    ),
    (
        "App::PropertyLength",
        "UnreachableFromAboveLength",
        "unreachable_from_above_length",
        "Of UnreachableLength: the path left out because a vertical tool "
        "cannot reach those places from above (undersides, places under an "
        "overhang; the ball there would be clear, the tool above it would not)",
    ),
    ("App::PropertyString", "DirectionUsed", None, "Isocurve direction used, per face"),
)
_OUTPUT_GROUP = "Certificate"


# Core argument names -> what the FreeCAD user sets.
_ARGUMENT_SOURCES = (
    ("scallop_height", "property ScallopHeight"),
    ("overcut_tolerance", "property OvercutTolerance"),
    ("chord_tolerance", "property ChordTolerance"),
    ("posted_resolution", "property PostPrecision"),
    ("air_clearance", "property AirClearance"),
    ("rapid_rate", "property RapidRate"),
    ("feed_rate", "the tool controller's HorizFeed"),
    ("plunge_rate", "the tool controller's VertFeed"),
    ("safe_z", "property SafeHeight"),
    ("ball_radius", "the tool controller's tool diameter / 2"),
    ("direction", "property Direction"),
    ("pattern", "property Pattern"),
    ("scallop_bound", "property ScallopBound"),
)


class ObjectAdaptiveIsocurve(IsoCAMOp):
    """Proxy of an Adaptive Isocurve operation (module-level so documents reopen)."""

    OUTPUTS = _OUTPUTS
    ARGUMENT_SOURCES = _ARGUMENT_SOURCES

    # -- PathOp hooks -------------------------------------------------------

    def opFeatures(self, obj):
        # No FeatureDepths: the passes follow the surface, depths do not apply.
        return (
            PathOp.FeatureTool
            | PathOp.FeatureHeights
            | PathOp.FeatureBaseFaces
            | PathOp.FeatureCoolant
        )

    def add_properties(self, obj):
        _add_properties(obj, set_defaults=True)

    def accepts_tool(self, tool):
        return compat.is_ball_end(tool)

    def opExecute(self, obj):
        started = time.monotonic()
        results = self.compute_or_fail(obj)
        self.emit_commands(obj, results)
        metrics = _combined_metrics(results)
        # The op's own commands (the lead-in at ClearanceHeight included),
        # as getCycleTimeEstimate() gives FreeCAD's CycleTime.
        # PathOp appends the retract to ClearanceHeight after opExecute.
        final = [Path.Command("G0", {"Z": obj.ClearanceHeight.Value})]
        metrics["machine_time"] = machine_seconds(
            self.commandlist + final, _rapid_mm_min(obj), *_feeds_mm_min(obj)
        )
        _write_outputs(obj, metrics, _directions_used(results))
        _print_certificate(obj, metrics, time.monotonic() - started)
        _warn_guarantee(obj, metrics)
        for res in results:
            for warning in res.warnings:
                op_base.PathLog.warning("%s: %s" % (obj.Label, warning))

    # -- steps of opExecute -------------------------------------------------

    def execute(self, obj):
        # FreeCAD 1.1 takes CycleTime from a module function of Path.Op.Base,
        # not from getCycleTimeEstimate() below: set it again afterwards (the
        # same value on 0.20 and 1.0, which call the method).
        result = super().execute(obj)
        if obj.ToolController is not None:
            obj.CycleTime = self.getCycleTimeEstimate(obj)
        return result

    def getCycleTimeEstimate(self, obj):
        """FreeCAD's CycleTime: our estimate (MachineTime), as HH:MM:SS.

        FreeCAD 0.20's Path.getCycleTime() ignores the F words and takes
        every move that changes Z at the vertical rate, which for a 3D
        finishing path (nearly every G1 changes Z) gives some three times
        the real time; this estimate takes each G1 at its own F, G0 at
        RapidRate, as the machine runs them.
        """
        if obj.ToolController is None:
            return super().getCycleTimeEstimate(obj)
        seconds = machine_seconds(obj.Path.Commands, _rapid_mm_min(obj), *_feeds_mm_min(obj))
        return time.strftime("%H:%M:%S", time.gmtime(seconds))

    def _compute(self, obj, core):
        """Run the core once per model object that has picked faces."""
        _check_ball_end(obj)
        picked = _picked_faces(obj)
        params = _iso_params(obj, core, self.radius)
        results = []
        for base, faces in picked:
            brep = base.Shape.exportBrepToString()
            results.append(self._run_core(core, brep, faces, params, base))
        results = [r for r in results if len(r.kind) > 0]
        if not results:
            raise IsoCAMError("the core returned no moves for the picked faces")
        return results

    def _run_core(self, core, brep, faces, params, base):
        """Call the core in a worker thread (it releases the GIL) and wait.

        The Progress object is kept in ``self.active_progress`` while the
        core runs, so a task panel can poll its fraction or cancel() it.
        """
        progress = core.Progress()
        outcome = {}

        def work():
            try:
                outcome["result"] = core.adaptive_isocurve(
                    brep, faces, params, progress
                )
            except BaseException as exc:  # handed to the calling thread
                outcome["error"] = exc

        worker = threading.Thread(target=work, name="isocam-adaptive-isocurve")
        self.active_progress = progress
        try:
            worker.start()
            _wait(worker, progress)
        finally:
            self.active_progress = None
        if "error" in outcome:
            exc = outcome["error"]
            if isinstance(exc, RuntimeError) and not isinstance(
                exc, core.CancelledError
            ):
                raise RuntimeError("%s (model %s)" % (exc, base.Label)) from exc
            raise exc
        return outcome["result"]



# -- helpers (module level: small, no FreeCAD object state) -----------------


def _add_properties(obj, set_defaults):
    """Add the op's own properties that `obj` does not have yet."""
    for prop_type, name, group, tip, default in _INPUTS:
        if not hasattr(obj, name):
            obj.addProperty(prop_type, name, group, tip)
            if name in _ENUMERATIONS:
                setattr(obj, name, list(_ENUMERATIONS[name]))
            if set_defaults:
                setattr(obj, name, default)
    for prop_type, name, _attr, tip in _OUTPUTS:
        if not hasattr(obj, name):
            obj.addProperty(prop_type, name, _OUTPUT_GROUP, tip)
        obj.setEditorMode(name, 1)  # read-only in the property editor
        if hasattr(obj, "setPropertyStatus"):  # not on a SetupSheet prototype
            # Output: writing it during execute does not touch the op again.
            obj.setPropertyStatus(name, ["ReadOnly", "Output"])


def _check_ball_end(obj):
    tc = obj.ToolController
    tool = tc.Tool
    if not compat.is_ball_end(tool):
        raise IsoCAMError(
            "tool '%s' of tool controller '%s' is not a ball end (its shape is "
            "'%s'); Adaptive Isocurve needs a ball-end tool (ToolBit shape "
            "ballend.fcstd)"
            % (compat.tool_label(tool), tc.Label, compat.tool_shape(tool) or "unknown")
        )


def _picked_faces(obj):
    """[(model object, [0-based face indices])] from obj.Base, in pick order."""
    picked = picked_faces(obj)
    if not picked:
        raise IsoCAMError(
            "no faces picked: set Base to one or more faces of the Job's model"
        )
    return picked


# Feeds of the machine-time estimate where the tool controller has none
# (mm/min; the core's defaults).
_DEFAULT_FEED, _DEFAULT_PLUNGE = 1200.0, 400.0


def _feeds_mm_min(obj):
    """(horizontal, vertical) feed of the tool controller in mm/min, or the
    defaults where it has none."""
    tc = obj.ToolController
    h = tc.HorizFeed.Value * 60.0 if tc is not None else 0.0
    v = tc.VertFeed.Value * 60.0 if tc is not None else 0.0
    return (h if h > 0 else _DEFAULT_FEED, v if v > 0 else _DEFAULT_PLUNGE)


def _rapid_mm_min(obj):
    return float(obj.RapidRate)  # mm/min


def machine_seconds(commands, rapid, feed, plunge):
    """Estimated time (s) of Path commands, no acceleration: G0 at `rapid`,
    G1/G2/G3 at their F word (mm/s, FreeCAD's unit; `feed` / `plunge` in
    mm/min where a move has none and is horizontal / vertical), arcs by
    their chord. The first two moves (from wherever the machine is, up and
    across at ClearanceHeight) are not counted, as the core does not count
    its first move."""
    pos = None
    total = 0.0
    moves = 0
    for c in commands:
        p = c.Parameters
        if c.Name not in ("G0", "G00", "G1", "G01", "G2", "G02", "G3", "G03"):
            continue
        moves += 1
        nxt = tuple(p.get(a, pos[i] if pos else 0.0) for i, a in enumerate("XYZ"))
        if pos is not None and moves > 2:
            length = math.dist(pos, nxt)
            if c.Name in ("G0", "G00"):
                rate = rapid
            elif p.get("F", 0.0) > 0:
                rate = p["F"] * 60.0
            else:
                rate = plunge if pos[:2] == nxt[:2] else feed
            total += 60.0 * length / rate
        pos = nxt
    return total


def _iso_params(obj, core, ball_radius):
    """IsoParams from the op's properties; the core checks the ranges."""
    params = core.IsoParams()
    params.ball_radius = ball_radius
    params.scallop_height = obj.ScallopHeight.Value
    params.overcut_tolerance = obj.OvercutTolerance.Value
    params.chord_tolerance = obj.ChordTolerance.Value
    if not 0 <= obj.PostPrecision <= 9:
        raise IsoCAMError(
            "PostPrecision must be 0..9 decimals (got %d)" % obj.PostPrecision
        )
    params.posted_resolution = 10.0 ** -obj.PostPrecision
    params.air_clearance = obj.AirClearance.Value
    params.feed_rate, params.plunge_rate = _feeds_mm_min(obj)
    params.rapid_rate = _rapid_mm_min(obj)
    params.direction = getattr(core.IsoDirection, obj.Direction)
    params.pattern = getattr(core.IsoPattern, obj.Pattern)
    params.scallop_bound = getattr(core.IsoScallopBound, obj.ScallopBound)
    params.protect_unpicked_faces = bool(obj.ProtectModel)
    params.safe_z = obj.SafeHeight.Value
    params.max_moves = op_base.max_moves(obj)
    return params


def _wait(worker, progress):
    """Block until the worker ends.

    In the GUI, freecad_ext.gui.progress keeps the window painted, shows the
    progress and lets the user cancel (see there for what a cancel does).
    """
    if not FreeCAD.GuiUp:
        worker.join()
        return
    from freecad_ext.gui import progress as gui_progress  # GUI only

    gui_progress.wait(worker, progress, "Adaptive isocurve")


def _combined_metrics(results):
    """One set of metrics for the runs over several model objects.

    Lengths and counts add up, the iso-distance bounds take the worst run.
    Rapids that link one model object's path to the next are not counted.
    """
    first = results[0].metrics
    combined = {"delta": first.delta}
    for attr in (
        "cutting_length",
        "rapid_length",
        "plunge_length",
        "machine_time",
        "cutting_time",
        "lower_bound_length",
        "unreachable_length",
        "unreachable_from_above_length",
    ):
        combined[attr] = sum(getattr(r.metrics, attr) for r in results)
    for attr in ("sub_isocurves", "retracts"):
        combined[attr] = sum(int(getattr(r.metrics, attr)) for r in results)
    for attr in (
        "max_iso_distance",
        "guaranteed_scallop",
        "guaranteed_overcut",
        "chord_tolerance",
        "delta_max",
    ):
        combined[attr] = max(getattr(r.metrics, attr) for r in results)
    lower = combined["lower_bound_length"]
    combined["length_ratio"] = combined["cutting_length"] / lower if lower > 0 else 0.0
    return combined


def _directions_used(results):
    return ", ".join(d for r in results for d in r.face_direction)


def _write_outputs(obj, metrics, directions):
    for _type, name, attr, _tip in _OUTPUTS:
        if attr is not None:
            setattr(obj, name, metrics[attr])
    obj.DirectionUsed = directions


def _print_certificate(obj, m, seconds):
    FreeCAD.Console.PrintMessage(
        "IsoCAM %s (%s, %s bound): %d sub-isocurves (direction %s), "
        "cutting %.1f mm = %.2f x L* (%.1f mm), rapid %.1f mm, plunge %.1f mm, "
        "%d retracts; iso-distance tolerance %.4f..%.4f mm, max iso-distance "
        "%.4f mm -> guaranteed scallop %.5f mm (requested %.5f mm), "
        "guaranteed overcut %.5f mm (allowed %.5f mm, chords %.5f mm); "
        "machine time %.1f min (cutting %.1f min); unreachable %.1f mm "
        "(from above %.1f mm); %.2f s\n"
        % (
            obj.Label,
            obj.Pattern,
            obj.ScallopBound,
            m["sub_isocurves"],
            obj.DirectionUsed,
            m["cutting_length"],
            m["length_ratio"],
            m["lower_bound_length"],
            m["rapid_length"],
            m["plunge_length"],
            m["retracts"],
            m["delta"],
            m["delta_max"],
            m["max_iso_distance"],
            m["guaranteed_scallop"],
            obj.ScallopHeight.Value,
            m["guaranteed_overcut"],
            obj.OvercutTolerance.Value,
            m["chord_tolerance"],
            m["machine_time"] / 60.0,
            m["cutting_time"] / 60.0,
            m["unreachable_length"],
            m["unreachable_from_above_length"],
            seconds,
        )
    )


def _warn_guarantee(obj, m):
    """A warning in the report when the certificate promises less than asked."""
    requested = obj.ScallopHeight.Value
    if m["guaranteed_scallop"] > requested * (1 + 1e-6):
        op_base.PathLog.warning(
            "%s: the guaranteed scallop height %.5f mm is above the requested %.5f mm "
            "(ScallopBound = %s; the flat bound does not hold on convex ground)"
            % (obj.Label, m["guaranteed_scallop"], requested, obj.ScallopBound)
        )


def SetupProperties():
    """Properties for which a Job's SetupSheet may hold defaults."""
    return [
        "ScallopHeight",
        "OvercutTolerance",
        "Direction",
        "ChordTolerance",
        "Pattern",
        "ScallopBound",
        "AirClearance",
        "RapidRate",
    ]


def Create(name=OP_NAME, obj=None, parentJob=None, toolController=None):
    """Create an Adaptive Isocurve op and add it to `parentJob` (or the only Job).

    `toolController`: use this one instead of letting FreeCAD choose (headless
    FreeCAD cannot choose among several). Otherwise the job's only ball-end
    tool controller, or the previous op's, is used.
    """
    return op_base.create_op(
        ObjectAdaptiveIsocurve, name, obj, parentJob, toolController, "the Job has no ball-end tool controller; add one (ToolBit shape "
        "ballend.fcstd) or pass toolController="
    )


compat.PathSetupSheet.RegisterOperation(OP_NAME, Create, SetupProperties)
