"""The one place that knows which FreeCAD version we run in.

The rest of the glue imports FreeCAD Path/CAM modules only from here:

==================  =============================  ==================================
name here           FreeCAD 0.20                   FreeCAD 0.21 / 1.0 / 1.1
==================  =============================  ==================================
PathOp              PathScripts.PathOp             Path.Op.Base
PathLog             PathScripts.PathLog            Path.Log
PathUtil            PathScripts.PathUtil           Path.Base.Util
PathUtils           PathScripts.PathUtils          PathScripts.PathUtils
PathSetupSheet      PathScripts.PathSetupSheet     Path.Base.SetupSheet
PathJob             PathScripts.PathJob            Path.Main.Job
PathToolController  PathScripts.PathToolController Path.Tool.Controller
PathFeedRate        PathFeedRate                   Path.Base.FeedRate
tool_bit_module()   PathScripts.PathToolBit        Path.Tool.Bit (1.1: old documents only)
make_tool_bit()     PathToolBit.Factory            1.1: Path.Tool.toolbit.ToolBit
post_list()         None (the caller's 0.20 list)  Path.Post.Processor's factory
update_spin_box()   helper.updateSpinBox()         1.1: helper.updateWidget()
load_post_script()  PathScripts.post.<name>_post   Path.Post.scripts.<name>[_legacy]_post
gui().OpGui         PathScripts.PathOpGui          Path.Op.Gui.Base
gui().Selection     PathScripts.PathSelection      Path.Op.Gui.Selection
gui().GuiUtil       PathScripts.PathGui            Path.Base.Gui.Util
gui().JobGui        PathScripts.PathJobGui         Path.Main.Gui.Job
gui().Preferences   PathScripts.PathPreferences    Path.Preferences
gui().UtilsGui      PathScripts.PathUtilsGui       PathScripts.PathUtilsGui
==================  =============================  ==================================

FreeCAD 1.0 also renamed the workbench (PathWorkbench -> CAMWorkbench), its
commands (Path_Post -> CAM_Post) and its preference group; see
:func:`renamed_to_cam` and the names derived from it.

`./run test` exercises every branch for real: FreeCAD 0.20.2 (Debian
bookworm), 1.0.0 (trixie) and 1.1 (sid), headless and in the GUI; the module
names are also checked against faked package layouts
(tests/python/test_compat_layout.py).
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


# FreeCAD's Path modules by the names the glue uses, imported on first use
# (PEP 562), so that importing this module at GUI start-up costs nothing.
_MODULES = {
    "PathOp": ("Path.Op.Base", "PathScripts.PathOp"),
    "PathLog": ("Path.Log", "PathScripts.PathLog"),
    "PathUtil": ("Path.Base.Util", "PathScripts.PathUtil"),
    "PathUtils": ("PathScripts.PathUtils",),
    "PathSetupSheet": ("Path.Base.SetupSheet", "PathScripts.PathSetupSheet"),
    "PathJob": ("Path.Main.Job", "PathScripts.PathJob"),
    "PathToolController": ("Path.Tool.Controller", "PathScripts.PathToolController"),
    "PathFeedRate": ("Path.Base.FeedRate", "PathFeedRate"),
}


def __getattr__(name):
    try:
        names = _MODULES[name]
    except KeyError:
        raise AttributeError("module %r has no attribute %r" % (__name__, name)) from None
    module = _import_first(*names)
    globals()[name] = module
    return module


def version_tuple(version=None):
    """(major, minor) of `version` (FreeCAD.Version(), a list of strings) or
    of the running FreeCAD; (0, 0) if it cannot be read."""
    version = FreeCAD.Version() if version is None else version
    try:
        return int(version[0]), int(version[1])
    except (IndexError, TypeError, ValueError):
        return 0, 0


def tool_bit_module():
    """The ToolBit module of FreeCAD 0.20 / 1.0 (``Factory.Create(name,
    shapeFile)`` makes a bit). FreeCAD 1.1 keeps ``Path.Tool.Bit`` only to open
    old documents; use :func:`make_tool_bit`, which knows both."""
    return _import_first("Path.Tool.Bit", "PathScripts.PathToolBit")


def _toolbit_class():
    """FreeCAD 1.1's ToolBit asset class (Path.Tool.toolbit.ToolBit), or None
    before 1.1."""
    try:
        module = importlib.import_module("Path.Tool.toolbit")
    except ModuleNotFoundError:
        return None
    cls = getattr(module, "ToolBit", None)
    return cls if hasattr(cls, "from_dict") else None


def make_tool_bit(doc, shape_file, diameter, label):
    """A ToolBit document object in `doc` of FreeCAD's shape `shape_file`
    (e.g. "ballend.fcstd", as shipped with FreeCAD) with `diameter` (mm).

    FreeCAD 1.1: a ToolBit asset made from its shape id, then attached to the
    document (what FreeCAD's own CAMTests do). 0.20 / 1.0: the ToolBit
    module's Factory, which adds to the active document.
    """
    cls = _toolbit_class()
    if cls is not None:
        shape_id = os.path.splitext(os.path.basename(shape_file))[0]
        asset = cls.from_dict(
            {
                "name": label,
                "shape": shape_id,
                "parameter": {"Diameter": diameter},
                "attribute": {},
            }
        )
        bit = asset.attach_to_doc(doc=doc, label=label)
    else:
        with active_document(doc):
            bit = tool_bit_module().Factory.Create("ToolBit", shape_file)
    bit.Diameter = diameter
    bit.Label = label
    return bit


def post_processor_factory():
    """FreeCAD 1.0+'s Path.Post.Processor.PostProcessorFactory, or None."""
    try:
        module = importlib.import_module("Path.Post.Processor")
    except ModuleNotFoundError:
        return None
    return getattr(module, "PostProcessorFactory", None)


def post_list(job, postname):
    """The objects to post for `job`, in the order and with the fixture
    set-up of this FreeCAD's own post command.

    FreeCAD 1.0+: the post processor's own list (job.OrderOutputBy,
    SplitOutput sections joined); it writes no G0 Z before the first tool
    change, on purpose (no move before G43). FreeCAD 0.20: None, and the
    caller builds 0.20's "order by fixture" list itself, which goes to
    clearance height after each fixture's G54.
    """
    factory = post_processor_factory()
    if factory is None:
        return None
    processor = factory.get_post_processor(job, postname)
    if processor is None:
        raise ImportError("IsoCAM: FreeCAD has no post processor %r" % postname)
    return [item for _, section in processor._buildPostList() for item in section]


def update_spin_box(helper):
    """Show the bound property's value in a Path QuantitySpinBox helper:
    ``updateWidget()`` from FreeCAD 1.1 on, ``updateSpinBox()`` before."""
    update = getattr(helper, "updateWidget", None) or helper.updateSpinBox
    update()


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


# -- translation and the log ---------------------------------------------------

# Context of IsoCAM's user messages (FreeCAD's ops use e.g. "CAM_Surface").
TRANSLATION_CONTEXT = "IsoCAM"


def QT_TRANSLATE_NOOP(context, text):
    """Mark `text` for translation in `context`; returns it unchanged.

    What Qt's QT_TRANSLATE_NOOP does, in plain Python so that it needs no Qt
    (headless, and the faked layouts of the tests). FreeCAD's ops wrap every
    property tip in QT_TRANSLATE_NOOP("App::Property", ...): lupdate finds the
    call by its name, and the property editor translates the tip in that
    context when it shows it.
    """
    return text


def translate(context, text):
    """`text` translated in `context` by FreeCAD's translators
    (``FreeCAD.Qt.translate``, the same on 0.20, 1.0 and 1.1); `text` itself
    where this FreeCAD has none."""
    function = getattr(getattr(FreeCAD, "Qt", None), "translate", None)
    return function(context, text) if function is not None else text


class ModuleLogger:
    """FreeCAD's Path log (Path.Log; PathScripts.PathLog on 0.20) under one
    module's name, as FreeCAD's ops log: "module.LEVEL: message" in the
    report view, each module's level its own (``Path.Log.setLevel(
    Path.Log.Level.DEBUG, "adaptive_isocurve")`` shows that module's debug
    lines). The level starts at INFO, as FreeCAD's ops set theirs.

    Path.Log is imported on the first message, so a module can make its
    logger when it is imported at no cost (the GUI's start-up).
    """

    def __init__(self, module, level="INFO"):
        self.module = module.rsplit(".", 1)[-1]  # as Path.Log.thisModule()
        self._initial_level = level
        self._log = None

    def _path_log(self):
        if self._log is None:
            log = globals().get("PathLog") or __getattr__("PathLog")
            log.setLevel(getattr(log.Level, self._initial_level), self.module)
            self._log = log
        return self._log

    def _emit(self, level, message):
        log = self._path_log()
        message = str(message)
        loggers = getattr(log, "getModuleLogger", None)
        if loggers is not None:  # Path.Log with a logger object per module
            return getattr(loggers(self.module), level.lower())("{}", message)
        # 0.20 - 1.1: the module functions take the module from the caller's
        # file name; _log is what they call with it.
        return log._log(getattr(log.Level, level), (self.module, 0, ""), message)

    def debug(self, message):
        return self._emit("DEBUG", message)

    def info(self, message):
        return self._emit("INFO", message)

    def notice(self, message):
        return self._emit("NOTICE", message)

    def warning(self, message):
        return self._emit("WARNING", message)

    def error(self, message):
        return self._emit("ERROR", message)


def logger(module):
    """The log of `module` (pass ``__name__``); one per module."""
    return ModuleLogger(module)


# -- names FreeCAD 1.0 changed ------------------------------------------------

# The workbench our commands join, under either of its names.
PATH_WORKBENCHES = ("PathWorkbench", "CAMWorkbench")


def renamed_to_cam(version=None):
    """True from FreeCAD 1.0 on, where the Path workbench is called CAM.

    `version` is FreeCAD.Version() (a list of strings) or None for the
    running FreeCAD.
    """
    return version_tuple(version) >= (1, 0)


def workbench_name():
    """The Path (CAM) workbench's name in this FreeCAD."""
    return PATH_WORKBENCHES[1] if renamed_to_cam() else PATH_WORKBENCHES[0]


def path_command(name):
    """FreeCAD's own command `name` ("Post", "Simulator") under this version's
    prefix: Path_Post on 0.20/0.21, CAM_Post on 1.0."""
    return ("CAM_" if renamed_to_cam() else "Path_") + name


def preference_group():
    """The preferences dialog group of the Path (CAM) workbench."""
    return "CAM" if renamed_to_cam() else "Path"


class _GuiModules:
    """FreeCAD's Path GUI modules, imported on first use (GUI only)."""

    _NAMES = {
        "OpGui": ("Path.Op.Gui.Base", "PathScripts.PathOpGui"),
        "Selection": ("Path.Op.Gui.Selection", "PathScripts.PathSelection"),
        "GuiUtil": ("Path.Base.Gui.Util", "PathScripts.PathGui"),
        "JobGui": ("Path.Main.Gui.Job", "PathScripts.PathJobGui"),
        "Preferences": ("Path.Preferences", "PathScripts.PathPreferences"),
        "UtilsGui": ("PathScripts.PathUtilsGui",),
    }

    def __getattr__(self, attr):
        try:
            names = self._NAMES[attr]
        except KeyError:
            raise AttributeError(attr) from None
        module = _import_first(*names)
        setattr(self, attr, module)
        return module


_gui_modules = _GuiModules()


def gui():
    """Namespace of FreeCAD's Path GUI modules (see the table above).

    Importing them needs FreeCAD's GUI; headless code must not call this.
    """
    return _gui_modules


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


_FLAT_END_SHAPES = ("endmill", "flatendmill")


def is_flat_end(tool):
    """True if FreeCAD describes `tool` as a flat end mill (ToolBit endmill,
    legacy EndMill)."""
    return tool_shape(tool).lower().rstrip("0123456789") in _FLAT_END_SHAPES


# The bull nose: the ToolBit shape "bullnose.fcstd" (FreeCAD 1.1 also
# knows it as "torus").
_BULL_NOSE_SHAPES = ("bullnose", "torus")


def is_bull_nose(tool):
    """True if FreeCAD describes `tool` as a bull-nose (torus) mill."""
    return tool_shape(tool).lower().rstrip("0123456789") in _BULL_NOSE_SHAPES


def is_flat_bottomed(tool):
    """True if `tool` is a flat end or a bull nose (a flat bottom to tilt)."""
    return is_flat_end(tool) or is_bull_nose(tool)


def corner_radius(tool):
    """The corner radius (mm) of a flat end (0) or bull nose, or None if the
    tool says nothing of it. FreeCAD's bull-nose ToolBit of 0.20 and 1.0
    gives FlatRadius, the radius of its flat bottom: the corner radius is
    Diameter / 2 - FlatRadius; 1.1's Bullnose shape (and a legacy Path.Tool)
    gives CornerRadius directly (1.1 drops FlatRadius from it)."""
    if is_flat_end(tool) and not is_bull_nose(tool):
        legacy = getattr(tool, "CornerRadius", None)
        return float(legacy) if legacy is not None else 0.0
    corner = getattr(tool, "CornerRadius", None)
    if corner is not None:
        return float(corner)
    flat = getattr(tool, "FlatRadius", None)
    if flat is None:
        return None
    return float(tool.Diameter) / 2.0 - float(flat)


def corner_radius_property(tool):
    """The name of the property that sets `tool`'s corner: CornerRadius
    where it has one (FreeCAD 1.1's Bullnose), else FlatRadius (0.20, 1.0)."""
    return "CornerRadius" if hasattr(tool, "CornerRadius") else "FlatRadius"


def set_corner_radius(tool, corner):
    """Give the bull-nose `tool` the corner radius `corner` (mm), in the
    property this FreeCAD's shape has (corner_radius_property())."""
    if corner_radius_property(tool) == "CornerRadius":
        tool.CornerRadius = corner
    else:
        tool.FlatRadius = float(tool.Diameter) / 2.0 - corner


def tool_label(tool):
    """A name for the tool to put in messages."""
    return str(getattr(tool, "Label", None) or getattr(tool, "Name", None) or tool)


# -- the compiled core ------------------------------------------------------


def import_core():
    """Import the compiled ``isocam_core`` module or explain how to get it.

    It is looked up on sys.path first (FreeCAD puts Mod/IsoCAM there, and the
    build places the module in that folder), then in $ISOCAM_ADDON_DIR, then
    in build/addon/IsoCAM under the addon's own folder (where `./run build`
    puts it when the Addon Manager installed the sources as Mod/IsoCAM).
    """
    try:
        return importlib.import_module("isocam_core")
    except ImportError as first:
        source_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        for addon_dir in (
            os.environ.get("ISOCAM_ADDON_DIR"),
            os.path.join(source_root, "build", "addon", "IsoCAM"),
        ):
            if not addon_dir or addon_dir in sys.path or not os.path.isdir(addon_dir):
                continue
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
