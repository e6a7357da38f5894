"""What every IsoCAM Path operation shares: the op base class, which adds
the op's properties from its definitions (FreeCAD's convention), runs the
core with progress and cancel, maps its errors to the user's inputs and turns
its flat move arrays into ``Path.Command``s.

A subclass gives its properties as data, as FreeCAD's own ops (Surface,
Waterline, Slot) do, and the base reads them:

* ``opPropertyDefinitions()``: (type, name, group, tip) rows, every tip in
  ``QT_TRANSLATE_NOOP("App::Property", ...)``;
* ``ENUMERATIONS``: property -> its values; ``propertyEnumerations(dataType)``
  gives them as FreeCAD's ops do ("data", "raw", "translated");
* ``opPropertyDefaults(obj, job)``: property -> default of a new op (and of a
  property an older document lacks);
* ``OUTPUTS``: (type, name, core metrics attribute, tip) rows of the read-only
  outputs, all in :data:`OUTPUT_GROUP` (the task panel lists them);
* ``ARGUMENT_SOURCES``: (core argument, FreeCAD input) pairs, to say which
  input an error of the core is about.

FreeCAD offers (and, headless, picks) tool controllers through
``isToolSupported``. While Create() is given an explicit controller, only that
one qualifies, which avoids FreeCAD's GUI-only choice among several (the
headless pitfall with two or more tool controllers).
"""

import math
import threading

import FreeCAD
import Path

from freecad_ext import compat
from freecad_ext.compat import QT_TRANSLATE_NOOP, PathOp, translate

log = compat.logger(__name__)

# The read-only outputs of every op, in one group (the task panel shows it).
OUTPUT_GROUP = "Certificate"

# Move kinds of the core's flat toolpath arrays, as its module binds them:
# op_base.MOVE_FEED is isocam_core.FEED (read on first use, so importing the
# glue does not need the compiled core).
_MOVE_KINDS = {
    "MOVE_RAPID": "RAPID",
    "MOVE_FEED": "FEED",
    "MOVE_PLUNGE": "PLUNGE",
    "MOVE_ARC_CW": "ARC_CW",
    "MOVE_ARC_CCW": "ARC_CCW",
    "MOVE_RAMP": "RAMP",
}


def __getattr__(name):
    if name in _MOVE_KINDS:
        return getattr(compat.import_core(), _MOVE_KINDS[name])
    if name == "PathLog":  # the name ops written before the module loggers use
        return compat.PathLog
    raise AttributeError("module %r has no attribute %r" % (__name__, name))


class IsoCAMError(Exception):
    """An input the operation cannot be computed with; the message names it."""


def picked_faces(obj, what=None):
    """[(model object, [0-based face indices])] from obj.Base, in pick order.

    Raises IsoCAMError for a picked sub-element that is not a face; `what`
    names what the user should pick instead (default: faces).
    """
    what = what or translate("IsoCAM", "faces")
    picked = []
    for base, subs in obj.Base or []:
        indices = []
        for sub in subs:
            if not sub.startswith("Face") or not sub[4:].isdigit():
                raise IsoCAMError(
                    translate("IsoCAM", "Base %s.%s is not a face; pick %s of the Job's model")
                    % (base.Label, sub, what)
                )
            index = int(sub[4:]) - 1
            count = len(base.Shape.Faces)
            if not 0 <= index < count:
                raise IsoCAMError(
                    translate(
                        "IsoCAM", "Base %s.%s does not exist: %s has %d face%s (Face1..Face%d)"
                    )
                    % (base.Label, sub, base.Label, count, "" if count == 1 else "s", count)
                )
            if index not in indices:
                indices.append(index)
        if indices:
            picked.append((base, indices))
    return picked


def run_each_model(core, obj, picked, run, oplog):
    """``run(base, faces)`` -- the core on one model object's picked faces --
    for each of `picked`; the results that have moves.

    Habit 4, as Spiral Pocket reports its faces: the core skips a picked
    face whose geometry defeats it and says so in the result's warnings,
    which go to the report view (through the op's log `oplog`) naming the op
    and the model. A model on which every picked face fails (the core's
    RuntimeError) is such a warning too while another model is left; only
    when every model fails is it raised. A cancel is raised at once.
    """
    results, failed = [], []
    for base, faces in picked:
        try:
            res = run(base, faces)
        except RuntimeError as exc:
            if isinstance(exc, core.CancelledError) or len(picked) == 1:
                raise
            failed.append(exc)
            oplog.warning("%s: %s" % (obj.Label, exc))
            continue
        for warning in res.warnings:
            oplog.warning("%s: %s: %s" % (obj.Label, base.Label, warning))
        if len(res.kind) > 0:
            results.append(res)
    if failed and len(failed) == len(picked):
        raise RuntimeError("; ".join(str(exc) for exc in failed))
    return results


# The work budget (src/core isocam/work_budget.h: kDefaultMaxMoves).
DEFAULT_MAX_MOVES = 1000000

# The property every IsoCAM op has, whatever its own definitions.
_COMMON_DEFINITIONS = (
    (
        "App::PropertyInteger",
        "MaxMoves",
        "Work budget",
        QT_TRANSLATE_NOOP(
            "App::Property",
            "Largest number of moves the operation may compute. A job whose "
            "estimate (from the faces' area, the stepover and the tolerances) "
            "is larger is refused before the work; raise it for a larger job.",
        ),
    ),
)
_COMMON_DEFAULTS = {"MaxMoves": DEFAULT_MAX_MOVES}


class IsoCAMOp(PathOp.ObjectOp):
    """Base of our operation proxies (each lives in an importable module, so
    saved documents reopen). Subclasses give their properties as data (see
    the module docstring), say which tools they accept and compute in
    _compute(obj, core)."""

    OUTPUTS = ()
    ARGUMENT_SOURCES = ()
    ENUMERATIONS = {}
    # True: feed rates by FreeCAD's setFeedRate helper (HorizFeed, VertFeed
    # for vertical moves, the tool controller's rapid rates on G0), as
    # FreeCAD's Helix and Drilling ops. False: by the core's move kinds
    # (plunge at VertFeed, the rest at HorizFeed) in commands_from_moves.
    FEEDS_BY_SET_FEED_RATE = False

    def __init__(self, obj, name, parentJob=None, toolController=None):
        # Read by isToolSupported/opSetDefaultValues while the base class
        # picks the tool controller; not saved with the document.
        self._requested_tc = toolController
        self.active_progress = None
        super().__init__(obj, name, parentJob)
        self._requested_tc = None

    # -- the op's properties as data ------------------------------------------

    def opPropertyDefinitions(self):
        """(type, name, group, tip) of the op's own properties."""
        return []

    def opPropertyDefaults(self, obj, job):
        """Property -> default value of a new op (`job` may be None)."""
        return {}

    @classmethod
    def propertyEnumerations(cls, dataType="data"):
        """The values of the op's enumeration properties, as FreeCAD's ops
        give them: "data" [(property, [value])], "raw" {property:
        [(translated, value)]}, "translated" [(property, [translated])]."""
        raw = {
            prop: [(translate("IsoCAM", value), value) for value in values]
            for prop, values in cls.ENUMERATIONS.items()
        }
        if dataType == "raw":
            return raw
        index = 0 if dataType == "translated" else 1
        return [(prop, [pair[index] for pair in pairs]) for prop, pairs in raw.items()]

    def init_properties(self, obj):
        """Add the properties `obj` does not have yet, set the enumerations
        (keeping a value that is still offered) and mark the outputs
        read-only, in OUTPUT_GROUP. Returns the names of the added ones.

        `obj` may be a SetupSheet OpPrototype: addProperty, setEditorMode
        and attribute assignment are all it supports.
        """
        added = []
        for prop_type, name, group, tip in (
            tuple(self.opPropertyDefinitions()) + _COMMON_DEFINITIONS
        ):
            if not hasattr(obj, name):
                obj.addProperty(prop_type, name, group, tip)
                added.append(name)
        for name, values in self.propertyEnumerations():
            # (A SetupSheet prototype answers no hasattr(): its properties
            # are the ones just added.)
            if name not in added and not hasattr(obj, name):
                continue
            previous = getattr(obj, name) if name not in added else None
            setattr(obj, name, list(values))
            if previous in values:
                setattr(obj, name, previous)
        for prop_type, name, _attr, tip in self.OUTPUTS:
            if not hasattr(obj, name):
                obj.addProperty(prop_type, name, OUTPUT_GROUP, tip)
            elif (
                hasattr(obj, "setGroupOfProperty") and obj.getGroupOfProperty(name) != OUTPUT_GROUP
            ):
                # Before issue 14 the pocketing ops kept them in "Result".
                obj.setGroupOfProperty(name, OUTPUT_GROUP)
            obj.setEditorMode(name, 1)  # read-only in the property editor
            if hasattr(obj, "setPropertyStatus"):  # not on a SetupSheet prototype
                # Output: writing it during execute does not touch the op again.
                obj.setPropertyStatus(name, ["ReadOnly", "Output"])
        return added

    def apply_defaults(self, obj, job, names):
        """Set the defaults of the properties `names` (FreeCAD's
        opApplyPropertyDefaults)."""
        defaults = dict(_COMMON_DEFAULTS)
        defaults.update(self.opPropertyDefaults(obj, job))
        for name in names:
            if name in defaults:
                setattr(obj, name, defaults[name])

    # -- PathOp hooks -----------------------------------------------------------

    def opFeatures(self, obj):
        """FreeCAD's op features of a surface operation (finishing): tool,
        heights, picked faces, coolant. No FeatureDepths: the passes follow
        the surface, depths do not apply (the pocketing ops add them)."""
        return (
            PathOp.FeatureTool
            | PathOp.FeatureHeights
            | PathOp.FeatureBaseFaces
            | PathOp.FeatureCoolant
        )

    def accepts_tool(self, tool):
        """True if the operation can use `tool` (any tool by default)."""
        return True

    def add_properties(self, obj):
        """Add what `obj` lacks and give the added ones their defaults."""
        self.apply_defaults(obj, None, self.init_properties(obj))

    def initOperation(self, obj):
        # Defaults here, not in opSetDefaultValues: a SetupSheet prototype
        # gets no opSetDefaultValues and shows these in the sheet's editor.
        self.add_properties(obj)
        add_budget_property(obj)  # for an add_properties() of a subclass

    def opOnDocumentRestored(self, obj):
        # Files written by older versions may lack newer properties (they
        # get their defaults); enumerations and editor modes are not saved.
        self.add_properties(obj)
        add_budget_property(obj)

    def sanitizeBase(self, obj):
        # FreeCAD's version empties Base when a picked face no longer exists
        # ("stale base geometry"), after which the op only says that no face
        # is picked. Keep the user's Base: picked_faces() names the face.
        return False

    def updateDepths(self, obj, ignoreErrors=False):
        # FreeCAD 1.x reads every Base element here, before opExecute: a
        # missing face would fail with "Shape index 999 out of bound 8".
        # Name it first, as opExecute would.
        try:
            picked_faces(obj)
        except IsoCAMError as exc:
            self.fail(obj, str(exc))
        return super().updateDepths(obj, ignoreErrors)

    def isToolSupported(self, obj, tool):
        requested = getattr(self, "_requested_tc", None)
        if requested is not None:
            return tool == requested.Tool
        return self.accepts_tool(tool)

    def opSetDefaultValues(self, obj, job):
        requested = getattr(self, "_requested_tc", None)
        if requested is not None:
            obj.ToolController = requested
            obj.OpToolDiameter = requested.Tool.Diameter

    # -- running the core -------------------------------------------------------

    def compute_or_fail(self, obj):
        """Import the core and return self._compute(obj, core). A bad input or
        an error of the core marks this operation in error (fail()); anything
        else empties the outputs and the path and goes on up."""
        try:
            core = compat.import_core()
        except ImportError as exc:
            self.fail(obj, str(exc))
        try:
            return self._compute(obj, core)
        except (IsoCAMError, ValueError, RuntimeError, core.CancelledError) as exc:
            self.fail(obj, describe(exc, self.ARGUMENT_SOURCES))
        except Exception:
            clear_outputs(obj, self.OUTPUTS)
            obj.Path = Path.Path()
            raise

    def run_core(self, core, call, title):
        """Run ``call(progress)`` in a worker thread (the core releases the
        GIL) and return its result, or raise its exception here.

        The Progress object is kept in ``self.active_progress`` while the
        core runs, so a script or the task panel can poll its fraction or
        cancel() it. In the GUI, freecad_ext.gui.progress keeps the window
        painted and shows `title` in a progress dialog with Cancel.
        """
        progress = core.Progress()
        outcome = {}

        def work():
            try:
                outcome["result"] = call(progress)
            except BaseException as exc:  # handed to the calling thread
                outcome["error"] = exc

        worker = threading.Thread(target=work, name="isocam-" + title)
        self.active_progress = progress
        try:
            worker.start()
            if FreeCAD.GuiUp:
                from freecad_ext.gui import progress as gui_progress  # GUI only

                gui_progress.wait(worker, progress, title)
            else:
                worker.join()
        finally:
            self.active_progress = None
        if "error" in outcome:
            raise outcome["error"]
        return outcome["result"]

    def emit_commands(self, obj, results):
        """Append the moves: up to ClearanceHeight, across, then each core
        result's path (arcs where it has them), with their feed rates (see
        FEEDS_BY_SET_FEED_RATE).

        The core's first move is a rapid to (x0, y0, SafeHeight) from
        wherever the machine is; going across at ClearanceHeight first makes
        that a straight descent.
        """
        clearance = obj.ClearanceHeight.Value
        check_moves(self, obj, results, clearance)
        x0, y0 = (float(v) for v in results[0].xyz[0][:2])
        self.commandlist.append(Path.Command("G0", {"Z": clearance}))
        self.commandlist.append(Path.Command("G0", {"X": x0, "Y": y0, "Z": clearance}))
        by_kind = not self.FEEDS_BY_SET_FEED_RATE
        for res in results:
            self.commandlist.extend(
                commands_from_moves(
                    res.kind,
                    res.xyz,
                    self.horizFeed if by_kind else None,
                    self.vertFeed if by_kind else None,
                    getattr(res, "centre", None),
                )
            )
        if not by_kind:
            compat.PathFeedRate.setFeedRate(self.commandlist, obj.ToolController)

    def fail(self, obj, message):
        """Report `message`, leave an empty path and no outputs, raise."""
        message = "%s: %s" % (obj.Label, message)
        log.error(message)
        clear_outputs(obj, self.OUTPUTS)
        obj.Path = Path.Path()
        # The message says it all; FreeCAD prints the traceback of this raise.
        raise IsoCAMError(message) from None


def add_budget_property(obj):
    """The MaxMoves property every IsoCAM op has (added to older files)."""
    for prop_type, name, group, tip in _COMMON_DEFINITIONS:
        if not hasattr(obj, name):
            obj.addProperty(prop_type, name, group, tip)
            setattr(obj, name, _COMMON_DEFAULTS[name])


def max_moves(obj):
    """The core's max_moves from the MaxMoves property (the default if absent)."""
    return float(getattr(obj, "MaxMoves", DEFAULT_MAX_MOVES))


def check_moves(proxy, obj, results, clearance):
    """Refuse (fail()) moves that are not finite, and a ClearanceHeight
    below the path's highest point: the first move goes there, across the
    model. Warn when the path is empty."""
    top = None
    for res in results:
        xyz = res.xyz
        if len(xyz) == 0:
            continue
        if not all(math.isfinite(v) for v in xyz.ravel().tolist()):
            proxy.fail(
                obj,
                translate("IsoCAM", "the core returned a move that is not finite (please report)"),
            )
        z = float(xyz[:, 2].max())
        top = z if top is None else max(top, z)
    if top is None:
        log.warning(translate("IsoCAM", "%s: the path is empty") % obj.Label)
        return
    if clearance < top - 1e-9:
        proxy.fail(
            obj,
            translate(
                "IsoCAM",
                "property ClearanceHeight (%g mm) is below the path's highest point "
                "(z = %g mm, SafeHeight or the model's top); raise ClearanceHeight",
            )
            % (clearance, top),
        )


def clear_outputs(obj, outputs):
    """Zero (or empty) the read-only output properties `obj` has."""
    for prop_type, name, _attr, _tip in outputs:
        if hasattr(obj, name):
            setattr(obj, name, "" if prop_type == "App::PropertyString" else 0)


def write_outputs(obj, outputs, metrics):
    """Write the outputs from `metrics` (an object or a dict of the core's
    metrics attributes); rows without an attribute are the caller's."""
    for _type, name, attr, _tip in outputs:
        if attr is None:
            continue
        value = metrics[attr] if isinstance(metrics, dict) else getattr(metrics, attr)
        setattr(obj, name, value)


# Core arguments every operation sets the same way.
COMMON_SOURCES = (("max_moves", "property MaxMoves"),)


def describe(exc, argument_sources):
    """The exception's message, plus which FreeCAD input sets the core
    arguments the error is about (`argument_sources`: (core argument,
    FreeCAD input) pairs).

    The core's InvalidArgumentError carries the names of the arguments its
    message is about (``exc.arguments``); other errors name none.
    """
    message = str(exc) or type(exc).__name__
    sources = dict(COMMON_SOURCES)
    sources.update(dict(argument_sources))
    named = [sources[arg] for arg in getattr(exc, "arguments", ()) if arg in sources]
    named = [src for i, src in enumerate(named) if src not in named[:i]]
    if named:
        message += " [%s %s]" % (translate("IsoCAM", "set by"), ", ".join(named))
    return message


def create_op(proxy_class, name, obj, parent_job, tool_controller, missing_tc):
    """The body of every op module's Create(): a new (or the given) object
    with a `proxy_class` proxy, added to `parent_job` (or the only Job).

    FreeCAD finds the job by name in the active document only, hence the
    document switch. Without a tool controller FreeCAD raises; the new
    object is then removed (the document stays as it was) and IsoCAMError
    says `missing_tc`.
    """
    created = obj is None
    if created:
        doc = parent_job.Document if parent_job is not None else FreeCAD.ActiveDocument
        obj = doc.addObject("Path::FeaturePython", name)
    try:
        if parent_job is None:
            obj.Proxy = proxy_class(obj, name, None, tool_controller)
        else:
            with compat.active_document(parent_job.Document):
                obj.Proxy = proxy_class(obj, name, parent_job, tool_controller)
    except compat.PathUtils.PathNoTCExistsException:
        if created:
            obj.Document.removeObject(obj.Name)
        raise IsoCAMError("%s: %s" % (name, missing_tc)) from None
    return obj


def commands_from_moves(kind, xyz, horiz_feed, vert_feed, centre=None):
    """Path.Commands for the core's flat arrays: kind (N,), xyz (N,3) and,
    where the path has arcs, centre (N,2).

    Rapid -> G0; feed and ramp -> G1 at `horiz_feed`; plunge -> G1 at `vert_feed`
    (FreeCAD's units: mm and mm/s; None: no F word, for setFeedRate to set);
    arcs -> G2 (clockwise) / G3 with I, J relative to the arc's start, as
    FreeCAD's Path and the post-processors expect.
    """
    core = compat.import_core()
    rapid, plunge = core.RAPID, core.PLUNGE
    feeds = (core.FEED, core.RAMP)
    arcs = {core.ARC_CW: "G2", core.ARC_CCW: "G3"}

    def fed(params, feed):
        if feed is not None:
            params["F"] = feed
        return params

    commands = []
    px = py = None
    centres = centre.tolist() if centre is not None else [(math.nan, math.nan)] * len(kind)
    for k, (x, y, z), (cx, cy) in zip(kind.tolist(), xyz.tolist(), centres):
        if k == rapid:
            commands.append(Path.Command("G0", {"X": x, "Y": y, "Z": z}))
        elif k in feeds:
            commands.append(Path.Command("G1", fed({"X": x, "Y": y, "Z": z}, horiz_feed)))
        elif k == plunge:
            commands.append(Path.Command("G1", fed({"X": x, "Y": y, "Z": z}, vert_feed)))
        elif k in arcs:
            if px is None or math.isnan(cx):
                raise IsoCAMError(
                    translate("IsoCAM", "the core returned an arc without a start or centre")
                )
            params = {"X": x, "Y": y, "Z": z, "I": cx - px, "J": cy - py}
            commands.append(Path.Command(arcs[k], fed(params, horiz_feed)))
        else:
            raise IsoCAMError(translate("IsoCAM", "the core returned an unknown move kind %d") % k)
        px, py = x, y
    return commands
