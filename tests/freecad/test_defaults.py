"""Defaults of new operations: a Job template carries the SetupSheet's
Adaptive Isocurve defaults to a new Job, and the user's preferences fill in
where the SetupSheet has no value (the SetupSheet wins where it has one).

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_defaults.py
"""

import json
import os
import unittest

import FreeCAD

import fc_test_support as support
from freecad_ext import adaptive_isocurve, compat, preferences, scripting

OP = adaptive_isocurve.OP_NAME


def set_sheet_default(job, prop, value):
    """What the SetupSheet editor's "Operation Defaults" page does."""
    sheets = compat.PathSetupSheet
    prototype = sheets._RegisteredOps[OP].prototype(OP)
    prototype.getProperty(prop).setupProperty(
        job.SetupSheet,
        sheets.OpPropertyName(OP, prop),
        sheets.OpPropertyGroup(OP),
        value,
    )


def write_template(job, path):
    """A Job template as FreeCAD 0.20's Path_ExportTemplate writes it
    (PathJobCmd.CommandJobTemplateExport.Execute without its dialog, and
    with the operations that have settings, as the dialog offers them)."""
    sheet = job.Proxy.setupSheet
    attrs = job.Proxy.templateAttrs(job)
    attrs[compat.PathJob.JobTemplate.SetupSheet] = sheet.templateAttributes(
        True, True, True, True, sheet.operationsWithSettings()
    )
    with open(path, "w") as out:
        json.dump(sheet.encodeTemplateAttributes(attrs), out, sort_keys=True, indent=2)


class TemplateCarriesDefaults(unittest.TestCase):
    def test_new_job_from_template_gives_new_ops_the_defaults(self):
        first = support.JobSetup("IsoTemplateA")
        self.addCleanup(first.close)
        set_sheet_default(first.job, "ScallopHeight", 0.05)
        set_sheet_default(first.job, "Direction", "U")
        self.assertIn(OP, first.job.Proxy.setupSheet.operationsWithSettings())
        template = os.path.join(support.temp_dir(self), "job_isocam.json")
        write_template(first.job, template)
        with open(template) as text:
            stored = json.load(text)["SetupSheet"][OP]
        self.assertEqual(stored["Direction"], "U")

        doc = FreeCAD.newDocument("IsoTemplateB")
        self.addCleanup(FreeCAD.closeDocument, doc.Name)
        model = doc.addObject("Part::Feature", "Model")
        model.Shape = support.load_shape("MAT.brep")
        with compat.active_document(doc):
            job = compat.PathJob.Create("Job", [model], template)
        tc = scripting.make_ball_end_tool_controller(job, 6.0)
        op = adaptive_isocurve.Create(OP, parentJob=job, toolController=tc)
        self.assertAlmostEqual(op.ScallopHeight.Value, 0.05)
        self.assertEqual(op.Direction, "U")
        self.assertAlmostEqual(op.ChordTolerance.Value, 0.0)  # built-in: derived


class PreferenceDefaults(unittest.TestCase):
    def setUp(self):
        self.setup = support.JobSetup("IsoPrefs")
        self.addCleanup(self.setup.close)
        self.addCleanup(preferences.group(OP).Clear)
        preferences.store_default(OP, "ChordTolerance", 0.002)
        preferences.store_default(OP, "Direction", "V")
        preferences.store_default(OP, "ScallopHeight", 0.03)

    def new_op(self):
        return adaptive_isocurve.Create(
            OP, parentJob=self.setup.job, toolController=self.setup.ball_tc
        )

    def test_preferences_fill_in_and_the_setup_sheet_wins(self):
        set_sheet_default(self.setup.job, "ScallopHeight", 0.05)
        op = self.new_op()
        applied = preferences.apply_defaults(
            op, OP, adaptive_isocurve.SetupProperties(), self.setup.job
        )
        self.assertEqual(sorted(applied), ["ChordTolerance", "Direction"])
        self.assertAlmostEqual(op.ChordTolerance.Value, 0.002)
        self.assertEqual(op.Direction, "V")
        self.assertAlmostEqual(op.ScallopHeight.Value, 0.05)  # the sheet's

    def test_stored_numbers_take_the_type_of_the_property(self):
        self.assertEqual(preferences._as_type_of(5, 50.0), 50)
        self.assertIsInstance(preferences._as_type_of(5, 50.0), int)
        self.assertIs(preferences._as_type_of(False, 1.0), True)
        self.assertEqual(preferences._as_type_of(0.5, 0.25), 0.25)
        self.assertEqual(preferences._as_type_of("Auto", "V"), "V")

    def test_a_stored_value_the_property_refuses_is_skipped(self):
        preferences.store_default(OP, "Direction", "Diagonal")
        op = self.new_op()
        applied = preferences.apply_defaults(
            op, OP, adaptive_isocurve.SetupProperties(), self.setup.job
        )
        self.assertNotIn("Direction", applied)
        self.assertEqual(op.Direction, "Auto")
        self.assertEqual(preferences.stored_defaults(OP)["Direction"], "Diagonal")


if __name__ == "__main__":
    unittest.main()
