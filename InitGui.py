# IsoCAM GUI start-up hook. IsoCAM extends FreeCAD's Path workbench and
# defines no workbench of its own; its commands are added by a later change.
import FreeCAD

FreeCAD.Console.PrintLog("IsoCAM: addon loaded (GUI)\n")
