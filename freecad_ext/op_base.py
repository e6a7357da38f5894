"""What every IsoCAM Path operation shares: the error type, reading the picked
faces, and taking the tool controller that Create() was given.

FreeCAD offers (and, headless, picks) tool controllers through
``isToolSupported``. While Create() is given an explicit controller, only that
one qualifies, which avoids FreeCAD's GUI-only choice among several (the
headless pitfall with two or more tool controllers).
"""

import math

import FreeCAD
import Path

from freecad_ext import compat
from freecad_ext.compat import PathLog, PathOp


# Move kinds of the core's flat toolpath arrays (src/core isocam/toolpath.h,
# isocam/pocketing.h).
MOVE_RAPID, MOVE_FEED, MOVE_PLUNGE, MOVE_ARC_CW, MOVE_ARC_CCW, MOVE_RAMP = 0, 1, 2, 3, 4, 5


class IsoCAMError(Exception):
    """An input the operation cannot be computed with; the message names it."""


def picked_faces(obj, what="faces"):
    """[(model object, [0-based face indices])] from obj.Base, in pick order.

    Raises IsoCAMError for a picked sub-element that is not a face; `what`
    names what the user should pick instead.
    """
    picked = []
    for base, subs in obj.Base or []:
        indices = []
        for sub in subs:
            if not sub.startswith("Face") or not sub[4:].isdigit():
                raise IsoCAMError(
                    "Base %s.%s is not a face; pick %s of the Job's model"
                    % (base.Label, sub, what)
                )
            index = int(sub[4:]) - 1
            count = len(base.Shape.Faces)
            if not 0 <= index < count:
                raise IsoCAMError(
                    "Base %s.%s does not exist: %s has %d face%s (Face1..Face%d)"
                    % (base.Label, sub, base.Label, count, "" if count == 1 else "s", count)
                )
            if index not in indices:
                indices.append(index)
        if indices:
            picked.append((base, indices))
    return picked


class IsoCAMOp(PathOp.ObjectOp):
    """Base of our operation proxies (each lives in an importable module, so
    saved documents reopen). Subclasses say which tools they accept, their
    read-only OUTPUTS ((type, property, metrics attribute, tip) rows) and
    ARGUMENT_SOURCES (which FreeCAD input sets a core argument), and compute
    in _compute(obj, core)."""

    OUTPUTS = ()
    ARGUMENT_SOURCES = ()

    def __init__(self, obj, name, parentJob=None, toolController=None):
        # Read by isToolSupported/opSetDefaultValues while the base class
        # picks the tool controller; not saved with the document.
        self._requested_tc = toolController
        self.active_progress = None
        super().__init__(obj, name, parentJob)
        self._requested_tc = None

    def accepts_tool(self, tool):
        """True if the operation can use `tool` (any tool by default)."""
        return True

    def add_properties(self, obj):
        """Add the operation's own properties that `obj` does not have yet."""
        raise NotImplementedError

    def initOperation(self, obj):
        # `obj` may be a SetupSheet OpPrototype: addProperty, setEditorMode
        # and attribute assignment are all it supports.
        self.add_properties(obj)
        add_budget_property(obj)

    def opOnDocumentRestored(self, obj):
        # Files written by older versions may lack newer properties; editor
        # modes are not saved.
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

    def emit_commands(self, obj, results):
        """Append the moves: up to ClearanceHeight, across, then each core
        result's path (arcs where it has them).

        The core's first move is a rapid to (x0, y0, SafeHeight) from
        wherever the machine is; going across at ClearanceHeight first makes
        that a straight descent.
        """
        clearance = obj.ClearanceHeight.Value
        check_moves(self, obj, results, clearance)
        x0, y0 = (float(v) for v in results[0].xyz[0][:2])
        self.commandlist.append(Path.Command("G0", {"Z": clearance}))
        self.commandlist.append(Path.Command("G0", {"X": x0, "Y": y0, "Z": clearance}))
        for res in results:
            self.commandlist.extend(
                commands_from_moves(
                    res.kind, res.xyz, self.horizFeed, self.vertFeed, getattr(res, "centre", None)
                )
            )

    def fail(self, obj, message):
        """Report `message`, leave an empty path and no outputs, raise."""
        message = "%s: %s" % (obj.Label, message)
        PathLog.error(message)
        clear_outputs(obj, self.OUTPUTS)
        obj.Path = Path.Path()
        # The message says it all; FreeCAD prints the traceback of this raise.
        raise IsoCAMError(message) from None


# The work budget (src/core isocam/work_budget.h: kDefaultMaxMoves).
DEFAULT_MAX_MOVES = 1000000


def add_budget_property(obj):
    """The MaxMoves property every IsoCAM op has (added to older files)."""
    if not hasattr(obj, "MaxMoves"):
        obj.addProperty(
            "App::PropertyInteger",
            "MaxMoves",
            "Work budget",
            "Largest number of moves the operation may compute. A job whose "
            "estimate (from the faces' area, the stepover and the tolerances) "
            "is larger is refused before the work; raise it for a larger job.",
        )
        obj.MaxMoves = DEFAULT_MAX_MOVES


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
            proxy.fail(obj, "the core returned a move that is not finite (please report)")
        z = float(xyz[:, 2].max())
        top = z if top is None else max(top, z)
    if top is None:
        PathLog.warning("%s: the path is empty" % obj.Label)
        return
    if clearance < top - 1e-9:
        proxy.fail(
            obj,
            "property ClearanceHeight (%g mm) is below the path's highest point "
            "(z = %g mm, SafeHeight or the model's top); raise ClearanceHeight"
            % (clearance, top),
        )


def clear_outputs(obj, outputs):
    """Zero (or empty) the read-only output properties `obj` has."""
    for prop_type, name, _attr, _tip in outputs:
        if hasattr(obj, name):
            setattr(obj, name, "" if prop_type == "App::PropertyString" else 0)


# Core arguments every operation sets the same way.
COMMON_SOURCES = (("max_moves", "property MaxMoves"),)


def describe(exc, argument_sources):
    """The exception's message, plus which FreeCAD input a core argument named
    in it is set by (`argument_sources`: (core argument, FreeCAD input) pairs)."""
    message = str(exc) or type(exc).__name__
    sources = [src for arg, src in tuple(argument_sources) + COMMON_SOURCES if arg in message]
    if sources:
        message += " [set by %s]" % ", ".join(sources)
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
    (FreeCAD's units: mm and mm/s); arcs -> G2 (clockwise) / G3 with I, J
    relative to the arc's start, as FreeCAD's Path and the post-processors
    expect.
    """
    commands = []
    px = py = None
    centres = centre.tolist() if centre is not None else [(math.nan, math.nan)] * len(kind)
    for k, (x, y, z), (cx, cy) in zip(kind.tolist(), xyz.tolist(), centres):
        if k == MOVE_RAPID:
            commands.append(Path.Command("G0", {"X": x, "Y": y, "Z": z}))
        elif k in (MOVE_FEED, MOVE_RAMP):
            commands.append(
                Path.Command("G1", {"X": x, "Y": y, "Z": z, "F": horiz_feed})
            )
        elif k == MOVE_PLUNGE:
            commands.append(
                Path.Command("G1", {"X": x, "Y": y, "Z": z, "F": vert_feed})
            )
        elif k in (MOVE_ARC_CW, MOVE_ARC_CCW):
            if px is None or math.isnan(cx):
                raise IsoCAMError("the core returned an arc without a start or centre")
            commands.append(
                Path.Command(
                    "G2" if k == MOVE_ARC_CW else "G3",
                    {
                        "X": x,
                        "Y": y,
                        "Z": z,
                        "I": cx - px,
                        "J": cy - py,
                        "F": horiz_feed,
                    },
                )
            )
        else:
            raise IsoCAMError("the core returned an unknown move kind %d" % k)
        px, py = x, y
    return commands
