"""package.xml as FreeCAD and its Addon Manager read it.

FreeCAD runs a package's Init.py and InitGui.py only for the <workbench>
items of its package.xml (FreeCAD 0.20.2 skips the folder otherwise), so
IsoCAM, which adds commands to the Path workbench and has no workbench of
its own, still needs one, pointing at the package's own folder.
"""

import os
import unittest
import xml.etree.ElementTree as ET

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
NS = {"p": "https://wiki.freecad.org/Package_Metadata"}


class PackageXml(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.root = ET.parse(os.path.join(ROOT, "package.xml")).getroot()

    def text(self, path, node=None):
        found = (node if node is not None else self.root).find(path, NS)
        return None if found is None else found.text

    def test_fields_the_addon_manager_shows(self):
        self.assertEqual(self.root.get("format"), "1")
        self.assertEqual(self.text("p:name"), "IsoCAM")
        for field in ("p:description", "p:version", "p:date", "p:maintainer"):
            self.assertTrue(self.text(field), field)
        license_ = self.root.find("p:license", NS)
        self.assertTrue(os.path.isfile(os.path.join(ROOT, license_.get("file"))))
        self.assertTrue(os.path.isfile(os.path.join(ROOT, self.text("p:icon"))))
        # The FreeCAD versions ./run test covers: 0.20.2, 1.0, 1.1.
        self.assertEqual(self.text("p:freecadmin"), "0.20.2")
        self.assertEqual(self.text("p:freecadmax"), "1.1.99")
        depends = [(d.get("type"), d.text) for d in self.root.findall("p:depend", NS)]
        self.assertIn(("python", "numpy"), depends)

    def test_one_workbench_item_in_the_package_folder(self):
        items = self.root.findall("p:content/p:workbench", NS)
        self.assertEqual(len(items), 1)
        item = items[0]
        self.assertEqual(self.text("p:subdirectory", item), "./")
        for entry in ("Init.py", "InitGui.py"):
            self.assertTrue(os.path.isfile(os.path.join(ROOT, entry)), entry)
        self.assertTrue(os.path.isfile(os.path.join(ROOT, self.text("p:icon", item))))


if __name__ == "__main__":
    unittest.main()
