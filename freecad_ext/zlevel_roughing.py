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

import Part

from freecad_ext import compat, op_base, pocket_glue
from freecad_ext.compat import QT_TRANSLATE_NOOP, translate
from freecad_ext.op_base import IsoCAMError

log = compat.logger(__name__)

__title__ = "IsoCAM Z-level Roughing operation"

OP_NAME = "ZLevelRoughing"
DIRECTIONS = pocket_glue.DIRECTIONS

_OUTPUTS = pocket_glue.OUTPUTS


_ARGUMENT_SOURCES = pocket_glue.argument_sources((("stock_to_leave", "property StockToLeave"),))


class ObjectZLevelRoughing(pocket_glue.PocketOp):
    """Proxy of a Z-level Roughing operation."""

    ARGUMENT_SOURCES = _ARGUMENT_SOURCES

    def opPropertyDefinitions(self):
        return [
            (
                "App::PropertyPercent",
                "StepOver",
                "Z-level Roughing",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Path interval in percent of the tool diameter (reduced by the "
                    "core where a larger one would leave material).",
                ),
            ),
            (
                "App::PropertyLength",
                "StockToLeave",
                "Z-level Roughing",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Material left on the model, on its sides and on its floors, for "
                    "the finishing pass.",
                ),
            ),
            (
                "App::PropertyLength",
                "Tolerance",
                "Z-level Roughing",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Section curves (B-splines) to arcs.",
                ),
            ),
            (
                "App::PropertyEnumeration",
                "Direction",
                "Z-level Roughing",
                QT_TRANSLATE_NOOP(
                    "App::Property",
                    "Climb: the material on the right of the cut (spindle M3); "
                    "Conventional: the reverse.",
                ),
            ),
        ]

    def opPropertyDefaults(self, obj, job):
        return {
            "StepOver": 50,
            "StockToLeave": 0.5,
            "Tolerance": 0.01,
            "Direction": "Climb",
        }

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
        log.info(
            translate(
                "IsoCAM",
                "IsoCAM %s: %d loops on %d levels, cutting %.1f mm, rapid %.1f mm, "
                "%d retracts, %d feed links; %.2f s",
            )
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
            raise IsoCAMError(translate("IsoCAM", "the Job has no model"))
        model = models[0] if len(models) == 1 else Part.makeCompound(models)
        stock = self.stock.Shape if self.stock is not None else None
        if stock is None or stock.isNull():
            raise IsoCAMError(translate("IsoCAM", "the Job has no stock"))
        params = pocket_glue.pocket_params(obj, core, self.radius, obj.Tolerance.Value)
        model_brep, stock_brep = model.exportBrepToString(), stock.exportBrepToString()
        stl = obj.StockToLeave.Value

        def call(progress):
            return core.zlevel_roughing(model_brep, stock_brep, params, levels, stl, progress)

        res = self.run_core(core, call, translate("IsoCAM", "Z-level roughing"))
        for message in res.warnings:
            log.warning("%s: %s" % (obj.Label, message))
        if len(res.kind) == 0:
            raise IsoCAMError(
                translate(
                    "IsoCAM",
                    "nothing to cut between StartDepth and FinalDepth (is the stock "
                    "above the model, and the tool small enough?)",
                )
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
        translate("IsoCAM", "the Job has no tool controller; add one or pass toolController="),
    )


compat.PathSetupSheet.RegisterOperation(OP_NAME, Create, SetupProperties)
