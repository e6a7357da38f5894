"""Island-aware spiral pocketing (Suh & Lee) as a FreeCAD Path operation.

Thin operation (ENGINEERING.md, habit 6): ``opExecute`` maps FreeCAD's depth
properties (StartDepth, FinalDepth, StepDown) to z levels, the op's own
properties and its tool controller to ``isocam_core.PocketParams``, runs
``isocam_core.pocket_faces`` on the picked floor faces in a worker thread and
turns the returned flat move arrays (with G2/G3 arcs) into ``Path.Command``s.

Base = the pocket floor face(s). Islands come from the floors' inner wires
and from the model's material standing above each level inside the
outline (as FreeCAD's Pocket Shape does). A planar floor is cleared at every
level down to FinalDepth; a sculptured floor needs a ball-end tool, whose
tip then follows the floor with the ScallopHeight between passes.

Errors (habit 4): a bad input -- no face picked, a parameter out of range
(the core's ``ValueError``), a cancel -- is logged with a message naming the
property or face; the op's Path is emptied, its results cleared, and
:class:`IsoCAMError` is raised out of ``execute`` (FreeCAD marks this op
invalid). Faces the core could not pocket are reported as warnings and the
rest of the work goes on.
"""

import time


from freecad_ext import compat, op_base, pocket_glue
from freecad_ext.compat import QT_TRANSLATE_NOOP, translate
from freecad_ext.op_base import IsoCAMError

log = compat.logger(__name__)

__title__ = "IsoCAM Spiral Pocket operation"

OP_NAME = "SpiralPocket"
DIRECTIONS = pocket_glue.DIRECTIONS

_OUTPUTS = pocket_glue.OUTPUTS


# Core argument names -> what the FreeCAD user sets.
_ARGUMENT_SOURCES = pocket_glue.argument_sources((("scallop_height", "property ScallopHeight"),))


class ObjectSpiralPocket(pocket_glue.PocketOp):
    """Proxy of a Spiral Pocket operation (module-level so documents reopen)."""

    ARGUMENT_SOURCES = _ARGUMENT_SOURCES

    def opPropertyDefinitions(self):
        return [
            (
                "App::PropertyPercent",
                "StepOver",
                "Spiral Pocket",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Path interval on a flat floor, in percent of the tool diameter. "
                    "Where a larger interval would leave material (sharp corners, "
                    "narrow fingers), the core reduces it.",
                ),
            ),
            (
                "App::PropertyLength",
                "ScallopHeight",
                "Spiral Pocket",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Sculptured floor (ball-end tool): largest scallop left between "
                    "passes; sets the path interval from the floor's curvature.",
                ),
            ),
            (
                "App::PropertyLength",
                "Tolerance",
                "Spiral Pocket",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Free curves (ellipses, B-splines) to arcs, and the plan-view and "
                    "floor deviation of the sculptured floor's points.",
                ),
            ),
            (
                "App::PropertyEnumeration",
                "Direction",
                "Spiral Pocket",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Climb: the wall on the right of the cut (spindle M3); "
                    "Conventional: the reverse.",
                ),
            ),
        ]

    def opPropertyDefaults(self, obj, job):
        return {
            "StepOver": 50,
            "ScallopHeight": 0.05,
            "Tolerance": 0.01,
            "Direction": "Climb",
        }

    # -- PathOp hooks -------------------------------------------------------

    def opExecute(self, obj):
        started = time.monotonic()
        results = self.compute_or_fail(obj)
        self.emit_commands(obj, results)
        metrics = _combined(results)
        pocket_glue.write_outputs(obj, _OUTPUTS, metrics)
        _print_summary(obj, metrics, time.monotonic() - started)

    # -- steps of opExecute -------------------------------------------------

    def _compute(self, obj, core):
        picked = pocket_glue.picked_faces(obj)
        if not picked:
            raise IsoCAMError(
                translate(
                    "IsoCAM",
                    "no faces picked: set Base to the pocket floor face(s) of the Job's model",
                )
            )
        levels = pocket_glue.depth_levels(obj)
        tool = obj.ToolController.Tool
        ball_end = compat.is_ball_end(tool)
        params = pocket_glue.pocket_params(
            obj, core, self.radius, obj.Tolerance.Value, obj.ScallopHeight.Value
        )
        results = []
        for base, faces in picked:
            brep = base.Shape.exportBrepToString()

            def call(progress, brep=brep, faces=faces):
                return core.pocket_faces(brep, faces, params, levels, ball_end, progress)

            res = self.run_core(core, call, translate("IsoCAM", "Spiral pocket"))
            for message in res.warnings:
                log.warning("%s: %s: %s" % (obj.Label, base.Label, message))
            if len(res.kind) > 0:
                results.append(res)
        if not results:
            raise IsoCAMError(
                translate(
                    "IsoCAM",
                    "nothing to cut: the picked faces are too small for the tool "
                    "or cannot be pocketed (see the warnings)",
                )
            )
        return results


class _Combined:
    """Metrics of several core runs (one per model object) added up."""

    def __init__(self, results):
        def total(attr):
            return sum(getattr(r.metrics, attr) for r in results)

        for attr in (
            "cutting_length",
            "rapid_length",
            "retracts",
            "feed_links",
            "loops",
            "levels",
            "cl_points",
            "arcs",
        ):
            setattr(self, attr, total(attr))
        self.min_interval = min(r.metrics.min_interval for r in results)
        self.max_interval = max(r.metrics.max_interval for r in results)


def _combined(results):
    return _Combined(results)


def _print_summary(obj, m, seconds):
    log.info(
        translate(
            "IsoCAM",
            "IsoCAM %s: %d loops on %d levels, %d CL points (%d G2/G3), cutting %.1f mm, "
            "rapid %.1f mm, %d retracts, %d feed links, interval %.3f-%.3f mm; %.2f s",
        )
        % (
            obj.Label,
            m.loops,
            m.levels,
            m.cl_points,
            m.arcs,
            m.cutting_length,
            m.rapid_length,
            m.retracts,
            m.feed_links,
            m.min_interval,
            m.max_interval,
            seconds,
        )
    )


def SetupProperties():
    """Properties for which a Job's SetupSheet may hold defaults."""
    return ["StepOver", "ScallopHeight", "Tolerance", "Direction"]


def Create(name=OP_NAME, obj=None, parentJob=None, toolController=None):
    """Create a Spiral Pocket op and add it to `parentJob` (or the only Job).

    `toolController`: use this one instead of letting FreeCAD choose
    (headless FreeCAD cannot choose among several).
    """
    return op_base.create_op(
        ObjectSpiralPocket,
        name,
        obj,
        parentJob,
        toolController,
        translate("IsoCAM", "the Job has no tool controller; add one or pass toolController="),
    )


compat.PathSetupSheet.RegisterOperation(OP_NAME, Create, SetupProperties)
