"""Commands for IsoCAM's operations and their place in the Path (CAM) workbench.

:func:`install` (called by InitGui.py at start-up) registers one command per
available row of freecad_ext.operations, the preferences page, and the hooks
that put the commands into the Path workbench:

* FreeCAD 0.21+ (``FreeCADGui.addWorkbenchManipulator``): a manipulator adds
  them to the workbench's "New Operations" toolbar and after its Adaptive
  entry in the menu.
* FreeCAD 0.20 has no such hook: when the main window reports the Path
  workbench activated (its ``workbenchActivated`` signal), an "IsoCAM"
  toolbar and a "&Path > IsoCAM" menu are appended to that workbench once and
  the workbench is reloaded.

Either way the operation modules are imported at that moment, which
registers them with the SetupSheet (Job templates then carry their defaults).
A document observer gives our view provider to operations that lack one
(made by a script, or saved without a GUI) so they show our icon and panel.
"""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from freecad_ext import compat, operations, preferences
from freecad_ext.compat import translate

log = compat.logger(__name__)

TOOLBAR = "IsoCAM"
SUBMENU = "IsoCAM"
# FreeCAD's commands our menu entries follow (only one exists per version).
MENU_ANCHORS = ("Path_Adaptive", "CAM_Adaptive")
OPERATIONS_TOOLBAR = "New Operations"

_registered = []  # rows with a command, in table order
_observer = None


# -- the command ------------------------------------------------------------------


class OperationCommand:
    """Make an operation of one row in the active Job and open its panel."""

    def __init__(self, spec):
        self.spec = spec

    def GetResources(self):
        return {
            "Pixmap": operations.icon_path(self.spec),
            "MenuText": self.spec.menu_text,
            "ToolTip": self.spec.tooltip,
        }

    def IsActive(self):
        doc = FreeCAD.ActiveDocument
        return doc is not None and bool(_jobs(doc))

    def Activated(self):
        return create_operation(self.spec)


def _jobs(doc):
    job_class = compat.PathJob.ObjectJob
    return [o for o in doc.Objects if isinstance(getattr(o, "Proxy", None), job_class)]


def _tell_user(text):
    """Report view plus a message box, as FreeCAD's own op commands do."""
    log.error(text)
    QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), "IsoCAM", text)


def _choose_job(doc):
    jobs = _jobs(doc)
    if len(jobs) == 1:
        return jobs[0]
    for sel in FreeCADGui.Selection.getSelection():
        if sel in jobs:
            return sel
        parent = compat.PathUtils.findParentJob(sel)
        if parent in jobs:
            return parent
        owners = [job for job in jobs if sel in job.Model.Group]
        if len(owners) == 1:
            return owners[0]
    return compat.gui().UtilsGui.PathUtilsUserInput().chooseJob(jobs)


def _supports(spec, tc):
    """Whether the row's rules accept `tc`'s tool (before the op exists)."""
    if ("ball_end",) in spec.rules:
        return compat.is_ball_end(tc.Tool)
    if ("flat_end",) in spec.rules:
        return compat.is_flat_bottomed(tc.Tool)
    return True


def _choose_tool_controller(spec, job):
    """The one picked in the tree, else the previous op's (FreeCAD's habit)
    if it fits, else the only fitting one, else the user's choice."""
    controllers = list(job.Tools.Group)
    for sel in FreeCADGui.Selection.getSelection():
        if sel in controllers:
            FreeCADGui.Selection.removeSelection(sel)  # keep only the faces
            return sel
    fitting = [tc for tc in controllers if _supports(spec, tc)]
    ops = job.Operations.Group
    if ops:
        previous = compat.PathUtil.toolControllerForOp(ops[-1])
        if previous in fitting:
            return previous
    if len(fitting) == 1:
        return fitting[0]
    if not fitting:
        return None
    return compat.gui().UtilsGui.PathUtilsUserInput().chooseToolController(fitting)


BALL_END_OFFER = "IsoCAMBallEndOffer"  # the dialog's objectName
DEFAULT_BALL_DIAMETER = 6.0  # mm


def _offer_ball_end_tool_controller(spec, job):
    """A Job with no ball-end tool (a new Job has only FreeCAD's 5 mm end
    mill): offer to add a ball-end tool controller, diameter asked. Returns
    the new tool controller, or None if the user declines."""
    dialog = QtGui.QInputDialog(FreeCADGui.getMainWindow())
    dialog.setObjectName(BALL_END_OFFER)
    dialog.setWindowTitle("IsoCAM")
    dialog.setInputMode(QtGui.QInputDialog.DoubleInput)
    dialog.setLabelText(
        "%s needs a ball-end tool and Job '%s' has none.\n"
        "Add a ball-end tool controller of diameter (mm):" % (spec.menu_text, job.Label)
    )
    dialog.setDoubleDecimals(3)
    dialog.setDoubleRange(0.1, 100.0)
    dialog.setDoubleValue(DEFAULT_BALL_DIAMETER)
    dialog.setOkButtonText("Add tool controller")
    run = getattr(dialog, "exec", None) or dialog.exec_  # PySide6 / PySide2
    if run() != QtGui.QDialog.Accepted:
        return None
    diameter = dialog.doubleValue()
    from freecad_ext import scripting

    doc = job.Document
    doc.openTransaction("Add ball-end tool controller")
    try:
        tc = scripting.make_ball_end_tool_controller(job, diameter)
    except Exception as exc:
        doc.abortTransaction()
        _tell_user(translate("IsoCAM", "the ball-end tool controller could not be added: %s") % exc)
        return None
    doc.commitTransaction()
    doc.recompute()
    return tc


def create_operation(spec):
    """What the command does; returns the new op or None."""
    doc = FreeCAD.ActiveDocument
    job = _choose_job(doc)
    if job is None:
        return None
    tc = _choose_tool_controller(spec, job)
    if tc is None and ("ball_end",) in spec.rules:
        tc = _offer_ball_end_tool_controller(spec, job)
        if tc is None:
            log.notice(
                translate("IsoCAM", "%s not created: Job '%s' has no ball-end tool.")
                % (spec.menu_text, job.Label)
            )
            return None
    if tc is None:
        if ("ball_end",) in spec.rules:
            needs = translate("IsoCAM", "a ball-end tool")
        elif ("flat_end",) in spec.rules:
            needs = translate("IsoCAM", "a flat-end or bull-nose tool")
        else:
            needs = translate("IsoCAM", "a tool")
        _tell_user(
            translate(
                "IsoCAM",
                "%s: Job '%s' has no tool controller with %s. Add one (Path > "
                "ToolBit Library editor) and try again.",
            )
            % (spec.menu_text, job.Label, needs)
        )
        return None
    module = spec.import_module()
    doc.openTransaction("Create %s" % spec.menu_text)
    try:
        obj = module.Create(getattr(module, "OP_NAME", spec.name), parentJob=job, toolController=tc)
        preferences.apply_defaults(
            obj, getattr(module, "OP_NAME", spec.name), module.SetupProperties(), job
        )
        from freecad_ext.gui import view_provider

        view_provider.attach(obj, spec, delete_on_reject=True)
        obj.ViewObject.Visibility = True
    except Exception as exc:
        doc.abortTransaction()
        _tell_user(translate("IsoCAM", "%s could not be created: %s") % (spec.menu_text, exc))
        return None
    doc.commitTransaction()
    obj.ViewObject.Document.setEdit(obj.ViewObject, 0)
    return obj


# -- the Path workbench ----------------------------------------------------------


class _Manipulator:
    """FreeCAD 0.21+: put the commands into the Path (CAM) workbench only;
    the anchors exist there and nowhere else."""

    def modifyToolBars(self):
        return [{"append": spec.command, "toolBar": OPERATIONS_TOOLBAR} for spec in _registered]

    def modifyMenuBar(self):
        items = []
        for anchor in MENU_ANCHORS:
            for spec in reversed(_registered):  # each goes right after anchor
                items.append({"insert": spec.command, "menuItem": anchor, "after": ""})
        return items


def _import_operations():
    """Import the rows' modules: each registers with the SetupSheet."""
    for spec in _registered:
        try:
            spec.import_module()
        except Exception as exc:  # a broken op must not break the others
            log.error(translate("IsoCAM", "cannot load %s: %s") % (spec.module, exc))


def _add_to_workbench(name):
    """FreeCAD 0.20: append our toolbar and submenu to the workbench once."""
    workbench = FreeCADGui.getWorkbench(name)
    if TOOLBAR in workbench.listToolbars():
        return
    commands = [spec.command for spec in _registered]
    menus = workbench.listMenus()
    main_menu = next((m for m in ("&Path", "&CAM") if m in menus), "&Path")
    workbench.appendToolbar(TOOLBAR, commands)
    workbench.appendMenu([main_menu, SUBMENU], commands)
    workbench.reloadActive()


def _on_workbench_activated(name):
    if name not in compat.PATH_WORKBENCHES:
        return
    # Not inside the signal: reloading the workbench activates it again.
    QtCore.QTimer.singleShot(0, lambda: _path_workbench_active(name))


def _path_workbench_active(name):
    _import_operations()
    if not hasattr(FreeCADGui, "addWorkbenchManipulator"):
        if _active_workbench_name() == name:
            _add_to_workbench(name)


# -- view providers for ops that have none ------------------------------------------


class _DocumentObserver:
    """Attach our view provider where an op has none (see module docstring).
    Deferred to the event loop: never in the middle of a restore or a
    Create(). FreeCAD 0.20 tells Python observers of a finished restore only
    through the document's activation, which follows it."""

    def slotChangedObject(self, obj, prop):
        if prop == "Proxy" and not obj.Document.Restoring:
            QtCore.QTimer.singleShot(0, lambda: _attach_missing([obj]))

    def slotActivateDocument(self, doc):
        name = doc.Name  # the document may be closed before the timer fires
        QtCore.QTimer.singleShot(0, lambda: _attach_missing_in(name))

    slotFinishRestoreDocument = slotActivateDocument


def _attach_missing_in(doc_name):
    doc = FreeCAD.listDocuments().get(doc_name)
    if doc is not None:
        _attach_missing(doc.Objects)


def _attach_missing(objects):
    from freecad_ext.gui import view_provider

    for obj in objects:
        try:
            spec = view_provider.needs_view_provider(obj)
        except (ReferenceError, RuntimeError):  # deleted meanwhile
            continue
        if spec is not None:
            view_provider.attach(obj, spec)


# -- start-up -------------------------------------------------------------------------


def install():
    """Register everything (InitGui.py). Cheap: nothing of Path is imported."""
    global _observer
    for spec in operations.available():
        if spec.command not in FreeCADGui.listCommands():
            FreeCADGui.addCommand(spec.command, OperationCommand(spec))
        if spec not in _registered:
            _registered.append(spec)

    from freecad_ext.gui import preferences_page

    FreeCADGui.addPreferencePage(preferences_page.PreferencesPage, compat.preference_group())
    if hasattr(FreeCADGui, "addWorkbenchManipulator"):
        FreeCADGui.addWorkbenchManipulator(_Manipulator())
    if _observer is None:
        _observer = _DocumentObserver()
        FreeCAD.addDocumentObserver(_observer)
    _connect_main_window()


def _connect_main_window():
    window = FreeCADGui.getMainWindow()
    if window is None:  # too early: try again from the event loop
        QtCore.QTimer.singleShot(0, _connect_main_window)
        return
    window.workbenchActivated.connect(_on_workbench_activated)
    name = _active_workbench_name()
    if name in compat.PATH_WORKBENCHES:
        _on_workbench_activated(name)


def _active_workbench_name():
    try:
        return FreeCADGui.activeWorkbench().name()
    except Exception:  # "No active workbench" during start-up
        return ""


def registered():
    """The rows that have a command in this session."""
    return tuple(_registered)
