# IsoCAM GUI start-up hook. IsoCAM extends FreeCAD's Path (CAM) workbench and
# defines no workbench of its own: freecad_ext.gui.commands registers one
# command per operation, the preferences page, and the hooks that put the
# commands into the Path workbench when it is activated. Nothing of Path is
# imported here.
import FreeCAD


def _isocam_gui_startup():
    try:
        from freecad_ext.gui import commands

        commands.install()
    except Exception as exc:  # never take FreeCAD's start-up down with us
        FreeCAD.Console.PrintError("IsoCAM: GUI start-up failed: %s\n" % exc)
        return
    FreeCAD.Console.PrintLog("IsoCAM: addon loaded (GUI)\n")


_isocam_gui_startup()
