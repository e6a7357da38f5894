"""IsoCAM's FreeCAD GUI: commands in the Path (CAM) workbench, view providers,
task panels, progress with cancel and the preferences page.

Imported only when FreeCAD's GUI is up (InitGui.py). Everything version
dependent comes from :mod:`freecad_ext.compat`; everything operation specific
from the table in :mod:`freecad_ext.operations`.
"""
