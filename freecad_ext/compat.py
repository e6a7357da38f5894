"""The one place that knows which FreeCAD version we run in.

The rest of the glue imports FreeCAD Path/CAM modules only from here:

==================  =============================  ==================================
name here           FreeCAD 0.20 (tested)          FreeCAD 0.21 / 1.0
==================  =============================  ==================================
PathOp              PathScripts.PathOp             Path.Op.Base
PathLog             PathScripts.PathLog            Path.Log
PathUtil            PathScripts.PathUtil           Path.Base.Util
PathUtils           PathScripts.PathUtils          PathScripts.PathUtils
PathSetupSheet      PathScripts.PathSetupSheet     Path.Base.SetupSheet
PathJob             PathScripts.PathJob            Path.Main.Job
PathToolController  PathScripts.PathToolController Path.Tool.Controller
tool_bit_module()   PathScripts.PathToolBit        Path.Tool.Bit
load_post_script()  PathScripts.post.<name>_post   Path.Post.scripts.<name>[_legacy]_post
==================  =============================  ==================================

Only FreeCAD 0.20.2 is exercised by the tests; the 0.21/1.0 names follow
FreeCAD's own module moves and are tried first.
"""

import contextlib
import importlib
import os
import sys

import FreeCAD


def _import_first(*names):
    """Import and return the first module of `names` that exists.

    A module that exists but fails while importing is not skipped: its error
    propagates, so a broken FreeCAD installation is not mistaken for an older
    version.
    """
    for name in names:
        try:
            return importlib.import_module(name)
        except ModuleNotFoundError as exc:
            missing = exc.name or ""
            if not (name == missing or name.startswith(missing + ".")):
                raise
    raise ImportError(
        "IsoCAM: none of the FreeCAD modules %s could be imported; is this "
        "FreeCAD's Python with the Path (CAM) workbench?" % ", ".join(names)
    )


PathOp = _import_first("Path.Op.Base", "PathScripts.PathOp")
PathLog = _import_first("Path.Log", "PathScripts.PathLog")
PathUtil = _import_first("Path.Base.Util", "PathScripts.PathUtil")
PathUtils = _import_first("PathScripts.PathUtils")
PathSetupSheet = _import_first("Path.Base.SetupSheet", "PathScripts.PathSetupSheet")
PathJob = _import_first("Path.Main.Job", "PathScripts.PathJob")
PathToolController = _import_first(
    "Path.Tool.Controller", "PathScripts.PathToolController"
)


def tool_bit_module():
    """The ToolBit module (its ``Factory.Create(name, shapeFile)`` makes a bit).

    Imported lazily: FreeCAD 1.1 replaced it and the op itself never needs it.
    """
    return _import_first("Path.Tool.Bit", "PathScripts.PathToolBit")


def load_post_script(name):
    """Return a freshly loaded post-processor script module with a
    function ``export(objectslist, filename, argstring)``.

    Post scripts keep their options in module globals that ``export`` only ever
    switches on, so the module is reloaded to start from its defaults.
    """
    module = _import_first(
        "PathScripts.post.%s_post" % name,
        "Path.Post.scripts.%s_legacy_post" % name,
        "Path.Post.scripts.%s_post" % name,
    )
    return importlib.reload(module)


@contextlib.contextmanager
def active_document(doc):
    """Make `doc` FreeCAD's active document for the block, then restore.

    Path's factories (PathJob.Create, PathUtils.addToJob, ...) look jobs up
    in, and add objects to, the active document only.
    """
    previous = FreeCAD.ActiveDocument
    if previous is not doc:
        FreeCAD.setActiveDocument(doc.Name)
    try:
        yield doc
    finally:
        if previous is not None and previous is not doc:
            if previous.Name in FreeCAD.listDocuments():
                FreeCAD.setActiveDocument(previous.Name)


# -- tools -----------------------------------------------------------------

# Shape identifiers FreeCAD uses for ball-end tools: the ToolBit shape file
# "ballend.fcstd" (0.19+) and the legacy Path.Tool type "BallEndMill".
_BALL_END_SHAPES = ("ballend", "ballendmill")


def tool_shape(tool):
    """The tool's shape identifier as FreeCAD names it, e.g. "ballend".

    Legacy ``Path.Tool``: its ToolType. ToolBit: the stem of its shape file
    (BitShape holds the file, ShapeName the name of the document it came
    from, which FreeCAD may suffix with digits). Empty if unknown.
    """
    legacy_type = getattr(tool, "ToolType", None)
    if legacy_type:
        return str(legacy_type)
    for attr in ("ShapeType", "BitShape", "ShapeName"):
        value = getattr(tool, attr, None)
        if value:
            return os.path.splitext(os.path.basename(str(value)))[0]
    return ""


def is_ball_end(tool):
    """True if FreeCAD describes `tool` as a ball-end mill."""
    shape = tool_shape(tool).lower()
    return shape in _BALL_END_SHAPES or shape.rstrip("0123456789") == "ballend"


def tool_label(tool):
    """A name for the tool to put in messages."""
    return str(getattr(tool, "Label", None) or getattr(tool, "Name", None) or tool)


# -- the compiled core ------------------------------------------------------


def import_core():
    """Import the compiled ``isocam_core`` module or explain how to get it.

    It is looked up on sys.path first (FreeCAD puts Mod/IsoCAM there, and the
    build places the module in that folder), then in $ISOCAM_ADDON_DIR.
    """
    try:
        return importlib.import_module("isocam_core")
    except ImportError as first:
        addon_dir = os.environ.get("ISOCAM_ADDON_DIR")
        if addon_dir and addon_dir not in sys.path:
            sys.path.append(addon_dir)
            try:
                return importlib.import_module("isocam_core")
            except ImportError:
                pass
        raise ImportError(
            "IsoCAM: the compiled module isocam_core cannot be imported (%s). "
            "Build it with `./run build` (it is written to build/addon/IsoCAM, "
            "next to freecad_ext, and FreeCAD's Mod/IsoCAM is linked there) or "
            "set ISOCAM_ADDON_DIR to the folder that holds it. It must be built "
            "for FreeCAD's Python %d.%d." % (first, *sys.version_info[:2])
        ) from first
