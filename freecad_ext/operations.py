"""The table of IsoCAM operations the GUI offers, and the input rules they share.

Data-driven (issue 5): a module that exposes ``Create(name, obj=None,
parentJob=None, toolController=None)``, ``SetupProperties()`` and ``OP_NAME``
gets a command, an icon, a task panel, a selection gate and live input checks
by adding one :class:`OperationSpec` row to :data:`OPERATIONS`. A row whose
module is not installed is skipped (:func:`available`).

Per row the GUI looks for, under Resources/:
    icons/<name>.svg     command, tree and panel icon (a generic one if absent)
    panels/<name>.ui     the operation's own task panel page; widgets named
                         like the op's properties are bound to them. Without
                         the file the page is built from SetupProperties().

This module has no GUI dependency: the rules are plain functions of the values
as typed, so the panel and the tests can both call them.
"""

import importlib
import importlib.util
import os
from dataclasses import dataclass

from freecad_ext import compat
from freecad_ext.compat import QT_TRANSLATE_NOOP, translate

# Selection gates (freecad_ext.gui.view_provider): which picks a row accepts.
FACES = "faces"  # any face: finishing follows the surface
FLOOR_FACES = "floor_faces"  # planar faces facing +Z: pocket floors


@dataclass(frozen=True)
class OperationSpec:
    """One operation the GUI offers (see the module docstring)."""

    module: str  # importable module with Create / SetupProperties / OP_NAME
    name: str  # object name, SetupSheet name, icon and .ui file stem
    menu_text: str
    tooltip: str
    selection: str = FACES
    # Input rules, checked as the user types; see RULES below.
    rules: tuple = ()
    # Name of a HINTS entry: a line of information shown while the inputs
    # are valid (e.g. the stepover a scallop height gives).
    hint: str = ""

    @property
    def command(self):
        """FreeCAD command name, e.g. IsoCAM_AdaptiveIsocurve."""
        return "IsoCAM_" + self.name

    def import_module(self):
        return importlib.import_module(self.module)


OPERATIONS = (
    OperationSpec(
        module="freecad_ext.adaptive_isocurve",
        name="AdaptiveIsocurve",
        menu_text=QT_TRANSLATE_NOOP("IsoCAM_AdaptiveIsocurve", "Adaptive Isocurve"),
        tooltip=QT_TRANSLATE_NOOP(
            "IsoCAM_AdaptiveIsocurve",
            "Adaptive isocurve finishing of the picked faces with a ball-end "
            "tool (Elber and Cohen): the scallop height stays below the requested "
            "one everywhere, with fewer and shorter passes than a uniform pattern.",
        ),
        selection=FACES,
        rules=(
            ("faces",),
            ("ball_end",),
            ("positive", "ScallopHeight"),
            ("below_ball_radius", "ScallopHeight"),
            ("not_negative", "ChordTolerance"),
        ),
        hint="ball_stepover",
    ),
    OperationSpec(
        module="freecad_ext.spiral_pocket",
        name="SpiralPocket",
        menu_text=QT_TRANSLATE_NOOP("IsoCAM_SpiralPocket", "Spiral Pocket"),
        tooltip=QT_TRANSLATE_NOOP(
            "IsoCAM_SpiralPocket",
            "Pocket the picked floor faces (flat or sculptured) with an "
            "island-aware spiral path.",
        ),
        # Any face: a sculptured floor is a valid pick; the operation checks.
        selection=FACES,
        rules=(("faces",), ("tool",)),
    ),
    OperationSpec(
        module="freecad_ext.zlevel_roughing",
        name="ZLevelRoughing",
        menu_text=QT_TRANSLATE_NOOP("IsoCAM_ZLevelRoughing", "Z-level Roughing"),
        tooltip=QT_TRANSLATE_NOOP(
            "IsoCAM_ZLevelRoughing",
            "Rough the stock down to the model in constant-Z levels, leaving "
            "StockToLeave for the finish; picked faces (optional) set the final depth.",
        ),
        selection=FLOOR_FACES,
        rules=(("tool",),),
    ),
    OperationSpec(
        module="freecad_ext.five_axis_finish",
        name="FiveAxisStripFinish",
        menu_text=QT_TRANSLATE_NOOP("IsoCAM_FiveAxisStripFinish", "5-Axis Strip Finish"),
        tooltip=QT_TRANSLATE_NOOP(
            "IsoCAM_FiveAxisStripFinish",
            "5-axis finishing of the picked faces with a flat-end or bull-nose tool tilted "
            "by a lead angle (Lee 1998): strips several times wider than a ball's at "
            "the same scallop height; posted with A and C for a table-tilting A/C "
            "machine with tool-centre-point control.",
        ),
        selection=FACES,
        rules=(
            ("faces",),
            ("flat_end",),
            ("positive", "ScallopHeight"),
        ),
    ),
)


def is_installed(spec):
    """True if the row's module can be found (it is not imported)."""
    try:
        return importlib.util.find_spec(spec.module) is not None
    except (ImportError, ValueError):
        return False


def available(table=OPERATIONS):
    """The rows of `table` whose module exists."""
    return tuple(spec for spec in table if is_installed(spec))


def spec_for_proxy(proxy, table=OPERATIONS):
    """The row whose module defines `proxy`'s class, or None."""
    module = type(proxy).__module__
    for spec in table:
        if spec.module == module:
            return spec
    return None


def spec_named(name, table=OPERATIONS):
    for spec in table:
        if spec.name == name:
            return spec
    return None


# -- resources --------------------------------------------------------------

RESOURCES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "Resources")
GENERIC_ICON = os.path.join(RESOURCES, "icons", "IsoCAM.svg")


def icon_path(spec):
    path = os.path.join(RESOURCES, "icons", spec.name + ".svg")
    return path if os.path.isfile(path) else GENERIC_ICON


def panel_path(spec):
    """The row's .ui file, or None when the page is to be generated."""
    path = os.path.join(RESOURCES, "panels", spec.name + ".ui")
    return path if os.path.isfile(path) else None


# -- input rules ------------------------------------------------------------


class Inputs:
    """What the panel shows right now, for the rules.

    values: property name -> value as typed (mm for lengths), None if the
    text does not parse; tool_controller: the chosen one or None; faces:
    the picked (object label, sub-element) pairs.
    """

    def __init__(self, values, tool_controller, faces):
        self.values = values
        self.tool_controller = tool_controller
        self.faces = faces

    @property
    def tool(self):
        tc = self.tool_controller
        return getattr(tc, "Tool", None) if tc is not None else None

    def tool_radius(self):
        tool = self.tool
        try:
            return float(tool.Diameter) / 2.0
        except (AttributeError, TypeError, ValueError):
            return None


def _faces(inputs):
    if not inputs.faces:
        return translate(
            "IsoCAM",
            "No face picked: select faces of the Job's model in the 3D view and "
            "press Add on the Base Geometry page.",
        )
    return None


def _tool(inputs):
    if inputs.tool_controller is None:
        return translate("IsoCAM", "No tool controller: add one to the Job.")
    return None


def _ball_end(inputs):
    missing = _tool(inputs)
    if missing:
        return missing
    tool = inputs.tool
    if not compat.is_ball_end(tool):
        return translate(
            "IsoCAM",
            "Tool controller '%s' holds '%s', a %s tool; this operation needs a "
            "ball-end tool (ToolBit shape ballend.fcstd).",
        ) % (
            inputs.tool_controller.Label,
            compat.tool_label(tool),
            compat.tool_shape(tool) or "unknown",
        )
    return None


def _flat_end(inputs):
    missing = _tool(inputs)
    if missing:
        return missing
    tool = inputs.tool
    if not compat.is_flat_bottomed(tool):
        return (
            "Tool controller '%s' holds '%s', a %s tool; this operation needs a "
            "flat-end or bull-nose tool (ToolBit shape endmill.fcstd or bullnose.fcstd)."
            % (
                inputs.tool_controller.Label,
                compat.tool_label(tool),
                compat.tool_shape(tool) or "unknown",
            )
        )
    return None


def _positive(inputs, prop):
    value = inputs.values.get(prop)
    if value is None:
        return translate("IsoCAM", "%s: not a length.") % prop
    if value <= 0:
        return translate("IsoCAM", "%s must be greater than 0 mm.") % prop
    return None


def _not_negative(inputs, prop):
    value = inputs.values.get(prop)
    if value is None:
        return translate("IsoCAM", "%s: not a length.") % prop
    if value < 0:
        return translate("IsoCAM", "%s must be 0 (derived) or greater.") % prop
    return None


def _below_ball_radius(inputs, prop):
    value, radius = inputs.values.get(prop), inputs.tool_radius()
    if value is None or radius is None or value <= 0:
        return None  # reported by other rules
    if value >= radius:
        return translate(
            "IsoCAM", "%s %g mm must be smaller than the ball radius %g mm of '%s'."
        ) % (
            prop,
            value,
            radius,
            compat.tool_label(inputs.tool),
        )
    return None


RULES = {
    "faces": _faces,
    "tool": _tool,
    "ball_end": _ball_end,
    "flat_end": _flat_end,
    "positive": _positive,
    "not_negative": _not_negative,
    "below_ball_radius": _below_ball_radius,
}


def check(spec, inputs):
    """Messages (reasons) for every rule of `spec` that `inputs` break."""
    messages = []
    for rule in spec.rules:
        message = RULES[rule[0]](inputs, *rule[1:])
        if message and message not in messages:
            messages.append(message)
    return messages


# -- hints ------------------------------------------------------------------


def _ball_stepover(inputs):
    """The flat-ground stepover of the typed scallop height (the core's
    formula, r - sqrt(r^2 - (delta/2)^2) = h)."""
    radius, scallop = inputs.tool_radius(), inputs.values.get("ScallopHeight")
    if radius is None or scallop is None:
        return ""
    delta = compat.import_core().stepover_for_scallop(radius, scallop)
    # The exact value: the field may show it rounded to the decimals of
    # FreeCAD's unit preferences.
    return translate(
        "IsoCAM",
        "Scallop height %g mm: adjacent passes at most %.4g mm apart along "
        "the surface (ball radius %g mm).",
    ) % (scallop, delta, radius)


HINTS = {"ball_stepover": _ball_stepover}


def hint(spec, inputs):
    """The row's hint for valid `inputs`, or ""."""
    function = HINTS.get(spec.hint)
    if function is None:
        return ""
    try:
        return function(inputs)
    except (ImportError, ValueError, RuntimeError):
        return ""
