"""The pocketing ops in the real FreeCAD GUI (run under Xvfb by
run_gui_test.sh), as the user guide promises for every op: OK computes with
IsoCAM's progress dialog, its Cancel stops the computation and leaves the
document as it was with the panel open, and the panel lists the op's
read-only outputs once computed.

The model: a 120 x 80 x 20 block with a 100 x 60 pocket 10 mm deep and a round
island standing in it; Spiral Pocket on the pocket floor with a 6 mm end mill.
"""

import unittest

import FreeCAD
import FreeCADGui
import Part
from PySide import QtGui

import gui_support as gui
from freecad_ext import op_base, scripting, spiral_pocket
from freecad_ext.gui import progress as gui_progress

COMMAND = "IsoCAM_SpiralPocket"
FLOOR_Z = 10.0
COMPUTE_TIMEOUT = 120.0  # s
# StepOver (%) and StepDown (mm). The dialog is made to show at the first
# poll (SHOW_AFTER 0 while these tests run), so whether it is seen does not
# depend on the machine's speed as long as the computation outlasts the
# watcher's first look (0.2 s): QUICK is 100 levels (0.5-2 s here), LONG 400
# levels, still running when the watcher presses Cancel.
QUICK = (5, 0.1)
LONG = (2, 0.025)


def _model():
    body = Part.makeBox(120, 80, 20).cut(Part.makeBox(100, 60, 10, FreeCAD.Vector(10, 10, FLOOR_Z)))
    return body.fuse(Part.makeCylinder(8, 10, FreeCAD.Vector(40, 35, FLOOR_Z))).removeSplitter()


def _ops(doc):
    return gui.ops_of(doc, spiral_pocket.ObjectSpiralPocket)


class Pocketing(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.show_after = gui_progress.SHOW_AFTER
        gui_progress.SHOW_AFTER = 0.0
        gui.open_path_workbench(COMMAND)
        cls.doc = FreeCAD.newDocument("IsoCAMPocketing")
        model = cls.doc.addObject("Part::Feature", "Block")
        model.Shape = _model()
        cls.job = scripting.make_job(model)
        cls.tc = scripting.make_tool_controller(cls.job, "endmill.fcstd", 6.0)
        cls.doc.recompute()
        clone = cls.job.Model.Group[0]
        floor = next(
            i
            for i, f in enumerate(clone.Shape.Faces)
            if abs(f.BoundBox.ZMin - FLOOR_Z) < 1e-6 and abs(f.BoundBox.ZMax - FLOOR_Z) < 1e-6
        )
        # The tool controller picked in the tree, the floor in the 3D view.
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(cls.doc.Name, cls.tc.Name)
        FreeCADGui.Selection.addSelection(cls.doc.Name, clone.Name, "Face%d" % (floor + 1))
        gui.trigger(gui.toolbar_action(gui.isocam_toolbar(), COMMAND))
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Ok), 20, "the task panel")
        (cls.op,) = _ops(cls.doc)

    @classmethod
    def tearDownClass(cls):
        gui_progress.SHOW_AFTER = cls.show_after
        if FreeCADGui.Control.activeDialog():
            FreeCADGui.Control.closeDialog()
        FreeCAD.closeDocument(cls.doc.Name)

    def page(self):
        return self.op.ViewObject.Proxy.panel.op_page

    def label(self, name):
        return self.page().form.findChild(QtGui.QLabel, name).text()

    def set_inputs(self, step_over, step_down):
        """As if typed: the properties, then every page of the open panel
        shows them (its OK writes the pages' fields back)."""
        # FreeCAD binds StepDown to the SetupSheet's expression (the tool
        # diameter); a typed value replaces it.
        self.op.setExpression("StepDown", None)
        self.op.StepOver, self.op.StepDown = step_over, step_down
        self.op.ViewObject.Proxy.panel.panelSetFields()
        self.page().setDirty()  # as an edit does: FreeCAD enables Apply
        gui.pump(0.1)

    def watch_progress(self, seen, cancel=False):
        """Note the progress dialog's value while it is up; press its
        Cancel the first time if `cancel`. The watch ends with the test."""
        watching = [True]
        self.addCleanup(watching.__setitem__, 0, False)

        def look():
            if not watching[0]:
                return
            modal = QtGui.QApplication.activeModalWidget()
            if modal is not None and gui.is_progress_dialog(modal):
                seen.append(modal.value())
                if cancel:
                    gui.screenshot("pocket-progress-before-cancel")
                    gui.click(gui.button_labelled(modal, "Cancel"))
                    return
            if len(seen) < 3:
                gui.later(0.1, look)

        gui.later(0.2, look)

    def test_1_ok_computes_with_progress_and_the_panel_lists_the_outputs(self):
        page = self.page()
        self.assertIs(self.op.ToolController, self.tc)
        self.assertEqual(page.messages, [])
        self.assertIn("not computed yet", self.label("certificate"))
        self.set_inputs(*QUICK)
        seen = []
        self.watch_progress(seen)
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Ok))
        gui.wait_until(
            lambda: not FreeCADGui.Control.activeDialog(), COMPUTE_TIMEOUT, "the panel to close"
        )
        self.assertNotIn("Invalid", self.op.State, self.op.getStatusString())
        self.assertGreater(self.op.Loops, 0)
        self.assertTrue(seen, "no progress dialog seen while computing")
        # Reopened, the panel lists every output with its value.
        FreeCADGui.ActiveDocument.setEdit(self.op.Name)
        gui.wait_until(FreeCADGui.Control.activeDialog, 20, "the task panel")
        text = self.label("certificate")
        for _type, name, _attr, _tip in self.op.Proxy.OUTPUTS:
            self.assertEqual(self.op.getGroupOfProperty(name), op_base.OUTPUT_GROUP)
            self.assertIn("<td>%s</td>" % name, text)
        self.assertIn("<td>%d</td>" % self.op.Loops, text)
        gui.screenshot("pocket-panel-with-outputs")

    def test_2_cancel_keeps_the_path_and_the_panel_open(self):
        self.assertTrue(FreeCADGui.Control.activeDialog())
        before = gui.snapshot(self.doc)
        loops = self.op.Loops
        self.set_inputs(*LONG)
        seen = []
        self.watch_progress(seen, cancel=True)
        gui.click(gui.task_button(QtGui.QDialogButtonBox.Apply))
        self.assertEqual(len(seen), 1)
        self.assertTrue(FreeCADGui.Control.activeDialog())
        self.assertIn("cancelled", self.label("validation"))
        self.assertEqual(self.op.Path.toGCode(), before[self.op.Name][2])
        self.assertEqual(self.op.Loops, loops)
        self.assertIn("Touched", self.op.State)
        self.assertIn("cancelled by the user", gui.report_view_text())
        gui.task_button(QtGui.QDialogButtonBox.Cancel).click()
        gui.wait_until(lambda: not FreeCADGui.Control.activeDialog(), 20, "the panel to close")


if __name__ == "__main__":
    unittest.main()
