"""Adaptive isocurve finishing with a ball-end tool, as a FreeCAD Path operation.

Thin operation (ENGINEERING.md, habit 6): ``opExecute`` maps the op's
properties and its tool controller to ``isocam_core.IsoParams``, runs
``isocam_core.adaptive_isocurve`` on the picked faces in a worker thread and
turns the returned flat move arrays into ``Path.Command``s. It never writes
the user's properties; it only writes the read-only "Certificate" properties
(the core's metrics) after each run and prints them to the report view.

Errors (habit 4, one error model). A picked face the core cannot machine (a
degenerate face, a guard tripped on it) is skipped by the core with a
warning, which goes to the report view; the other faces are finished. A bad
input -- a tool that is not a ball end, no face picked, a parameter out of
range (the core's ``ValueError``), no picked face the core can machine (its
``RuntimeError``), a cancel requested through
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
import time

import Path

from freecad_ext import compat, op_base
from freecad_ext.compat import QT_TRANSLATE_NOOP, translate
from freecad_ext.op_base import IsoCAMError, IsoCAMOp, picked_faces

log = compat.logger(__name__)

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

# (type, property name, core metrics attribute or None, tooltip) of the
# read-only outputs written after every run (op_base.OUTPUT_GROUP).
_OUTPUTS = (
    (
        "App::PropertyLength",
        "CuttingLength",
        "cutting_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Length of the feed moves",
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
        "App::PropertyLength",
        "PlungeLength",
        "plunge_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Length of the plunges",
        ),
    ),
    (
        "App::PropertyInteger",
        "SubIsocurves",
        "sub_isocurves",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Number of (sub-)isocurves cut",
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
        "App::PropertyLength",
        "IsoDistanceTolerance",
        "delta",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Stepover that leaves ScallopHeight on flat ground (the " "iso-distance bound)",
        ),
    ),
    (
        "App::PropertyLength",
        "IsoDistanceToleranceMax",
        "delta_max",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Largest iso-distance tolerance used on any patch (the curvature "
            "bound allows more than the flat one on concave ground, less on "
            "convex)",
        ),
    ),
    (
        "App::PropertyLength",
        "MaxIsoDistance",
        "max_iso_distance",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Largest iso-distance left between adjacent isocurves",
        ),
    ),
    (
        "App::PropertyLength",
        "GuaranteedScallop",
        "guaranteed_scallop",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "The most material left above the design where the ball reaches, "
            "everything included: the cusp of the largest iso-distance of "
            "every pair of adjacent curves on the largest curvature across "
            "the feed there, for centres off the offset by the chords and the "
            "rounding of the posted coordinates, plus that (<= ScallopHeight). "
            "ParallelPlanes: per face, the cusp of its largest pass spacing "
            "(MaxIsoDistance) on its most concave ground, which exceeds "
            "ScallopHeight where the planes run steeply; the ball radius means "
            "no bound (on walls the passes are too far apart for the balls to "
            "meet). ConstantScallop: from the spacing measured between its paths.",
        ),
    ),
    (
        "App::PropertyLength",
        "GuaranteedOvercut",
        "guaranteed_overcut",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "The deepest cut below the design: chord tolerance + clearance "
            "check tolerance + rounding of the posted coordinates (<= "
            "OvercutTolerance)",
        ),
    ),
    (
        "App::PropertyLength",
        "ChordToleranceUsed",
        "chord_tolerance",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "The chord tolerance used (derived from the budgets, or " "ChordTolerance)",
        ),
    ),
    (
        "App::PropertyFloat",
        "MachineTime",
        "machine_time",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Estimated machine time (s) of this op's commands at the tool "
            "controller's feeds and RapidRate, no acceleration (also "
            "CycleTime)",
        ),
    ),
    (
        "App::PropertyFloat",
        "CuttingTime",
        "cutting_time",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Estimated time (s) of the feed moves (passes and the links along " "the surface)",
        ),
    ),
    (
        "App::PropertyLength",
        "LowerBoundLength",
        "lower_bound_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "L*: integral over the picked faces of dA / w_max, a lower bound "
            "on the cutting length of any path with this scallop",
        ),
    ),
    (
        "App::PropertyFloat",
        "LengthRatio",
        "length_ratio",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "CuttingLength / LowerBoundLength (1 would be optimal)",
        ),
    ),
    (
        "App::PropertyLength",
        "UnreachableLength",
        "unreachable_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Length of tool-centre path left out because the ball would come "
            "closer than its radius to the model there, or a vertical tool cannot "
            "reach the place from above (material is left)",
        ),
    ),
    (
        "App::PropertyLength",
        "UnreachableFromAboveLength",
        "unreachable_from_above_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Of UnreachableLength: the path left out because a vertical tool "
            "cannot reach those places from above (undersides, places under an "
            "overhang; the ball there would be clear, the tool above it would not)",
        ),
    ),
    (
        "App::PropertyString",
        "DirectionUsed",
        None,
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Isocurve direction used, per face",
        ),
    ),
)


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
    # Feeds by the core's move kinds, not FreeCAD's setFeedRate. The two
    # agree on every move that moves; setFeedRate takes a G1 whose end
    # coincides with its start for vertical (VertFeed), and the core's
    # finishing paths have such zero-length G1s (10172 of 65949 on MAT's
    # Face1 at 0.05 mm scallop), which would be posted at the plunge feed.
    FEEDS_BY_SET_FEED_RATE = False

    # -- the op's properties (op_base reads them) ------------------------------

    ENUMERATIONS = {
        "Direction": (
            QT_TRANSLATE_NOOP("IsoCAM", "Auto"),
            QT_TRANSLATE_NOOP("IsoCAM", "U"),
            QT_TRANSLATE_NOOP("IsoCAM", "V"),
        ),
        "Pattern": tuple(QT_TRANSLATE_NOOP("IsoCAM", p) for p in PATTERNS),
        "ScallopBound": tuple(QT_TRANSLATE_NOOP("IsoCAM", b) for b in SCALLOP_BOUNDS),
    }

    def opPropertyDefinitions(self):
        return [
            (
                "App::PropertyLength",
                "ScallopHeight",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Largest scallop height left between adjacent passes; sets the "
                    "stepover. Must be smaller than the ball radius.",
                ),
            ),
            (
                "App::PropertyEnumeration",
                "Pattern",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Adaptive: sub-isocurves only where needed (Elber & Cohen, "
                    "Algorithm 1). Uniform: complete isocurves equally spaced in "
                    "parameter. ParallelPlanes: planes of constant X or Y. All three "
                    "keep the same scallop guarantee (the last two are the "
                    "yardsticks). ConstantScallop: passes that are not isocurves, "
                    "each placed from the one before by the width of the strip it "
                    "machines (Lee 1998); its certificate is measured between the "
                    "passes.",
                ),
            ),
            (
                "App::PropertyEnumeration",
                "ScallopBound",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Curvature: the stepover follows the curvature across the feed, "
                    "so the scallop stays under ScallopHeight on convex ground too "
                    "and widens on concave ground. Flat: the paper's flat-ground "
                    "stepover, never wider, narrowed as Curvature on convex ground. "
                    "Both keep GuaranteedScallop <= ScallopHeight.",
                ),
            ),
            (
                "App::PropertyEnumeration",
                "Direction",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Isocurve direction: U (u constant), V (v constant), or Auto (per "
                    "face, the one with the shorter planned path).",
                ),
            ),
            (
                "App::PropertyBool",
                "ProtectModel",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Keep the ball clear of every face of the model, not only the "
                    "picked ones (each face inside its edges). Where another face "
                    "keeps the ball from a picked one, material is left "
                    "(UnreachableLength says how much). Off: only the picked faces "
                    "are protected.",
                ),
            ),
            (
                "App::PropertyLength",
                "OvercutTolerance",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Deepest cut below the design allowed anywhere (chords on convex "
                    "ground, clearance check, rounding of the posted coordinates); "
                    "GuaranteedOvercut stays within it.",
                ),
            ),
            (
                "App::PropertyLength",
                "ChordTolerance",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Advanced: largest distance between a pass and its linear G1 "
                    "segments. 0 (default): derived from ScallopHeight and "
                    "OvercutTolerance; otherwise it must fit both, and the guarantees "
                    "include it.",
                ),
            ),
            (
                "App::PropertyInteger",
                "PostPrecision",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Decimals of the coordinates the post-processor writes (linuxcnc: "
                    "--precision, default 3); the guarantees include their rounding.",
                ),
            ),
            (
                "App::PropertyLength",
                "AirClearance",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Gap kept between the ball and the model by rapid moves between "
                    "passes, and the height above an entry point from which it is "
                    "fed.",
                ),
            ),
            (
                "App::PropertyFloat",
                "RapidRate",
                "Adaptive Isocurve",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Rapid rate of the machine in mm/min, for MachineTime and "
                    "CycleTime (and the choice between a feed link and a hop).",
                ),
            ),
        ]

    def opPropertyDefaults(self, obj, job):
        return {
            "ScallopHeight": 0.01,
            "Pattern": "Adaptive",
            "ScallopBound": "Curvature",
            "Direction": "Auto",
            "ProtectModel": True,
            "OvercutTolerance": 0.005,
            "ChordTolerance": 0.0,
            "PostPrecision": 3,
            "AirClearance": 1.0,
            "RapidRate": 5000.0,
        }

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
        """Run the core once per model object that has picked faces
        (op_base.run_each_model: a face the core skips is a warning in the
        report view, the other faces are finished)."""
        _check_ball_end(obj)
        picked = _picked_faces(obj)
        params = _iso_params(obj, core, self.radius)

        def run(base, faces):
            return self._run_core(core, base.Shape.exportBrepToString(), faces, params, base)

        results = op_base.run_each_model(core, obj, picked, run, log)
        if not results:
            raise IsoCAMError(
                translate("IsoCAM", "the core returned no moves for the picked faces")
            )
        return results

    def _run_core(self, core, brep, faces, params, base):
        """The core on one model object's faces (op_base.run_core: worker
        thread, progress and cancel); its geometry errors name the model."""

        def call(progress):
            return core.adaptive_isocurve(brep, faces, params, progress)

        try:
            return self.run_core(core, call, translate("IsoCAM", "Adaptive isocurve"))
        except RuntimeError as exc:
            if isinstance(exc, core.CancelledError):
                raise
            raise RuntimeError("%s (model %s)" % (exc, base.Label)) from exc


# -- helpers (module level: small, no FreeCAD object state) -----------------


def _check_ball_end(obj):
    tc = obj.ToolController
    tool = tc.Tool
    if not compat.is_ball_end(tool):
        raise IsoCAMError(
            translate(
                "IsoCAM",
                "tool '%s' of tool controller '%s' is not a ball end (its shape is "
                "'%s'); Adaptive Isocurve needs a ball-end tool (ToolBit shape "
                "ballend.fcstd)",
            )
            % (compat.tool_label(tool), tc.Label, compat.tool_shape(tool) or "unknown")
        )


def _picked_faces(obj):
    """[(model object, [0-based face indices])] from obj.Base, in pick order."""
    picked = picked_faces(obj)
    if not picked:
        raise IsoCAMError(
            translate("IsoCAM", "no faces picked: set Base to one or more faces of the Job's model")
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


def machine_seconds(commands, rapid, feed, plunge, rotary=None):
    """Estimated time (s) of Path commands, no acceleration: G0 at `rapid`,
    G1/G2/G3 at their F word (mm/s, FreeCAD's unit; `feed` / `plunge` in
    mm/min where a move has none and is horizontal / vertical), arcs by
    their chord. With `rotary` (deg/min), a move takes at least |dA| and
    |dC| at that rate (the 5-axis op's A and C words). The first two moves
    (from wherever the machine is, up and across at ClearanceHeight) are not
    counted, as the core does not count its first move."""
    pos = ang = None
    total = 0.0
    moves = 0
    for c in commands:
        p = c.Parameters
        if c.Name not in ("G0", "G00", "G1", "G01", "G2", "G02", "G3", "G03"):
            continue
        moves += 1
        nxt = tuple(p.get(a, pos[i] if pos else 0.0) for i, a in enumerate("XYZ"))
        nxt_ang = tuple(p.get(a, ang[i] if ang else 0.0) for i, a in enumerate("AC"))
        if pos is not None and moves > 2:
            length = math.dist(pos, nxt)
            if c.Name in ("G0", "G00"):
                rate = rapid
            elif p.get("F", 0.0) > 0:
                rate = p["F"] * 60.0
            else:
                rate = plunge if pos[:2] == nxt[:2] else feed
            minutes = length / rate
            if rotary:
                turn = max(abs(nxt_ang[0] - ang[0]), abs(nxt_ang[1] - ang[1]))
                minutes = max(minutes, turn / rotary)
            total += 60.0 * minutes
        pos, ang = nxt, nxt_ang
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
            translate("IsoCAM", "PostPrecision must be 0..9 decimals (got %d)") % obj.PostPrecision
        )
    params.posted_resolution = 10.0**-obj.PostPrecision
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
    op_base.write_outputs(obj, _OUTPUTS, metrics)
    obj.DirectionUsed = directions


def _print_certificate(obj, m, seconds):
    log.info(
        translate(
            "IsoCAM",
            "IsoCAM %s (%s, %s bound): %d sub-isocurves (direction %s), "
            "cutting %.1f mm = %.2f x L* (%.1f mm), rapid %.1f mm, plunge %.1f mm, "
            "%d retracts; iso-distance tolerance %.4f..%.4f mm, max iso-distance "
            "%.4f mm -> guaranteed scallop %.5f mm (requested %.5f mm), "
            "guaranteed overcut %.5f mm (allowed %.5f mm, chords %.5f mm); "
            "machine time %.1f min (cutting %.1f min); unreachable %.1f mm "
            "(from above %.1f mm); %.2f s",
        )
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
        log.warning(
            translate(
                "IsoCAM",
                "%s: the guaranteed scallop height %.5f mm is above the requested %.5f mm "
                "(ScallopBound = %s; the flat bound does not hold on convex ground)",
            )
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
        ObjectAdaptiveIsocurve,
        name,
        obj,
        parentJob,
        toolController,
        translate(
            "IsoCAM",
            "the Job has no ball-end tool controller; add one (ToolBit shape "
            "ballend.fcstd) or pass toolController=",
        ),
    )


compat.PathSetupSheet.RegisterOperation(OP_NAME, Create, SetupProperties)
