"""Z-level roughing as a FreeCAD Path operation (Elber & Cohen section 4,
Figure 4; the 2D stage is Suh & Lee's spiral pocketing).

Thin operation: at every level of StartDepth / FinalDepth / StepDown the
core clears the region between the Job's stock outline and the slice of the
model's manufacturing offset (the model's material at and above the level
grown by the tool radius plus StockToLeave), with the same spiral pocketing
engine as the Spiral Pocket op. What is left for the finishing pass (e.g.
Adaptive Isocurve) is a layer of about StockToLeave, plus the steps between
levels.

Base is optional: without it the whole model is roughed down to the model's
lowest point; with floor faces picked, FreeCAD's FinalDepth follows them
(roughing stops at the picked floor), the region is still the stock against
the whole model.
"""

import time

import FreeCAD
import Part

from freecad_ext import compat, op_base, pocket_glue
from freecad_ext.compat import PathLog
from freecad_ext.op_base import IsoCAMError

__title__ = "IsoCAM Z-level Roughing operation"

OP_NAME = "ZLevelRoughing"
DIRECTIONS = pocket_glue.DIRECTIONS

_INPUTS = (
    (
        "App::PropertyPercent",
        "StepOver",
        "Z-level Roughing",
        "Path interval in percent of the tool diameter (reduced by the core "
        "where a larger one would leave material).",
        50,
    ),
    (
        "App::PropertyLength",
        "StockToLeave",
        "Z-level Roughing",
        "Material left on the model, on its sides and on its floors, for the "
        "finishing pass.",
        0.5,
    ),
    (
        "App::PropertyLength",
        "Tolerance",
        "Z-level Roughing",
        "Section curves (B-splines) to arcs.",
        0.01,
    ),
    (
        "App::PropertyEnumeration",
        "Direction",
        "Z-level Roughing",
        "Climb: the material on the right of the cut (spindle M3); Conventional: the reverse.",
        "Climb",
        DIRECTIONS,
    ),
)
_OUTPUTS = pocket_glue.OUTPUTS


_ARGUMENT_SOURCES = pocket_glue.argument_sources(
    (("stock_to_leave", "property StockToLeave"),)
)


class ObjectZLevelRoughing(pocket_glue.PocketOp):
    """Proxy of a Z-level Roughing operation."""

    ARGUMENT_SOURCES = _ARGUMENT_SOURCES

    INPUTS = _INPUTS

    def opUpdateDepths(self, obj):
        # Without Base FreeCAD takes the model's top as the final depth (for
        # facing); roughing goes down to the model's lowest point.
        if not obj.Base:
            job = compat.PathUtils.findParentJob(obj)
            if job is not None and job.Model.Group:
                zmin = min(m.Shape.BoundBox.ZMin for m in job.Model.Group)
                if abs(obj.OpFinalDepth.Value - zmin) > 1e-9:
                    obj.OpFinalDepth = zmin

    def opExecute(self, obj):
        started = time.monotonic()
        res = self.compute_or_fail(obj)
        self.emit_commands(obj, [res])
        pocket_glue.write_outputs(obj, _OUTPUTS, res.metrics)
        m = res.metrics
        FreeCAD.Console.PrintMessage(
            "IsoCAM %s: %d loops on %d levels, cutting %.1f mm, rapid %.1f mm, "
            "%d retracts, %d feed links; %.2f s\n"
            % (
                obj.Label,
                m.loops,
                m.levels,
                m.cutting_length,
                m.rapid_length,
                m.retracts,
                m.feed_links,
                time.monotonic() - started,
            )
        )

    def _compute(self, obj, core):
        levels = pocket_glue.depth_levels(obj)
        models = [m.Shape for m in self.model]
        if not models:
            raise IsoCAMError("the Job has no model")
        model = models[0] if len(models) == 1 else Part.makeCompound(models)
        stock = self.stock.Shape if self.stock is not None else None
        if stock is None or stock.isNull():
            raise IsoCAMError("the Job has no stock")
        params = pocket_glue.pocket_params(obj, core, self.radius, obj.Tolerance.Value)
        model_brep, stock_brep = model.exportBrepToString(), stock.exportBrepToString()
        stl = obj.StockToLeave.Value

        def call(progress):
            return core.zlevel_roughing(
                model_brep, stock_brep, params, levels, stl, progress
            )

        res = pocket_glue.run_core(self, core, call, "zlevel-roughing")
        for message in res.metrics.messages:
            PathLog.warning("%s: %s" % (obj.Label, message))
        if len(res.kind) == 0:
            raise IsoCAMError(
                "nothing to cut between StartDepth and FinalDepth (is the stock "
                "above the model, and the tool small enough?)"
            )
        return res


def SetupProperties():
    return ["StepOver", "StockToLeave", "Tolerance", "Direction"]


def Create(name=OP_NAME, obj=None, parentJob=None, toolController=None):
    """Create a Z-level Roughing op and add it to `parentJob` (or the only Job)."""
    return op_base.create_op(
        ObjectZLevelRoughing,
        name,
        obj,
        parentJob,
        toolController,
        "the Job has no tool controller; add one or pass toolController=",
    )


compat.PathSetupSheet.RegisterOperation(OP_NAME, Create, SetupProperties)
