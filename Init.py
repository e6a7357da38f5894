# IsoCAM start-up hook: FreeCAD runs it in console and GUI mode alike, with
# this addon's folder on sys.path (that is how `freecad_ext` and the compiled
# `isocam_core` next to it become importable).
#
# Kept thin: nothing is imported here. freecad_ext.adaptive_isocurve registers
# the operation with the Path SetupSheet when it is first imported.
import FreeCAD

FreeCAD.Console.PrintLog("IsoCAM: addon loaded (console)\n")
