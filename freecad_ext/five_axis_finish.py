"""5-axis strip finishing with a tilted flat-end or bull-nose tool, as a FreeCAD Path operation.

Thin operation (ENGINEERING.md, habit 6): ``opExecute`` maps the op's
properties and its flat-end or bull-nose tool controller (the bull nose's
corner radius: Diameter / 2 - FlatRadius, as FreeCAD 0.20 and 1.0's
bullnose.fcstd describes it, or 1.1's CornerRadius) to ``isocam_core.FiveAxisParams``,
runs ``isocam_core.five_axis_finish`` on the picked faces in a worker thread
and turns the returned flat arrays (move kind, tip, rotary angles) into
``Path.Command``s with X Y Z A C words. The geometry is the core's
(src/core/include/isocam/five_axis.h, after Y.S. Lee 1998).

The machine convention (also written as a comment at the head of the op's
commands, so it reaches the posted G-code):

* a table-tilting A/C machine with tool-centre-point control (TCP): X Y Z
  are the TOOL TIP, the centre of the flat bottom face (a bull nose's too),
  in the part's (work) frame, and the controller keeps the tip there while the table turns;
* the tool axis relative to the part is (sin A sin C, -sin A cos C, cos A);
* A stays within [AMin, AMax] (default 0..90 degrees); C is unwrapped: each
  move takes the C branch nearest the previous one (no 360 degree unwinds
  between neighbours), and where A is 0 C keeps its previous value.

The tool axis at a contact point is the surface normal tilted by LeadAngle
along the feed (and TiltAngle across it; with LagOnReturn the passes the
zig-zag runs back keep the forward passes' tilt, so the tool lags there);
on concave ground tighter than the bottom allows, the core raises the lead there (up to MaxLeadAngle) so
that the heel does not dig in (rear gouge), and says so in the report view.
Errors follow the other IsoCAM ops: the message names the property or tool,
the op's Path is emptied and the op is marked invalid. A picked face the
core cannot machine is skipped with a warning in the report view naming it,
and the other faces are finished (op_base.run_each_model).
"""

import time

import Path

from freecad_ext import compat, op_base
from freecad_ext.adaptive_isocurve import machine_seconds
from freecad_ext.compat import QT_TRANSLATE_NOOP, translate
from freecad_ext.op_base import IsoCAMError, IsoCAMOp, picked_faces

log = compat.logger(__name__)

__title__ = "IsoCAM 5-Axis Strip Finish operation"

OP_NAME = "FiveAxisStripFinish"

DIRECTIONS = ("Auto", "U", "V")
STRATEGIES = ("StripEvaluation", "NormalIsocurves")
_ENUMERATIONS = {"Direction": DIRECTIONS, "Strategy": STRATEGIES}

# The G-code comment header (no parentheses inside: rs274 does not nest them).
HEADER = (
    "IsoCAM 5-axis strip finish: table-tilting A/C machine with TCP",
    "X Y Z = tool tip = centre of the flat bottom, part frame",
    "tool axis relative to the part = [sin A sin C, -sin A cos C, cos A]",
)

_GROUP = "5-Axis Strip Finish"

# (type, name, tip) of the inputs, all in _GROUP.
_DEFINITIONS = (
    (
        "App::PropertyLength",
        "ScallopHeight",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Largest scallop height left between adjacent passes; sets the strip width.",
        ),
    ),
    (
        "App::PropertyAngle",
        "LeadAngle",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Tilt of the tool axis from the surface normal towards the feed (degrees, > 0). "
            "Smaller: wider strips; the core raises it where concave ground needs more.",
        ),
    ),
    (
        "App::PropertyAngle",
        "TiltAngle",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Tilt of the tool axis across the feed (degrees), e.g. to reach past a wall.",
        ),
    ),
    (
        "App::PropertyAngle",
        "MaxLeadAngle",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "The most the lead may be raised to keep the flat bottom off concave ground.",
        ),
    ),
    (
        "App::PropertyAngle",
        "AMin",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Lowest A of the machine (degrees).",
        ),
    ),
    (
        "App::PropertyAngle",
        "AMax",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Highest A of the machine (degrees).",
        ),
    ),
    (
        "App::PropertyLength",
        "ToolLength",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Length of the tool above the tip kept clear of the model (shank and holder as "
            "a cylinder of the tool's diameter).",
        ),
    ),
    (
        "App::PropertyEnumeration",
        "Strategy",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "StripEvaluation: each pass placed from the one before by the width of the strip "
            "it cuts (Lee 1998); on a face where the adaptive isocurves come out a tenth shorter (the "
            "front folding on rugged ground) they are used, and a warning says so. "
            "NormalIsocurves: adaptive isocurves of the face spaced by "
            "that width, the tool along each oriented by the surface normal there (Elber & "
            "Cohen).",
        ),
    ),
    (
        "App::PropertyEnumeration",
        "Direction",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Start path: V (the face's v = vmin boundary), U (u = umin), or Auto (the "
            "shorter paths per face).",
        ),
    ),
    (
        "App::PropertyBool",
        "ProtectModel",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Keep the shank clear of every face of the model, not only the picked ones.",
        ),
    ),
    (
        "App::PropertyInteger",
        "PostPrecision",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Decimals of the coordinates the post-processor writes (linuxcnc: 3).",
        ),
    ),
    (
        "App::PropertyLength",
        "AirClearance",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Approach and retract distance along the tool axis.",
        ),
    ),
    (
        "App::PropertyFloat",
        "RapidRate",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Rapid rate in mm/min for MachineTime.",
        ),
    ),
    (
        "App::PropertyFloat",
        "RotaryRate",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Speed of the A and C axes in deg/min for MachineTime (and the choice of links).",
        ),
    ),
    (
        "App::PropertyBool",
        "LowLinks",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Link consecutive passes low, along a rapid proven clear of the model, where "
            "quicker than through SafeHeight. Needs G0 moved straight with A and C linear "
            "under TCP; turn off for machines that do not.",
        ),
    ),
    (
        "App::PropertyBool",
        "LagOnReturn",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "The passes run back keep the tilt of the passes run forward (the tool lags, "
            "tilted against the feed by the lead), so C does not turn half a turn between "
            "passes where the axis is near vertical. Off: the tool leads along every pass.",
        ),
    ),
)

_DEFAULTS = {
    "ScallopHeight": 0.01,
    "LeadAngle": 5.0,
    "TiltAngle": 0.0,
    "MaxLeadAngle": 45.0,
    "AMin": 0.0,
    "AMax": 90.0,
    "ToolLength": 30.0,
    "Strategy": "StripEvaluation",
    "Direction": "Auto",
    "ProtectModel": True,
    "PostPrecision": 3,
    "AirClearance": 1.0,
    "RapidRate": 5000.0,
    "RotaryRate": 3600.0,
    "LowLinks": True,
    "LagOnReturn": False,
}

_OUTPUTS = (
    (
        "App::PropertyLength",
        "CuttingLength",
        "cutting_length",
        QT_TRANSLATE_NOOP("App::Property", "Length of the feed moves (tip)"),
    ),
    (
        "App::PropertyLength",
        "RapidLength",
        "rapid_length",
        QT_TRANSLATE_NOOP("App::Property", "Length of the rapid moves (tip)"),
    ),
    (
        "App::PropertyInteger",
        "Passes",
        "paths",
        QT_TRANSLATE_NOOP("App::Property", "Number of paths traced"),
    ),
    (
        "App::PropertyLength",
        "StripWidth",
        "flat_strip_width",
        QT_TRANSLATE_NOOP("App::Property", "Strip width on flat ground at LeadAngle (2 x_h)"),
    ),
    (
        "App::PropertyLength",
        "MaxSpacing",
        "max_spacing",
        QT_TRANSLATE_NOOP("App::Property", "Largest measured distance between adjacent paths"),
    ),
    (
        "App::PropertyLength",
        "GuaranteedScallop",
        "guaranteed_scallop",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Measured cusp between adjacent paths plus the positions' error (<= ScallopHeight)",
        ),
    ),
    (
        "App::PropertyLength",
        "GuaranteedOvercut",
        "guaranteed_overcut",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Deepest cut below the picked faces: chord + posted rounding + axis step + gouge check",
        ),
    ),
    (
        "App::PropertyLength",
        "UnreachableLength",
        "unreachable_length",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Path left out: gouge even at MaxLeadAngle, shank against the model, A out of range",
        ),
    ),
    (
        "App::PropertyInteger",
        "UnconvergedMoves",
        "unconverged_moves",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Moves where the pose still jumps after 12 halvings (the lead raised on one side): "
            "the swing there is checked instead",
        ),
    ),
    (
        "App::PropertyInteger",
        "SwingsSplit",
        "swings_split",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Of UnconvergedMoves: swings that would gouge or hit the model; the path is split there",
        ),
    ),
    (
        "App::PropertyInteger",
        "IsocurveFaces",
        "isocurve_faces",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "StripEvaluation: faces finished with the adaptive isocurves instead of the march "
            "(shorter by over a tenth, or the march's paths left a gap or exceeded the scallop "
            "height; the report view names them)",
        ),
    ),
    (
        "App::PropertyFloat",
        "MaxLeadUsed",
        "max_lead_used",
        QT_TRANSLATE_NOOP("App::Property", "Largest lead angle used (degrees)"),
    ),
    (
        "App::PropertyFloat",
        "RotaryTravelA",
        "rotary_travel_a",
        QT_TRANSLATE_NOOP("App::Property", "Sum of |dA| over all moves (degrees)"),
    ),
    (
        "App::PropertyFloat",
        "RotaryTravelC",
        "rotary_travel_c",
        QT_TRANSLATE_NOOP("App::Property", "Sum of |dC| over all moves (degrees)"),
    ),
    (
        "App::PropertyFloat",
        "MachineTime",
        "machine_time",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Estimated time (s): each move at its feed or RapidRate, and at least its A and C "
            "turns at RotaryRate",
        ),
    ),
)

_ARGUMENT_SOURCES = (
    ("scallop_height", "property ScallopHeight"),
    ("lead_angle", "property LeadAngle"),
    ("max_lead_angle", "property MaxLeadAngle"),
    ("tilt_angle", "property TiltAngle"),
    ("a_min", "property AMin"),
    ("a_max", "property AMax"),
    ("tool_length", "property ToolLength"),
    ("tool_radius", "the tool controller's tool diameter / 2"),
    (
        "corner_radius",
        "the tool controller's bull nose: its CornerRadius (FreeCAD 1.1), "
        "or Diameter / 2 - FlatRadius (0.20, 1.0)",
    ),
    ("air_clearance", "property AirClearance"),
    ("rapid_rate", "property RapidRate"),
    ("rotary_rate", "property RotaryRate"),
    ("posted_resolution", "property PostPrecision"),
    ("safe_z", "property SafeHeight"),
)


def is_flat_end(tool):
    """True if FreeCAD describes `tool` as a flat end mill."""
    return compat.is_flat_end(tool)


def is_flat_bottomed(tool):
    """True if the op can use `tool`: a flat end or a bull nose."""
    return compat.is_flat_bottomed(tool)


class ObjectFiveAxisStripFinish(IsoCAMOp):
    """Proxy of a 5-Axis Strip Finish operation (module-level so documents reopen)."""

    OUTPUTS = _OUTPUTS
    ARGUMENT_SOURCES = _ARGUMENT_SOURCES
    ENUMERATIONS = _ENUMERATIONS

    def opPropertyDefinitions(self):
        return [(prop_type, name, _GROUP, tip) for prop_type, name, tip in _DEFINITIONS]

    def opPropertyDefaults(self, obj, job):
        return dict(_DEFAULTS)

    def accepts_tool(self, tool):
        return is_flat_bottomed(tool)

    def opExecute(self, obj):
        started = time.monotonic()
        results = self.compute_or_fail(obj)
        clearance = obj.ClearanceHeight.Value
        op_base.check_moves(self, obj, results, clearance)
        for line in HEADER:
            self.commandlist.append(Path.Command("(%s)" % line))
        self.commandlist.append(
            Path.Command("(A range %g..%g deg, C unwrapped)" % (obj.AMin.Value, obj.AMax.Value))
        )
        first = results[0]
        a0, c0 = (float(v) for v in first.ac[0])
        x0, y0 = (float(v) for v in first.xyz[0][:2])
        self.commandlist.append(Path.Command("G0", {"Z": clearance}))
        self.commandlist.append(
            Path.Command("G0", {"X": x0, "Y": y0, "Z": clearance, "A": a0, "C": c0})
        )
        for res in results:
            self.commandlist.extend(commands_from_moves(res, self.horizFeed, self.vertFeed))
        metrics = _combined(results)
        final = [Path.Command("G0", {"Z": clearance})]
        metrics["machine_time"] = machine_seconds(
            self.commandlist + final,
            float(obj.RapidRate),
            *_feeds(obj),
            rotary=float(obj.RotaryRate)
        )
        op_base.write_outputs(obj, _OUTPUTS, metrics)
        log.info(
            "IsoCAM %s (%s): %d paths, strip %.3f mm on flat ground, cutting %.1f mm, "
            "rapid %.1f mm, "
            "guaranteed scallop %.5f mm (requested %.5f), guaranteed overcut %.5f mm, "
            "lead up to %.1f deg, rotary travel A %.0f deg C %.0f deg, unreachable %.1f mm, "
            "machine time %.1f min; %.2f s\n"
            % (
                obj.Label,
                obj.Strategy,
                metrics["paths"],
                metrics["flat_strip_width"],
                metrics["cutting_length"],
                metrics["rapid_length"],
                metrics["guaranteed_scallop"],
                obj.ScallopHeight.Value,
                metrics["guaranteed_overcut"],
                metrics["max_lead_used"],
                metrics["rotary_travel_a"],
                metrics["rotary_travel_c"],
                metrics["unreachable_length"],
                metrics["machine_time"] / 60.0,
                time.monotonic() - started,
            )
        )

    def _compute(self, obj, core):
        tc = obj.ToolController
        tool = tc.Tool
        if not is_flat_bottomed(tool):
            raise IsoCAMError(
                "tool '%s' of tool controller '%s' is not a flat end mill or bull nose (its shape "
                "is '%s'); 5-Axis Strip Finish needs a flat-end or bull-nose tool (ToolBit shape "
                "endmill.fcstd or bullnose.fcstd)%s"
                % (
                    compat.tool_label(tool),
                    tc.Label,
                    compat.tool_shape(tool) or "unknown",
                    "; a ball end has no flat bottom to tilt: use Adaptive Isocurve for it"
                    if compat.is_ball_end(tool)
                    else "",
                )
            )
        picked = picked_faces(obj)
        if not picked:
            raise IsoCAMError("no faces picked: set Base to one or more faces of the Job's model")
        params = _params(obj, core, float(tool.Diameter) / 2.0, _corner_radius(tool, tc))

        def run(base, faces):
            return self._run_core(core, base.Shape.exportBrepToString(), faces, params, base)

        # A face the core skips is a warning in the report view, the other
        # faces are finished (op_base.run_each_model).
        results = op_base.run_each_model(core, obj, picked, run, log)
        if not results:
            raise IsoCAMError("the core returned no moves for the picked faces")
        return results

    def _run_core(self, core, brep, faces, params, base):
        def call(progress):
            return core.five_axis_finish(brep, faces, params, progress)

        try:
            return self.run_core(core, call, translate("IsoCAM", "5-axis strip finish"))
        except core.CancelledError:
            raise
        except RuntimeError as exc:
            raise RuntimeError("%s (model %s)" % (exc, base.Label)) from exc


def _feeds(obj):
    tc = obj.ToolController
    h = tc.HorizFeed.Value * 60.0 if tc is not None else 0.0
    v = tc.VertFeed.Value * 60.0 if tc is not None else 0.0
    return (h if h > 0 else 1200.0, v if v > 0 else 400.0)


def _corner_radius(tool, tc):
    """The bull nose's corner radius (0 for a flat end); the core checks
    0 <= rc < R and names corner_radius (ARGUMENT_SOURCES: CornerRadius or
    FlatRadius)."""
    corner = compat.corner_radius(tool)
    if corner is None:
        raise IsoCAMError(
            "bull-nose tool '%s' of tool controller '%s' has no FlatRadius (nor CornerRadius): "
            "its corner radius is unknown" % (compat.tool_label(tool), tc.Label)
        )
    return corner


def _params(obj, core, radius, corner=0.0):
    p = core.FiveAxisParams()
    p.tool_radius = radius
    p.corner_radius = corner
    p.scallop_height = obj.ScallopHeight.Value
    p.lead_angle = obj.LeadAngle.Value
    p.tilt_angle = obj.TiltAngle.Value
    p.max_lead_angle = obj.MaxLeadAngle.Value
    p.a_min = obj.AMin.Value
    p.a_max = obj.AMax.Value
    p.tool_length = obj.ToolLength.Value
    p.direction = getattr(core.IsoDirection, obj.Direction)
    p.strategy = getattr(core.FiveAxisStrategy, obj.Strategy)
    p.protect_unpicked_faces = bool(obj.ProtectModel)
    if not 0 <= obj.PostPrecision <= 9:
        raise IsoCAMError("PostPrecision must be 0..9 decimals (got %d)" % obj.PostPrecision)
    p.posted_resolution = 10.0**-obj.PostPrecision
    p.air_clearance = obj.AirClearance.Value
    p.feed_rate, p.plunge_rate = _feeds(obj)
    p.rapid_rate = float(obj.RapidRate)
    p.rotary_rate = float(obj.RotaryRate)
    p.low_links = bool(obj.LowLinks)
    p.lag_on_return = bool(obj.LagOnReturn)
    p.safe_z = obj.SafeHeight.Value
    p.max_moves = op_base.max_moves(obj)
    return p


def _combined(results):
    out = {}
    for attr in (
        "cutting_length",
        "rapid_length",
        "machine_time",
        "unreachable_length",
        "rotary_travel_a",
        "rotary_travel_c",
    ):
        out[attr] = sum(getattr(r.metrics, attr) for r in results)
    for attr in ("paths", "unconverged_moves", "swings_split", "isocurve_faces"):
        out[attr] = sum(int(getattr(r.metrics, attr)) for r in results)
    for attr in (
        "flat_strip_width",
        "max_spacing",
        "guaranteed_scallop",
        "guaranteed_overcut",
        "max_lead_used",
    ):
        out[attr] = max(getattr(r.metrics, attr) for r in results)
    return out


def commands_from_moves(res, horiz_feed, vert_feed):
    """Path.Commands with X Y Z A C for the core's arrays: rapid -> G0, feed
    -> G1 at `horiz_feed`, plunge (the fed entry along the axis) -> G1 at
    `vert_feed` (FreeCAD's units: mm, degrees, mm/s)."""
    commands = []
    for k, (x, y, z), (a, c) in zip(res.kind.tolist(), res.xyz.tolist(), res.ac.tolist()):
        words = {"X": x, "Y": y, "Z": z, "A": a, "C": c}
        if k == op_base.MOVE_RAPID:
            commands.append(Path.Command("G0", words))
        elif k in (op_base.MOVE_FEED, op_base.MOVE_PLUNGE):
            words["F"] = horiz_feed if k == op_base.MOVE_FEED else vert_feed
            commands.append(Path.Command("G1", words))
        else:
            raise IsoCAMError("the core returned an unknown move kind %d" % k)
    return commands


def SetupProperties():
    return [
        "ScallopHeight",
        "LeadAngle",
        "TiltAngle",
        "MaxLeadAngle",
        "AMin",
        "AMax",
        "ToolLength",
        "Strategy",
        "Direction",
        "AirClearance",
        "RapidRate",
        "RotaryRate",
        "LowLinks",
        "LagOnReturn",
    ]


def Create(name=OP_NAME, obj=None, parentJob=None, toolController=None):
    """Create a 5-Axis Strip Finish op and add it to `parentJob` (or the only Job).

    `toolController`: a flat-end or bull-nose tool controller to use (headless FreeCAD
    cannot choose among several)."""
    return op_base.create_op(
        ObjectFiveAxisStripFinish,
        name,
        obj,
        parentJob,
        toolController,
        "the Job has no flat-end or bull-nose tool controller; add one (ToolBit shape "
        "endmill.fcstd or bullnose.fcstd) or pass toolController=",
    )


compat.PathSetupSheet.RegisterOperation(OP_NAME, Create, SetupProperties)
