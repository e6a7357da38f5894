"""Bad input in the real FreeCAD GUI (run under Xvfb by run_gui_test.sh).

Each case goes through the command and the task panel as a user would: the
panel names the problem while it is typed (where it can be seen before
computing), OK computes, the operation ends marked in error with a message in
the report view, FreeCAD keeps running and nothing else in the document
changes -- checked against a snapshot that includes a computed operation.
Also: operations made by a script, or saved by headless FreeCAD, get our view
provider (icon, panel) when shown in the GUI.
"""

import os
import shutil
import subprocess
import tempfile
import textwrap
import unittest

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

import gui_support as gui
from freecad_ext import adaptive_isocurve, compat, operations, scripting

COMMAND = "IsoCAM_AdaptiveIsocurve"


def _our_ops(doc):
    return gui.ops_of(doc, adaptive_isocurve.ObjectAdaptiveIsocurve)


class BadInput(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        gui.open_path_workbench(COMMAND)
        cls.doc = doc = FreeCAD.newDocument("IsoCAMBadInput")
        mat = doc.addObject("Part::Feature", "MAT")
        mat.Shape = gui.load_shape("MAT.brep")
        sliver = doc.addObject("Part::Feature", "Sliver")
        sliver.Shape = gui.degenerate_face()
        doc.recompute()
        cls.job = compat.gui().JobGui.Create([mat, sliver], openTaskPanel=False)
        cls.ball_tc = scripting.make_ball_end_tool_controller(cls.job, 6.0)
        cls.flat_tc = cls.job.Tools.Group[0]  # FreeCAD's default end mill
        assert not compat.is_ball_end(cls.flat_tc.Tool)
        cls.mat_clone, cls.sliver_clone = cls.job.Model.Group
        # A computed operation made by a script: the bystander every case
        # checks, and a script-made op that must get our view provider.
        cls.good = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME, parentJob=cls.job, toolController=cls.ball_tc
        )
        cls.good.Label = "Good"
        cls.good.Base = [(cls.mat_clone, ["Face1"])]
        cls.good.ScallopHeight = 0.05
        doc.recompute()
        gui.settle(doc)
        gui.set_view(doc.Name, on=[cls.mat_clone])

    def run_command(self, faces=()):
        """Pick `faces` ((object, sub) pairs), run the command, return the new
        op and its page."""
        FreeCAD.setActiveDocument(self.doc.Name)
        FreeCADGui.Selection.clearSelection()
        for obj, sub in faces:
            FreeCADGui.Selection.addSelection(self.doc.Name, obj.Name, sub)
        known = {o.Name for o in _our_ops(self.doc)}
        gui.trigger(gui.toolbar_action(gui.isocam_toolbar(), COMMAND))
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Ok), 20, "the task panel")
        (op,) = [o for o in _our_ops(self.doc) if o.Name not in known]
        return op, op.ViewObject.Proxy.panel.op_page

    def ok_expecting_error(self, op, before, *fragments):
        """Press OK; `op` must end in error naming `fragments`, the rest of
        the document as in `before`."""
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Ok))
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 60, "the panel to close")
        message = op.getStatusString()
        self.assertIn("Invalid", op.State, message)
        for fragment in fragments:
            self.assertIn(fragment, message)
            self.assertIn(fragment, gui.report_view_text())
        self.assertEqual(len(op.Path.Commands), 0)
        after = gui.snapshot(self.doc, skip=[op.Name])
        self.assertEqual(gui.snapshot_changes(after, before), [])
        self.assertNotIn("Invalid", self.good.State)
        return message

    def test_script_made_op_has_our_view_provider(self):
        from freecad_ext.gui import view_provider

        gui.wait_until(
            lambda: isinstance(self.good.ViewObject.Proxy, view_provider.ViewProvider),
            10,
            "the view provider",
        )
        proxy = self.good.ViewObject.Proxy
        self.assertIs(proxy.Object, self.good)
        self.assertTrue(proxy.getIcon().endswith("AdaptiveIsocurve.svg"))

    def test_panel_widgets_get_their_own_class_back(self):
        """A wrapper of another class at a widget's address (PySide hands out
        a kept wrapper of a deleted widget for a new one at the same place)
        is replaced, in a loaded form's attributes, by one of the widget's
        own class; wrappers of the right class are kept as they are."""
        from freecad_ext.gui import qt_objects

        if qt_objects._shiboken is None:
            self.skipTest("no shiboken module in this FreeCAD's Python")
        form = QtGui.QWidget()
        combo = QtGui.QComboBox(form)
        combo.setObjectName("toolController")
        spin = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox", form)
        spin.setObjectName("ScallopHeight")
        address = qt_objects._shiboken.getCppPointer(combo)[0]
        form.toolController = qt_objects._shiboken.wrapInstance(address, QtGui.QDialog)
        form.ScallopHeight = spin
        qt_objects.true_type_children(form)
        self.assertIsInstance(form.toolController, QtGui.QComboBox)
        self.assertEqual(qt_objects._shiboken.getCppPointer(form.toolController)[0], address)
        form.toolController.addItem("ball", "TC")
        self.assertEqual(combo.itemData(0), "TC")
        self.assertIs(form.ScallopHeight, spin)
        self.assertIs(qt_objects.true_type(None), None)
        form.deleteLater()
        # true_type_children reads the named children from the form's own
        # attributes: a form loaded from our .ui file has them there.
        loaded = FreeCADGui.PySideUic.loadUi(
            operations.panel_path(operations.spec_named("AdaptiveIsocurve"))
        )
        held = {k for k, v in vars(loaded).items() if isinstance(v, QtCore.QObject)}
        self.assertLessEqual({"toolController", "ScallopHeight"}, held)
        loaded.deleteLater()

    def test_a_panel_that_fails_to_open_leaves_nothing_open_or_changed(self):
        """A page that raises while the panel is set up (as a wrong widget
        class once made it): the panel closes again, the report view names
        the op and the error, the document is as it was, and the panel opens
        once the page works."""
        from freecad_ext.gui import task_panel

        before = gui.snapshot(self.doc)
        good_set_fields = task_panel.OperationPage.setFields

        def broken_set_fields(page, obj):
            raise RuntimeError("a page that cannot be filled")

        task_panel.OperationPage.setFields = broken_set_fields
        try:
            FreeCADGui.ActiveDocument.setEdit(self.good.Name)
            gui.pump(0.5)
        finally:
            task_panel.OperationPage.setFields = good_set_fields
        self.assertFalse(FreeCADGui.Control.activeDialog())
        report = gui.report_view_text()
        self.assertIn("Good: the task panel could not be opened", report)
        self.assertIn("RuntimeError: a page that cannot be filled", report)
        self.assertEqual(gui.snapshot_changes(gui.snapshot(self.doc), before), [])
        self.assertIsNone(self.good.ViewObject.Proxy.panel)
        FreeCADGui.ActiveDocument.setEdit(self.good.Name)
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Cancel), 20, "the panel")
        gui.task_button(QtGui.QDialogButtonBox.Cancel).click()
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 20, "the panel to close")
        self.assertEqual(gui.snapshot_changes(gui.snapshot(self.doc), before), [])

    def test_no_face_picked(self):
        before = gui.snapshot(self.doc)
        op, page = self.run_command()
        self.assertTrue(any("No face picked" in m for m in page.messages))
        gui.screenshot("no-face-panel", gui.combo_view())
        self.ok_expecting_error(op, before, "no faces picked")

    def test_scallop_larger_than_the_ball(self):
        before = gui.snapshot(self.doc)
        op, page = self.run_command([(self.mat_clone, "Face1")])
        gui.type_text(page.form.ScallopHeight, "4 mm")
        self.assertTrue(
            any("smaller than the ball radius 3 mm" in m for m in page.messages),
            page.messages,
        )
        gui.screenshot("scallop-too-large-panel")
        self.ok_expecting_error(op, before, "scallop_height", "ScallopHeight")

    def test_flat_end_tool(self):
        before = gui.snapshot(self.doc)
        # A user sets the op's ToolController to the flat end mill in the
        # property editor, then opens the panel.
        op = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME, parentJob=self.job, toolController=self.flat_tc
        )
        op.Label = "FlatTool"
        op.Base = [(self.mat_clone, ["Face1"])]
        gui.pump(0.2)  # the document observer attaches the view provider
        FreeCADGui.getDocument(self.doc.Name).setEdit(op.Name)
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Ok), 20, "the task panel")
        page = op.ViewObject.Proxy.panel.op_page
        self.assertEqual(page.form.toolController.currentText(), self.flat_tc.Label)
        self.assertTrue(any("ball-end tool" in m for m in page.messages), page.messages)
        gui.screenshot("flat-tool-panel")
        self.ok_expecting_error(op, before, "not a ball end", self.flat_tc.Label)

    def test_face_the_core_cannot_machine(self):
        before = gui.snapshot(self.doc)
        op, page = self.run_command([(self.sliver_clone, "Face1")])
        self.assertEqual(page.messages, [])  # nothing to see before computing
        gui.type_text(page.form.ScallopHeight, "0.05 mm")
        message = self.ok_expecting_error(op, before, "degenerate")
        self.assertIn("Face1", message)
        gui.screenshot("core-failure-report")

    def _fresh_job(self, name):
        """A new Job on MAT: FreeCAD gives it only its 5 mm end mill."""
        doc = FreeCAD.newDocument(name)
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        model = doc.addObject("Part::Feature", "MAT")
        model.Shape = gui.load_shape("MAT.brep")
        job = compat.gui().JobGui.Create([model], openTaskPanel=False)
        doc.recompute()
        self.assertFalse(any(compat.is_ball_end(tc.Tool) for tc in job.Tools.Group))
        return doc, job

    def _press_with_offer(self, seen, **answer):
        from freecad_ext.gui import commands

        gui.answer_input_dialog(commands.BALL_END_OFFER, seen, **answer)
        with gui.expect_dialog(lambda w: isinstance(w, QtGui.QInputDialog)):
            gui.trigger(gui.toolbar_action(gui.isocam_toolbar(), COMMAND))
            gui.wait_until(lambda: seen, 20, "the ball-end offer")

    def test_fresh_job_declining_the_ball_end_offer_changes_nothing(self):
        doc, job = self._fresh_job("IsoCAMNoBall")
        before = gui.snapshot(doc)
        seen = []
        self._press_with_offer(seen, accept=False)
        label, default = seen[0]
        self.assertIn("needs a ball-end tool", label)
        self.assertIn(job.Label, label)
        self.assertEqual(default, 6.0)
        gui.pump(0.5)
        self.assertFalse(FreeCADGui.Control.activeDialog())
        self.assertEqual(_our_ops(doc), [])
        self.assertEqual(gui.snapshot(doc), before)

    def test_fresh_job_accepting_the_ball_end_offer_makes_the_op(self):
        doc, job = self._fresh_job("IsoCAMAddBall")
        seen = []
        self._press_with_offer(seen, value=8.0)
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Cancel), 30, "the panel")
        gui.screenshot("panel-after-ball-end-offer")
        (op,) = _our_ops(doc)
        tc = op.ToolController
        self.assertTrue(compat.is_ball_end(tc.Tool))
        self.assertAlmostEqual(tc.Tool.Diameter.Value, 8.0)
        self.assertIn(tc, job.Tools.Group)
        self.assertEqual(len(job.Tools.Group), 2)  # FreeCAD's end mill, ours
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Cancel))
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 20, "close")
        self.assertEqual(_our_ops(doc), [])

    def test_document_saved_headless_gets_our_view_provider(self):
        tmp = tempfile.mkdtemp(prefix="isocam-gui-")
        self.addCleanup(shutil.rmtree, tmp, True)
        path = os.path.join(tmp, "headless.FCStd")
        _save_headless_document(path, tmp)
        doc = FreeCAD.openDocument(path)
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        (op,) = _our_ops(doc)
        from freecad_ext.gui import view_provider

        gui.wait_until(
            lambda: isinstance(op.ViewObject.Proxy, view_provider.ViewProvider),
            10,
            "the view provider",
        )
        FreeCADGui.getDocument(doc.Name).setEdit(op.Name)
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Cancel), 20, "the panel")
        self.assertIs(op.ViewObject.Proxy.Object, op)
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Cancel))
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 20, "close")
        self.assertIn(op, doc.Objects)  # Cancel on an existing op keeps it
        self.assertNotIn("Traceback", gui.report_view_text())


def _save_headless_document(path, tmp):
    """A Job with an Adaptive Isocurve op made and saved by freecadcmd (no
    GUI, so no view provider is saved)."""
    script = os.path.join(tmp, "make.py")
    with open(script, "w") as f:
        f.write(
            textwrap.dedent(
                """
                import os, sys, traceback
                sys.path.insert(0, %r)
                try:
                    import FreeCAD, Part
                    from freecad_ext import adaptive_isocurve, scripting
                    doc = FreeCAD.newDocument("Headless")
                    model = doc.addObject("Part::Feature", "MAT")
                    shape = Part.Shape()
                    shape.read(%r)
                    model.Shape = shape
                    job = scripting.make_job(model)
                    tc = scripting.make_ball_end_tool_controller(job, 6.0)
                    op = adaptive_isocurve.Create(
                        adaptive_isocurve.OP_NAME, parentJob=job, toolController=tc)
                    op.Base = [(job.Model.Group[0], ["Face1"])]
                    op.ScallopHeight = 0.05  # FreeCAD recomputes it on Cancel
                    doc.saveAs(%r)
                except Exception:
                    traceback.print_exc()
                os._exit(0)
                """
                % (
                    os.environ.get("ISOCAM_ADDON_DIR", ""),
                    os.path.join(gui.DATA_DIR, "MAT.brep"),
                    path,
                )
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
    if not os.path.isfile(path):
        raise AssertionError("freecadcmd did not save %s" % path)


if __name__ == "__main__":
    unittest.main()
