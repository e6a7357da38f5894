"""freecad_ext.compat against faked FreeCAD package layouts, in plain Python.

Only FreeCAD 0.20.2 is installed here, so the 0.21 and 1.0 layouts (Path.Op,
Path.Main, ..., the workbench renamed CAM) are written as real packages into a
temporary folder -- one marker module per name -- together with a fake
``FreeCAD`` module of the matching version, and compat must pick them. The
same is done for the 0.20 layout (PathScripts, and ``Path`` a plain module as
FreeCAD 0.20's compiled one is). Also here: the operations table and its input
rules, which need nothing of FreeCAD but the compat helpers.
"""

import importlib
import os
import shutil
import sys
import tempfile
import textwrap
import unittest

ADDON_DIR = os.environ.get("ISOCAM_ADDON_DIR") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", ".."
)

# compat name -> module that provides it, per layout
NEW_LAYOUT = {
    "PathOp": "Path.Op.Base",
    "PathLog": "Path.Log",
    "PathUtil": "Path.Base.Util",
    "PathUtils": "PathScripts.PathUtils",
    "PathSetupSheet": "Path.Base.SetupSheet",
    "PathJob": "Path.Main.Job",
    "PathToolController": "Path.Tool.Controller",
    "PathFeedRate": "Path.Base.FeedRate",
}
NEW_GUI = {
    "OpGui": "Path.Op.Gui.Base",
    "Selection": "Path.Op.Gui.Selection",
    "GuiUtil": "Path.Base.Gui.Util",
    "JobGui": "Path.Main.Gui.Job",
    "Preferences": "Path.Preferences",
    "UtilsGui": "PathScripts.PathUtilsGui",
}
NEW_EXTRA = ["Path.Tool.Bit", "Path.Post.scripts.linuxcnc_legacy_post"]

OLD_LAYOUT = {
    "PathOp": "PathScripts.PathOp",
    "PathLog": "PathScripts.PathLog",
    "PathUtil": "PathScripts.PathUtil",
    "PathUtils": "PathScripts.PathUtils",
    "PathSetupSheet": "PathScripts.PathSetupSheet",
    "PathJob": "PathScripts.PathJob",
    "PathToolController": "PathScripts.PathToolController",
    "PathFeedRate": "PathFeedRate",
}
OLD_GUI = {
    "OpGui": "PathScripts.PathOpGui",
    "Selection": "PathScripts.PathSelection",
    "GuiUtil": "PathScripts.PathGui",
    "JobGui": "PathScripts.PathJobGui",
    "Preferences": "PathScripts.PathPreferences",
    "UtilsGui": "PathScripts.PathUtilsGui",
}
OLD_EXTRA = ["PathScripts.PathToolBit", "PathScripts.post.linuxcnc_post"]

FAKE_FREECAD = '''
"""A stand-in for FreeCAD's module: what compat and operations touch."""
GuiUp = False
ActiveDocument = None

def Version():
    return %r

class Console:
    @staticmethod
    def PrintMessage(text):
        pass
    PrintWarning = PrintError = PrintLog = PrintMessage
'''


class FakeLayout:
    """Writes `modules` (dotted names) as packages under a temporary folder,
    puts it first on sys.path and imports freecad_ext.compat afresh."""

    OWNED = ("FreeCAD", "Path", "PathScripts", "PathFeedRate", "freecad_ext")

    def __init__(self, version, modules, plain_path_module=False, broken=(), bodies=None):
        self.root = tempfile.mkdtemp(prefix="isocam-fake-freecad-")
        self._write("FreeCAD.py", FAKE_FREECAD % (list(version),))
        if plain_path_module:  # FreeCAD 0.20: Path is a compiled module
            self._write("Path.py", "LAYOUT_MARK = 'Path'\n")
        for name in modules:
            parts = name.split(".")
            for depth in range(1, len(parts)):
                init = os.path.join(*parts[:depth], "__init__.py")
                if not os.path.exists(os.path.join(self.root, init)):
                    self._write(init, "")
            body = "LAYOUT_MARK = %r\n" % name
            if name in broken:  # exists, but its own import fails
                body += "import a_dependency_that_is_missing\n"
            body += textwrap.dedent((bodies or {}).get(name, ""))
            self._write(os.path.join(*parts) + ".py", body)

    def _write(self, relative, text):
        path = os.path.join(self.root, relative)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as out:
            out.write(textwrap.dedent(text))

    def _forget(self):
        for name in list(sys.modules):
            if name.split(".")[0] in self.OWNED:
                del sys.modules[name]

    def __enter__(self):
        self._forget()
        sys.path.insert(0, self.root)
        sys.path.insert(1, ADDON_DIR)
        importlib.invalidate_caches()
        return importlib.import_module("freecad_ext.compat")

    def __exit__(self, *exc):
        self._forget()
        sys.path.remove(self.root)
        sys.path.remove(ADDON_DIR)
        shutil.rmtree(self.root, ignore_errors=True)


def _all(*tables):
    names = []
    for table in tables:
        names.extend(table.values() if isinstance(table, dict) else table)
    return names


class CompatLayouts(unittest.TestCase):
    def assert_picks(self, compat, layout, gui_layout):
        for attr, module in layout.items():
            self.assertEqual(getattr(compat, attr).LAYOUT_MARK, module, attr)
        for attr, module in gui_layout.items():
            self.assertEqual(getattr(compat.gui(), attr).LAYOUT_MARK, module, attr)

    def test_freecad_1_0_layout_and_cam_names(self):
        modules = _all(NEW_LAYOUT, NEW_GUI, NEW_EXTRA)
        with FakeLayout(["1", "0", "0"], modules) as compat:
            self.assert_picks(compat, NEW_LAYOUT, NEW_GUI)
            self.assertEqual(compat.tool_bit_module().LAYOUT_MARK, "Path.Tool.Bit")
            post = compat.load_post_script("linuxcnc")
            self.assertEqual(post.LAYOUT_MARK, "Path.Post.scripts.linuxcnc_legacy_post")
            self.assertTrue(compat.renamed_to_cam())
            self.assertEqual(compat.path_command("Post"), "CAM_Post")
            self.assertEqual(compat.path_command("OpActive"), "CAM_OpActive")
            self.assertEqual(compat.preference_group(), "CAM")
            self.assertIn("CAMWorkbench", compat.PATH_WORKBENCHES)

    def test_freecad_0_21_layout_keeps_path_names(self):
        modules = _all(NEW_LAYOUT, NEW_GUI, NEW_EXTRA)
        with FakeLayout(["0", "21", "2"], modules) as compat:
            self.assert_picks(compat, NEW_LAYOUT, NEW_GUI)
            self.assertFalse(compat.renamed_to_cam())
            self.assertEqual(compat.path_command("Post"), "Path_Post")
            self.assertEqual(compat.preference_group(), "Path")

    def test_freecad_0_20_layout(self):
        modules = _all(OLD_LAYOUT, OLD_GUI, OLD_EXTRA)
        with FakeLayout(["0", "20", "2"], modules, plain_path_module=True) as compat:
            self.assert_picks(compat, OLD_LAYOUT, OLD_GUI)
            self.assertEqual(compat.tool_bit_module().LAYOUT_MARK, "PathScripts.PathToolBit")
            post = compat.load_post_script("linuxcnc")
            self.assertEqual(post.LAYOUT_MARK, "PathScripts.post.linuxcnc_post")
            self.assertEqual(compat.path_command("Simulator"), "Path_Simulator")

    def test_importing_compat_imports_nothing_of_path(self):
        modules = _all(OLD_LAYOUT, OLD_GUI)
        with FakeLayout(["0", "20", "2"], modules, plain_path_module=True):
            loaded = [m for m in sys.modules if m.split(".")[0] == "PathScripts"]
            self.assertEqual(loaded, [])  # InitGui.py relies on it: cheap start-up

    def test_a_broken_module_is_reported_not_skipped(self):
        modules = _all(NEW_LAYOUT, OLD_LAYOUT)
        with FakeLayout(["1", "0", "0"], modules, broken=["Path.Op.Base"]) as compat:
            with self.assertRaises(ModuleNotFoundError) as caught:
                compat.PathOp
            self.assertEqual(caught.exception.name, "a_dependency_that_is_missing")

    def test_no_path_workbench_at_all(self):
        with FakeLayout(["0", "20", "2"], []) as compat:
            with self.assertRaisesRegex(ImportError, "Path .CAM. workbench"):
                compat.PathJob


# Path.Log as FreeCAD 0.20 - 1.1 have it (module functions, _log taking the
# module), and as FreeCAD's sources have it since (a logger per module).
FUNCTIONS_LOG = """
class Level:
    ERROR, WARNING, NOTICE, INFO, DEBUG = 0, 1, 2, 3, 4
levels, lines = {}, []
def setLevel(level, module=None):
    levels[module] = level
def _log(level, module_line_func, msg):
    if levels.get(module_line_func[0], Level.NOTICE) >= level:
        lines.append((module_line_func[0], level, msg))
"""
LOGGERS_LOG = (
    FUNCTIONS_LOG
    + """
class _Logger:
    def __init__(self, module):
        self.module = module
    def warning(self, fmt, *args):
        lines.append((self.module, Level.WARNING, fmt.format(*args)))
    def info(self, fmt, *args):
        if levels.get(self.module, Level.NOTICE) >= Level.INFO:
            lines.append((self.module, Level.INFO, fmt.format(*args)))
    def debug(self, fmt, *args):
        if levels.get(self.module, Level.NOTICE) >= Level.DEBUG:
            lines.append((self.module, Level.DEBUG, fmt.format(*args)))
def getModuleLogger(module):
    return _Logger(module)
"""
)


class TranslationAndLog(unittest.TestCase):
    def test_translate_and_the_marker_without_qt(self):
        with FakeLayout(["0", "20", "2"], []) as compat:
            self.assertEqual(compat.translate("IsoCAM", "a {text}"), "a {text}")
            self.assertEqual(compat.QT_TRANSLATE_NOOP("App::Property", "tip"), "tip")

    def test_translate_uses_freecads_translator(self):
        with FakeLayout(["1", "0", "0"], []) as compat:
            import FreeCAD

            class Qt:
                @staticmethod
                def translate(context, text):
                    return "%s|%s" % (context, text)

            FreeCAD.Qt = Qt
            self.assertEqual(compat.translate("IsoCAM", "a text"), "IsoCAM|a text")

    def check_module_log(self, body):
        layout = dict(NEW_LAYOUT)
        with FakeLayout(["1", "0", "0"], layout.values(), bodies={"Path.Log": body}) as compat:
            log = compat.logger("freecad_ext.adaptive_isocurve")
            self.assertEqual(sys.modules.get("Path.Log"), None)  # not yet imported
            log.warning("a {brace} 100 %")
            log.info("certificate")
            log.debug("not shown at INFO")
            path_log = sys.modules["Path.Log"]
            self.assertEqual(path_log.levels["adaptive_isocurve"], path_log.Level.INFO)
            self.assertEqual(
                path_log.lines,
                [
                    ("adaptive_isocurve", path_log.Level.WARNING, "a {brace} 100 %"),
                    ("adaptive_isocurve", path_log.Level.INFO, "certificate"),
                ],
            )

    def test_one_logger_per_module_through_path_log_functions(self):
        self.check_module_log(FUNCTIONS_LOG)

    def test_one_logger_per_module_through_path_log_loggers(self):
        self.check_module_log(LOGGERS_LOG)


class _Tool:
    def __init__(self, shape, diameter, label):
        self.BitShape, self.Diameter, self.Label = shape, diameter, label


class _ToolController:
    def __init__(self, tool, label):
        self.Tool, self.Label = tool, label


class OperationsTable(unittest.TestCase):
    def setUp(self):
        self.layout = FakeLayout(["0", "20", "2"], [])
        self.layout.__enter__()
        self.ops = importlib.import_module("freecad_ext.operations")
        self.isocurve = self.ops.spec_named("AdaptiveIsocurve")

    def tearDown(self):
        self.layout.__exit__(None, None, None)

    def test_rows_whose_module_is_missing_are_skipped(self):
        spec = self.ops.OperationSpec
        table = (
            spec("freecad_ext.compat", "Present", "Present", "a module that exists"),
            spec("freecad_ext.not_written_yet", "Absent", "Absent", "no module"),
        )
        self.assertEqual([s.name for s in self.ops.available(table)], ["Present"])
        self.assertEqual(table[0].command, "IsoCAM_Present")
        # No icon of its own: the generic one; no .ui: a generated page.
        self.assertEqual(self.ops.icon_path(table[0]), self.ops.GENERIC_ICON)
        self.assertIsNone(self.ops.panel_path(table[0]))
        self.assertTrue(os.path.isfile(self.ops.icon_path(self.isocurve)))
        self.assertTrue(self.ops.panel_path(self.isocurve).endswith(".ui"))

    def inputs(self, scallop=0.01, chord=0.01, shape="ballend.fcstd", faces=1):
        tc = _ToolController(_Tool(shape, 6.0, "bit"), "TC")
        values = {"ScallopHeight": scallop, "ChordTolerance": chord}
        picked = [("Model", "Face%d" % (i + 1)) for i in range(faces)]
        return self.ops.Inputs(values, tc, picked)

    def test_valid_inputs_pass_and_get_the_stepover_hint(self):
        self.assertEqual(self.ops.check(self.isocurve, self.inputs()), [])
        # delta = 2 sqrt(2 r h - h^2) for r = 3, h = 0.01 (the core's formula)
        hint = self.ops.hint(self.isocurve, self.inputs())
        self.assertIn("adjacent passes at most 0.4895 mm apart", hint)

    def test_each_rule_names_its_reason(self):
        cases = [
            (dict(faces=0), "No face picked"),
            (dict(shape="endmill.fcstd"), "needs a ball-end tool"),
            (dict(scallop=0.0), "ScallopHeight must be greater than 0"),
            (dict(scallop=3.0), "smaller than the ball radius 3 mm"),
            (dict(scallop=None), "ScallopHeight: not a length"),
            (dict(chord=-1.0), "ChordTolerance must be 0 (derived) or greater"),
        ]
        for kwargs, reason in cases:
            messages = self.ops.check(self.isocurve, self.inputs(**kwargs))
            self.assertEqual(len(messages), 1, (kwargs, messages))
            self.assertIn(reason, messages[0])

    def test_five_axis_row_wants_a_flat_end_or_bull_nose(self):
        five = self.ops.spec_named("FiveAxisStripFinish")
        self.assertEqual(self.ops.check(five, self.inputs(shape="endmill.fcstd")), [])
        self.assertEqual(self.ops.check(five, self.inputs(shape="bullnose.fcstd")), [])
        messages = self.ops.check(five, self.inputs(shape="ballend.fcstd"))
        self.assertEqual(len(messages), 1, messages)
        self.assertIn("needs a flat-end or bull-nose tool", messages[0])

    def test_corner_radius_of_each_tool(self):
        compat = importlib.import_module("freecad_ext.compat")
        flat, bull, ball = (
            _Tool(f, 6.0, "bit") for f in ("endmill.fcstd", "bullnose.fcstd", "ballend.fcstd")
        )
        bull.FlatRadius = 2.0  # FreeCAD's bullnose.fcstd: the flat bottom's radius
        self.assertEqual(compat.corner_radius(flat), 0.0)
        self.assertEqual(compat.corner_radius(bull), 1.0)
        self.assertTrue(compat.is_flat_bottomed(bull) and compat.is_flat_bottomed(flat))
        self.assertFalse(compat.is_flat_bottomed(ball))
        del bull.FlatRadius
        self.assertIsNone(compat.corner_radius(bull))  # unknown: the op says so
        bull.CornerRadius = 0.5  # a tool that gives it directly (FreeCAD 1.1)
        self.assertEqual(compat.corner_radius(bull), 0.5)
        self.assertEqual(compat.corner_radius_property(bull), "CornerRadius")
        compat.set_corner_radius(bull, 1.25)
        self.assertEqual(compat.corner_radius(bull), 1.25)
        del bull.CornerRadius
        bull.FlatRadius = 2.0  # FreeCAD 0.20 and 1.0: set by the flat bottom's radius
        self.assertEqual(compat.corner_radius_property(bull), "FlatRadius")
        compat.set_corner_radius(bull, 1.25)
        self.assertEqual(bull.FlatRadius, 1.75)

    def test_no_tool_controller(self):
        inputs = self.ops.Inputs({"ScallopHeight": 0.01}, None, [("M", "Face1")])
        self.assertIn("No tool controller", self.ops.check(self.isocurve, inputs)[0])


if __name__ == "__main__":
    unittest.main()
