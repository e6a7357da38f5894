"""A document saved by an earlier IsoCAM still opens: tests/data/previous_ops.FCStd
(the three ops, saved by IsoCAM d6ed807 on FreeCAD 0.20.2, before the op base
read the properties from definitions; make_previous_document.py wrote it and
previous_ops.json, which lists what each op held).

Every property the current ops define must be in the old document with the
same type (those defined since, ADDED_SINCE, are added on restore), the user's values must be as saved, the outputs end up in the one
output group the task panel shows, and the ops recompute.

Run: tests/freecad/run_in_freecad.sh tests/freecad/test_previous_document.py
"""

import json
import os
import shutil
import tempfile
import unittest

import FreeCAD

import fc_test_support as support
from freecad_ext import adaptive_isocurve, compat, op_base, spiral_pocket, zlevel_roughing

NAME = "previous_ops"
PROXIES = {
    "ObjectAdaptiveIsocurve": adaptive_isocurve.ObjectAdaptiveIsocurve,
    "ObjectSpiralPocket": spiral_pocket.ObjectSpiralPocket,
    "ObjectZLevelRoughing": zlevel_roughing.ObjectZLevelRoughing,
}
# Quantities read back from the file: FreeCAD writes them with 15 or more
# significant digits, so they come back within a few ulps.
VALUE_TOL = 1e-9
# Properties defined since the file was saved: restoring must add them (with
# their type); every other property must have been in the file already.
ADDED_SINCE = {"AdaptiveIsocurve": {"UnreachableFromAboveLength"}}


class PreviousDocumentTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(os.path.join(support.DATA_DIR, NAME + ".json")) as text:
            cls.record = json.load(text)
        cls.tmp = tempfile.mkdtemp(prefix="isocam-")
        path = os.path.join(cls.tmp, NAME + ".FCStd")
        shutil.copy(os.path.join(support.DATA_DIR, NAME + ".FCStd"), path)
        cls.doc = FreeCAD.openDocument(path)

    @classmethod
    def tearDownClass(cls):
        FreeCAD.closeDocument(cls.doc.Name)
        shutil.rmtree(cls.tmp, True)

    def ops(self):
        for name, saved in sorted(self.record["ops"].items()):
            op = self.doc.getObject(name)
            self.assertIsNotNone(op, name)
            yield op, saved

    def test_the_ops_restore_with_their_proxies(self):
        for op, saved in self.ops():
            self.assertIsInstance(op.Proxy, PROXIES[saved["proxy"]], op.Name)

    def test_every_current_property_was_in_the_old_document_with_its_type(self):
        for op, saved in self.ops():
            old = saved["properties"]
            defined = [row[:2] for row in op.Proxy.opPropertyDefinitions()]
            defined += [(row[0], row[1]) for row in op.Proxy.OUTPUTS]
            self.assertGreater(len(defined), 8)
            added = ADDED_SINCE.get(op.Name, set())
            for prop_type, name in defined:
                self.assertEqual(op.getTypeIdOfProperty(name), prop_type, "%s.%s" % (op.Name, name))
                if name in added:
                    self.assertNotIn(name, old, "%s.%s was not new" % (op.Name, name))
                    continue
                self.assertIn(name, old, "%s.%s is new" % (op.Name, name))
                self.assertEqual(old[name][0], prop_type, "%s.%s" % (op.Name, name))

    def test_the_users_values_are_as_saved(self):
        outputs = {row[1] for op, _ in self.ops() for row in op.Proxy.OUTPUTS}
        # FreeCAD's own output: test_the_ops_recompute (run before this test)
        # sets it from the path the current core computes.
        outputs.add("CycleTime")
        checked = 0
        for op, saved in self.ops():
            for name, (prop_type, _group, value) in saved["properties"].items():
                if name in outputs or value is None or not hasattr(op, name):
                    continue
                now = getattr(op, name)
                now = now.Value if hasattr(now, "Value") else now
                if isinstance(value, float):
                    self.assertAlmostEqual(now, value, delta=VALUE_TOL, msg=name)
                else:
                    self.assertEqual(now, value, "%s.%s" % (op.Name, name))
                checked += 1
        self.assertGreater(checked, 40)
        # The values the generator changed from the defaults among them.
        iso = self.doc.getObject("AdaptiveIsocurve")
        self.assertEqual((iso.Direction, iso.ScallopBound), ("U", "Flat"))
        self.assertAlmostEqual(iso.ScallopHeight.Value, 0.1)
        self.assertEqual(self.doc.getObject("SpiralPocket").StepOver, 40)

    def test_outputs_are_read_only_in_the_one_output_group(self):
        for op, saved in self.ops():
            for _type, name, _attr, _tip in op.Proxy.OUTPUTS:
                self.assertEqual(op.getGroupOfProperty(name), op_base.OUTPUT_GROUP, name)
                self.assertEqual(op.getPropertyStatus(name)[:2], ["ReadOnly", "Output"])
        # The pocketing ops kept them in "Result" before.
        self.assertEqual(self.record["ops"]["SpiralPocket"]["properties"]["Loops"][1], "Result")

    @unittest.skipIf(
        compat.version_tuple() >= (0, 21),
        "FreeCAD 0.21+ restores no Job or tool controller of a 0.20 file (their "
        "proxies moved from PathScripts to Path.*); the ops' own data is checked above",
    )
    def test_the_ops_recompute(self):
        for op, _ in self.ops():
            op.touch()
        self.doc.recompute()
        for op, saved in self.ops():
            self.assertNotIn("Invalid", op.State, op.getStatusString())
            self.assertGreater(len(op.Path.Commands), 10)
            self.assertGreater(op.CuttingLength.Value, 0.0)


if __name__ == "__main__":
    unittest.main()
