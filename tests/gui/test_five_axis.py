"""5-Axis Strip Finish in the real FreeCAD GUI (run under Xvfb by
run_gui_test.sh), as for the other ops: the command makes the op with a
flat-end tool controller of the Job (not the ball end the previous op used),
its task panel names a ball-end tool as the problem while the inputs are
edited, OK computes and the posted commands carry the rotary words, the
reopened panel lists the outputs, and Cancel on a new op leaves the document
as it was.

The model: a 10 x 10 box top tilted by 15 degrees about X (a few strips of
FreeCAD's 5 mm flat end at a 0.05 mm scallop, computed in well under a second).
"""

import unittest

import FreeCAD
import FreeCADGui
import Part
from PySide import QtGui

import gui_support as gui
from freecad_ext import adaptive_isocurve, compat, five_axis_finish, op_base, scripting
from freecad_ext.gui import progress as gui_progress

COMMAND = "IsoCAM_FiveAxisStripFinish"
COMPUTE_TIMEOUT = 120.0  # s: the job takes well under a second alone
SCALLOP = 0.05  # mm


def _model():
    box = Part.makeBox(10, 10, 6, FreeCAD.Vector(-5, -5, -6))
    box.rotate(FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(1, 0, 0), 15)
    return box


def _ops(doc):
    return gui.ops_of(doc, five_axis_finish.ObjectFiveAxisStripFinish)


class FiveAxis(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.show_after = gui_progress.SHOW_AFTER
        gui_progress.SHOW_AFTER = 0.0
        gui.open_path_workbench(COMMAND)
        cls.doc = doc = FreeCAD.newDocument("IsoCAMFiveAxis")
        model = doc.addObject("Part::Feature", "Tilted")
        model.Shape = _model()
        cls.job = scripting.make_job(model)
        # FreeCAD's default end mill (5 mm), the Job's one flat end: two
        # would make the command ask which (FreeCAD's tool controller chooser).
        cls.flat_tc = cls.job.Tools.Group[0]
        assert compat.is_flat_end(cls.flat_tc.Tool)
        cls.ball_tc = scripting.make_ball_end_tool_controller(cls.job, 6.0)
        doc.recompute()
        cls.clone = cls.job.Model.Group[0]
        cls.top = "Face%d" % (
            1 + max(range(len(cls.clone.Shape.Faces)), key=lambda i: _centre_z(cls.clone, i))
        )
        # The Job's last op is a ball-end finish: FreeCAD's habit would take
        # its tool controller for the next op, which does not fit this one.
        cls.ball_op = adaptive_isocurve.Create(
            adaptive_isocurve.OP_NAME, parentJob=cls.job, toolController=cls.ball_tc
        )
        cls.ball_op.Base = [(cls.clone, [cls.top])]
        cls.ball_op.ScallopHeight = 0.05
        doc.recompute()
        gui.settle(doc)

    @classmethod
    def tearDownClass(cls):
        gui_progress.SHOW_AFTER = cls.show_after
        if FreeCADGui.Control.activeDialog():
            FreeCADGui.Control.closeDialog()
        FreeCAD.closeDocument(cls.doc.Name)

    def run_command(self, *selected):
        """Pick `selected` (document objects, or (object, sub) pairs), run
        the command, return the new op and its page."""
        FreeCAD.setActiveDocument(self.doc.Name)
        FreeCADGui.Selection.clearSelection()
        for item in selected:
            if isinstance(item, tuple):
                FreeCADGui.Selection.addSelection(self.doc.Name, item[0].Name, item[1])
            else:
                FreeCADGui.Selection.addSelection(self.doc.Name, item.Name)
        known = {o.Name for o in _ops(self.doc)}
        gui.trigger(gui.toolbar_action(gui.isocam_toolbar(), COMMAND))
        gui.wait_until(lambda: gui.task_button(QtGui.QDialogButtonBox.Ok), 20, "the task panel")
        (op,) = [o for o in _ops(self.doc) if o.Name not in known]
        return op, op.ViewObject.Proxy.panel.op_page

    def close_panel(self, which):
        gui.click(gui.task_button(which))
        gui.wait_until(
            lambda: not FreeCADGui.Control.activeDialog(), COMPUTE_TIMEOUT, "the panel to close"
        )

    def test_1_ball_end_picked_is_named_and_cancel_leaves_nothing(self):
        before = gui.snapshot(self.doc)
        op, page = self.run_command(self.ball_tc, (self.clone, self.top))
        self.assertIs(op.ToolController, self.ball_tc)
        self.assertTrue(
            any("needs a flat-end or bull-nose tool" in m for m in page.messages), page.messages
        )
        self.assertTrue(any(self.ball_tc.Label in m for m in page.messages), page.messages)
        gui.screenshot("five-axis-ball-end-panel")
        self.close_panel(QtGui.QDialogButtonBox.Cancel)
        self.assertEqual(_ops(self.doc), [])
        self.assertEqual(gui.snapshot_changes(gui.snapshot(self.doc), before), [])

    def test_2_ok_computes_rotary_moves_and_the_panel_lists_the_outputs(self):
        op, page = self.run_command((self.clone, self.top))
        # Not the previous op's ball end: the Job's flat end.
        self.assertIs(op.ToolController, self.flat_tc)
        self.assertEqual(page.messages, [])
        gui.type_text(page.form.ScallopHeight, "%g mm" % SCALLOP)
        self.assertEqual(page.messages, [])
        self.close_panel(QtGui.QDialogButtonBox.Ok)
        self.assertNotIn("Invalid", op.State, op.getStatusString())
        self.assertAlmostEqual(op.ScallopHeight.Value, SCALLOP)
        moves = [c for c in op.Path.Commands if c.Name in ("G0", "G1")]
        # Every fed move of a pass on the tilted top carries A; the top
        # leans 15 degrees, so the tool is tilted by about that, with the
        # lead of LeadAngle on top.
        fed = [c for c in moves if c.Name == "G1" and "A" in c.Parameters]
        self.assertTrue(fed, "no fed move with an A word")
        tilts = [c.Parameters["A"] for c in fed]
        self.assertGreater(min(tilts), 15.0 - op.LeadAngle.Value - 1e-6)
        self.assertLess(max(tilts), 15.0 + op.MaxLeadAngle.Value + 1e-6)
        self.assertTrue(all("C" in c.Parameters for c in fed))
        self.assertGreater(op.CuttingLength.Value, 0.0)
        self.assertLessEqual(op.GuaranteedScallop.Value, SCALLOP * (1 + 1e-9))
        # Reopened, the panel lists every output with its value.
        FreeCADGui.ActiveDocument.setEdit(op.Name)
        gui.wait_until(FreeCADGui.Control.activeDialog, 20, "the task panel")
        text = op.ViewObject.Proxy.panel.op_page.form.findChild(QtGui.QLabel, "certificate").text()
        for _type, name, _attr, _tip in op.Proxy.OUTPUTS:
            self.assertEqual(op.getGroupOfProperty(name), op_base.OUTPUT_GROUP)
            self.assertIn("<td>%s</td>" % name, text)
        gui.screenshot("five-axis-panel-with-outputs")
        self.close_panel(QtGui.QDialogButtonBox.Cancel)


def _centre_z(obj, i):
    return obj.Shape.Faces[i].CenterOfMass.z


if __name__ == "__main__":
    unittest.main()
