"""The user's round trip in the real FreeCAD GUI (run under Xvfb by
run_gui_test.sh): the Path workbench shows our command; a face is picked, the
command opens the task panel, the panel checks what is typed, OK computes
with progress, the path is simulated and posted, a long computation is
cancelled without changing the document, and the document saved in the GUI
reopens in the GUI and headless and recomputes to the same path.

The steps run in order (test_1 ... test_9) on one document; each leaves
screenshots in $ISOCAM_SCREENSHOT_DIR.
"""

import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
import unittest

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

import gui_support as gui
from freecad_ext import adaptive_isocurve, compat, operations, preferences, scripting

COMMAND = "IsoCAM_AdaptiveIsocurve"
SCALLOP = 0.05  # mm: coarse, computes in a few seconds on MAT
PREFERRED_CHORD = 0.0005  # mm: a user default set in the preferences (fits the budgets)
COMPUTE_TIMEOUT = 90.0  # s


def _ops(doc):
    return gui.ops_of(doc, adaptive_isocurve.ObjectAdaptiveIsocurve)


class RoundTrip(unittest.TestCase):
    tmp = None
    doc = None
    op_name = None
    gcode = None

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="isocam-gui-")
        preferences.store_default(adaptive_isocurve.OP_NAME, "ChordTolerance", PREFERRED_CHORD)
        cls.doc = FreeCAD.newDocument("IsoCAMRoundTrip")
        model = cls.doc.addObject("Part::Feature", "MAT")
        model.Shape = gui.load_shape("MAT.brep")
        cls.doc.recompute()
        gui.set_view(cls.doc.Name)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def op(self):
        return FreeCAD.ActiveDocument.getObject(self.op_name)

    def test_1_command_in_the_path_workbench(self):
        gui.open_path_workbench(COMMAND)
        action = gui.toolbar_action(gui.isocam_toolbar(), COMMAND)
        self.assertFalse(action.icon().isNull())
        self.assertIn("ball-end", action.toolTip())
        self.assertIsNotNone(gui.menu_action(gui.isocam_menu_path(), COMMAND))
        # Without a Job the command cannot run.
        self.assertFalse(action.isEnabled())
        # One command per table row whose module exists, none for the others.
        from freecad_ext.gui import commands

        available = operations.available()
        self.assertEqual(commands.registered(), available)
        for spec in operations.OPERATIONS:
            registered = spec.command in FreeCADGui.listCommands()
            self.assertEqual(registered, spec in available, spec.command)

    def test_1b_preferences_page_shows_the_stored_default(self):
        from freecad_ext.gui import preferences_page

        page = preferences_page.PreferencesPage()
        page.loadSettings()
        field = page.form.findChild(QtCore.QObject, "AdaptiveIsocurve_ChordTolerance")
        self.assertAlmostEqual(field.property("rawValue"), PREFERRED_CHORD)
        scallop = page.form.findChild(QtCore.QObject, "AdaptiveIsocurve_ScallopHeight")
        self.assertAlmostEqual(scallop.property("rawValue"), 0.01)  # built-in
        page.form.deleteLater()

    def test_2_job_with_a_ball_end_tool(self):
        model = self.doc.getObject("MAT")
        job = compat.gui().JobGui.Create([model], openTaskPanel=False)
        type(self).ball_tc = scripting.make_ball_end_tool_controller(job, 6.0)
        type(self).job = job
        self.doc.recompute()
        gui.pump(0.5)
        self.assertTrue(gui.toolbar_action(gui.isocam_toolbar(), COMMAND).isEnabled())

    def test_3_command_opens_the_panel_which_checks_as_typed(self):
        clone = self.job.Model.Group[0]
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(self.doc.Name, clone.Name, "Face1")
        gui.trigger(gui.toolbar_action(gui.isocam_toolbar(), COMMAND))
        gui.wait_until(FreeCADGui.Control.activeDialog, 20, "the task panel")
        ops = _ops(self.doc)
        self.assertEqual(len(ops), 1)
        op = ops[0]
        type(self).op_name = op.Name
        panel = op.ViewObject.Proxy.panel
        page = panel.op_page
        titles = [p.getTitle(op) for p in panel.featurePages]
        self.assertIn("Base Geometry", titles)
        self.assertIn("Heights", titles)
        self.assertEqual(op.Base, [(clone, ("Face1",))])
        # Our selection gate: faces only while the panel is open.
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(self.doc.Name, clone.Name, "Edge1")
        self.assertEqual(FreeCADGui.Selection.getSelectionEx(), [])
        FreeCADGui.Selection.addSelection(self.doc.Name, clone.Name, "Face1")
        picked = FreeCADGui.Selection.getSelectionEx()
        self.assertEqual([s.SubElementNames for s in picked], [("Face1",)])
        FreeCADGui.Selection.clearSelection()
        self.assertAlmostEqual(op.ChordTolerance.Value, PREFERRED_CHORD)  # preference
        # Only the ball end is offered (the Job's default tool is flat).
        combo = page.form.toolController
        offered = [combo.itemText(i) for i in range(combo.count())]
        self.assertEqual(offered, [self.ball_tc.Label])
        field = page.form.ScallopHeight
        self.assertEqual(field.property("unit"), "mm")
        self.assertIn("ball radius", field.toolTip())

        gui.type_text(field, "5 mm")
        self.assertTrue(
            any("smaller than the ball radius 3 mm" in m for m in page.messages),
            page.messages,
        )
        gui.screenshot("panel-scallop-too-large")
        gui.type_text(field, "%g mm" % SCALLOP)
        self.assertEqual(page.messages, [])
        self.assertIn("adjacent passes at most", page.form.validation.text())
        gui.screenshot("panel")
        gui.screenshot("panel-only", gui.combo_view())

    def test_4_ok_computes_with_progress(self):
        seen = []
        watching = [True]  # the watch ends with this test
        self.addCleanup(watching.__setitem__, 0, False)

        def look():
            if not watching[0]:
                return
            modal = QtGui.QApplication.activeModalWidget()
            if modal is not None and gui.is_progress_dialog(modal):
                seen.append(modal.value())
                if len(seen) == 1:
                    gui.screenshot("progress")
            if len(seen) < 3:
                gui.later(0.3, look)

        gui.later(0.6, look)
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Ok))
        gui.wait_until(
            lambda: not FreeCADGui.Control.activeDialog(),
            COMPUTE_TIMEOUT,
            "the panel to close",
        )
        op = self.op()
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        self.assertAlmostEqual(op.ScallopHeight.Value, SCALLOP)
        self.assertGreater(op.SubIsocurves, 0)
        self.assertGreater(len(op.Path.Commands), 1000)
        self.assertLessEqual(op.GuaranteedScallop.Value, SCALLOP * (1 + 1e-6))
        # The GUI kept running: the timer above saw the progress dialog.
        self.assertTrue(seen, "no progress dialog seen while computing")
        icon = op.ViewObject.Proxy.getIcon()
        self.assertTrue(icon.endswith("AdaptiveIsocurve.svg") and os.path.isfile(icon))
        type(self).gcode = op.Path.toGCode()
        gui.show_in_tree(op)  # the tree shows the op with our icon
        gui.set_view(self.doc.Name, on=self.job.Model.Group)
        gui.screenshot("path")

    def test_5_simulator_runs_the_path(self):
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.runCommand(compat.path_command("Simulator"))
        gui.wait_until(FreeCADGui.Control.activeDialog, 60, "the simulator")
        window = FreeCADGui.getMainWindow()
        # The coarsest voxels: FreeCAD's default (0.1 % of the stock) would
        # take minutes on tens of thousands of moves.
        accuracy = window.findChild(QtGui.QSlider, "sliderAccuracy")
        accuracy.setValue(accuracy.minimum())
        operations = window.findChild(QtGui.QListWidget, "listOperations")
        names = [operations.item(i).text() for i in range(operations.count())]
        self.assertEqual(names, [self.op().Label])
        bar = window.findChild(QtGui.QProgressBar, "progressBar")
        window.findChild(QtGui.QToolButton, "toolButtonFF").click()
        gui.wait_until(lambda: bar.value() > 0, 60, "the simulation to advance")
        gui.pump(2.0)
        window.findChild(QtGui.QToolButton, "toolButtonPause").click()
        gui.set_view(self.doc.Name, on=self.job.Model.Group)
        gui.screenshot("simulator")
        gui.task_button(QtGui.QDialogButtonBox.Cancel).click()
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 30, "the simulator to close")
        leftovers = [o.Name for o in self.doc.Objects if o.Name.startswith("Cut")]
        self.assertEqual(leftovers, [])

    def test_6_post_writes_the_path(self):
        job = self.job
        ngc = os.path.join(self.tmp, "round_trip.ngc")
        job.PostProcessor = "linuxcnc"
        job.PostProcessorArgs = "--no-show-editor"
        job.PostProcessorOutputFile = ngc
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(job)
        FreeCADGui.runCommand(compat.path_command("Post"))
        gui.wait_until(lambda: os.path.isfile(ngc), 60, "the G-code file")
        with open(ngc) as text:
            lines = [line.strip() for line in text]
        op = self.op()
        self.assertIn("(%s)" % op.Label, lines)
        g1 = sum(1 for c in op.Path.Commands if c.Name == "G1")
        posted_g1 = sum(1 for line in lines if line.split()[:1] == ["G1"])
        self.assertEqual(posted_g1, g1)
        rs274 = shutil.which("rs274")
        if rs274:
            run = scripting.run_rs274(ngc, {self.ball_tc.ToolNumber: 6.0}, rs274=rs274)
            self.assertTrue(run.ok, run.errors[:5])

    def test_7_cancel_leaves_the_document_as_it_was(self):
        op = self.op()
        # 0.002 mm plans about 1.5 million moves, over the default MaxMoves:
        # on a fast machine the planning can end, refused, before the Cancel
        # below is pressed. With room in the budget the computation runs on
        # (cutting, about 15 s), so the Cancel always lands in it.
        max_moves = op.MaxMoves
        op.MaxMoves = 10 * max_moves
        before = gui.snapshot(self.doc)
        certificate = (op.SubIsocurves, op.CuttingLength.Value)
        FreeCADGui.ActiveDocument.setEdit(op.Name)  # what a double click does
        gui.wait_until(FreeCADGui.Control.activeDialog, 20, "the task panel")
        page = op.ViewObject.Proxy.panel.op_page
        gui.type_text(page.form.ScallopHeight, "0.002 mm")  # takes ~15 s
        cancelled = []
        polling = [True]  # ends with this test, never cancels a later one

        def cancel_when_shown():
            if not polling[0]:
                return
            modal = QtGui.QApplication.activeModalWidget()
            buttons = gui.children(modal, QtGui.QPushButton) if modal is not None else []
            if modal is not None and gui.is_progress_dialog(modal):
                if not buttons:  # shown, its button not laid out yet
                    gui.later(0.1, cancel_when_shown)
                    return
                gui.screenshot("progress-before-cancel")
                cancelled.append(modal.value())
                gui.click(gui.button_labelled(modal, "Cancel"))
            else:
                gui.later(0.1, cancel_when_shown)

        gui.later(1.0, cancel_when_shown)
        try:
            gui.click(gui.task_button(QtGui.QDialogButtonBox.Apply))
        finally:
            polling[0] = False
        self.assertEqual(len(cancelled), 1)
        # The computation stopped; the op kept its path and certificate and
        # waits to be recomputed; the panel is still open and says why.
        self.assertTrue(FreeCADGui.Control.activeDialog())
        self.assertIn("cancelled", page.form.validation.text())
        self.assertEqual(op.Path.toGCode(), before[op.Name][2])
        self.assertEqual((op.SubIsocurves, op.CuttingLength.Value), certificate)
        self.assertIn("Touched", op.State)
        self.assertIn("cancelled by the user", gui.report_view_text())
        gui.screenshot("panel-after-cancel")
        # Cancel on the panel discards the edit: everything as it was.
        gui.task_button(QtGui.QDialogButtonBox.Cancel).click()
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 20, "the panel to close")
        self.assertAlmostEqual(op.ScallopHeight.Value, SCALLOP)
        self.assertEqual(gui.snapshot(self.doc), before)
        op.MaxMoves = max_moves

    def test_8_saved_document_recomputes_the_same_path_in_gui_and_headless(self):
        path = os.path.join(self.tmp, "round_trip.FCStd")
        self.doc.saveAs(path)
        name = self.doc.Name
        FreeCAD.closeDocument(name)
        gui.pump(0.2)

        doc = FreeCAD.openDocument(path)
        type(self).doc = doc
        op = doc.getObject(self.op_name)
        from freecad_ext.gui import view_provider

        self.assertIsInstance(op.ViewObject.Proxy, view_provider.ViewProvider)
        self.assertTrue(op.ViewObject.Proxy.getIcon().endswith("AdaptiveIsocurve.svg"))
        op.touch()
        doc.recompute()
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        self.assertEqual(op.Path.toGCode(), self.gcode)
        # The reopened op opens its panel.
        FreeCADGui.ActiveDocument.setEdit(op.Name)
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Cancel), 20, "the panel")
        self.assertIsInstance(op.ViewObject.Proxy.panel.op_page.form.ScallopHeight, QtGui.QWidget)
        gui.screenshot("reopened-panel")
        gui.task_button(QtGui.QDialogButtonBox.Cancel).click()
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 20, "close")

        self.assertEqual(_headless_gcode(path, self.op_name, self.tmp), self.gcode)

    def test_9_a_fine_scallop_typed_and_ok_is_kept(self):
        """0.004 mm typed, then OK: the op computes with 0.004 mm. FreeCAD
        1.1's field shows it rounded to the decimals preference (2 by
        default: "0.00 mm") once it loses focus; the value typed counts.
        (0.002 mm on the whole of MAT, with the chords its budget derives,
        is some 1.5 million moves: over the default MaxMoves, refused.)"""
        op = self.doc.getObject(self.op_name)
        FreeCADGui.ActiveDocument.setEdit(op.Name)
        gui.wait_until(FreeCADGui.Control.activeDialog, 20, "the task panel")
        page = op.ViewObject.Proxy.panel.op_page
        gui.type_text(page.form.ScallopHeight, "0.004 mm")
        page.form.ChordTolerance.setFocus(QtCore.Qt.TabFocusReason)  # leave the field
        gui.pump(0.3)
        gui.screenshot("panel-fine-scallop")
        self.assertEqual(page.messages, [])
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Ok))
        gui.wait_until(
            lambda: not FreeCADGui.Control.activeDialog(),
            COMPUTE_TIMEOUT,
            "the panel to close",
        )
        self.assertAlmostEqual(op.ScallopHeight.Value, 0.004, places=9)
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        self.assertLessEqual(op.GuaranteedScallop.Value, 0.004 * (1 + 1e-6))
        self.assertGreater(len(op.Path.Commands), 0)
        gui.screenshot("path-fine-scallop")


def _headless_gcode(fcstd, op_name, tmp):
    """Open `fcstd` in freecadcmd, recompute `op_name` and return its G-code."""
    script = os.path.join(tmp, "headless_reopen.py")
    out = os.path.join(tmp, "headless.gcode")
    with open(script, "w") as f:
        f.write(
            textwrap.dedent(
                """
                import os, traceback
                import FreeCAD
                try:
                    doc = FreeCAD.openDocument(%r)
                    op = doc.getObject(%r)
                    op.touch()
                    doc.recompute()
                    with open(%r, "w") as out:
                        out.write(op.Path.toGCode() if "Invalid" not in op.State
                                  else "INVALID " + op.getStatusString())
                except Exception:
                    traceback.print_exc()
                os._exit(0)
                """
                % (fcstd, op_name, out)
            )
        )
    freecadcmd = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    subprocess.run(
        [freecadcmd, script],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        timeout=120,
        check=False,
    )
    with open(out) as f:
        return f.read()


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
