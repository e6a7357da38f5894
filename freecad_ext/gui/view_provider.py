"""View provider and selection gates of IsoCAM operations.

FreeCAD's Path ViewProvider (compat.gui().OpGui.ViewProvider) finds the icon
in FreeCAD's own resources and the selection gate in PathSelection's table of
FreeCAD's operations, which raises on names it does not know. Ours takes both
from the operation's row (freecad_ext.operations) and saves only the row's
name with the document, so a file opens wherever IsoCAM is installed.
"""

import FreeCADGui

from freecad_ext import compat, operations
from freecad_ext.compat import translate

log = compat.logger(__name__)

_base = compat.gui().OpGui


# -- selection gates ----------------------------------------------------------


class FaceGate:
    """Lets faces through; with `floor_only`, planar faces facing +Z only."""

    FLOOR_TOLERANCE = 1e-6  # on the z component of the unit normal

    def __init__(self, floor_only=False):
        self.floor_only = floor_only

    def allow(self, doc, obj, sub):
        if not sub or not sub.startswith("Face"):
            return False
        if not self.floor_only:
            return True
        try:
            face = obj.Shape.getElement(sub)
        except Exception:  # not a shape, or a stale name
            return False
        return is_floor(face, self.FLOOR_TOLERANCE)


def is_floor(face, tolerance):
    """True for a planar face whose outward normal points up (+Z)."""
    if face.Surface.__class__.__name__ != "Plane":
        return False
    u0, u1, v0, v1 = face.ParameterRange
    normal = face.normalAt(0.5 * (u0 + u1), 0.5 * (v0 + v1))
    return normal.z > 1.0 - tolerance


GATES = {
    operations.FACES: lambda: FaceGate(floor_only=False),
    operations.FLOOR_FACES: lambda: FaceGate(floor_only=True),
}


def selection_factory(spec):
    """A function that installs the row's gate (what PathSelection.select
    returns for FreeCAD's own operations); the task panel removes it."""

    def install():
        FreeCADGui.Selection.addSelectionGate(GATES[spec.selection]())

    return install


# -- view provider ------------------------------------------------------------


class ViewProvider(_base.ViewProvider):
    """Icon, selection gate and task panel of one IsoCAM operation."""

    def __init__(self, vobj, spec, delete_on_reject=False):
        # FreeCAD's __init__ wants its CommandResources; set what it sets.
        self.deleteOnReject = delete_on_reject
        self.OpName = spec.name
        self.vobj = vobj
        self.Object = None
        self.panel = None

    @property
    def spec(self):
        return operations.spec_named(self.OpName)

    @property
    def OpIcon(self):
        # Looked up at run time: a saved path would break on other machines.
        spec = self.spec
        return operations.icon_path(spec) if spec else operations.GENERIC_ICON

    # Saved with the document: the row's name only. FreeCAD 0.20 pickles
    # through __getstate__, 1.0 calls dumps/loads.
    def __getstate__(self):
        return {"Operation": self.OpName}

    def __setstate__(self, state):
        self.OpName = state.get("Operation") or state.get("OpName")
        self.deleteOnReject = False
        self.vobj = self.Object = self.panel = None

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)

    def getIcon(self):
        if self.Object is not None and not getattr(self.Object, "Active", True):
            return ":/icons/%s.svg" % compat.path_command("OpActive")
        return self.OpIcon

    def getTaskPanelOpPage(self, obj):
        from freecad_ext.gui import task_panel

        return task_panel.OperationPage(obj, 0, self.spec)

    def getSelectionFactory(self):
        return selection_factory(self.spec)

    def setupTaskPanel(self, panel):
        """FreeCAD's, minus its assumption that the Job has FreeCAD's view
        provider (a Job made without a GUI has none)."""
        self.panel = panel
        FreeCADGui.Control.closeDialog()
        FreeCADGui.Control.showDialog(panel)
        panel.setupUi()
        self._job_visibility("setupEditVisibility")

    def clearTaskPanel(self):
        self.panel = None
        self._job_visibility("resetEditVisibility")

    def _job_visibility(self, method):
        """Let the Job show what editing needs (model, no stock), if it can."""
        job = self.Object.Proxy.getJob(self.Object) if self.Object else None
        job_vp = getattr(getattr(job, "ViewObject", None), "Proxy", None)
        if hasattr(job_vp, method):
            getattr(job_vp, method)(job)

    def setEdit(self, vobj=None, mode=0):
        """Open the task panel (FreeCAD's own, with our operation page and
        our cancel handling); other edit modes are FreeCAD's."""
        if mode != 0:
            return False
        from freecad_ext.gui import task_panel

        vobj = vobj or self.vobj
        spec = self.spec
        if spec is None:
            log.error(translate("IsoCAM", "no operation named %s is installed") % self.OpName)
            return False
        page = self.getTaskPanelOpPage(vobj.Object)
        page.setTitle(spec.menu_text)
        page.setIcon(self.OpIcon)
        panel = task_panel.TaskPanel(
            vobj.Object, self.deleteObjectsOnReject(), page, self.getSelectionFactory()
        )
        try:
            self.setupTaskPanel(panel)
        except Exception as error:  # whatever failed, no half-open panel
            self._abandon(panel, vobj.Object, error)
            return False
        self.deleteOnReject = False
        return True

    def _abandon(self, panel, obj, error):
        """A panel that failed while it was set up: undone as its Cancel
        does (the document as before; a just-created op removed), closed,
        and the reason in the report view."""
        label = obj.Label
        log.error(
            translate("IsoCAM", "%s: the task panel could not be opened: %s")
            % (label, "%s: %s" % (type(error).__name__, error))
        )
        try:
            panel.reject(resetEdit=False)
        except Exception as second:  # closed below whatever happens
            log.debug("closing the failed panel: %s" % second)
        if FreeCADGui.Control.activeDialog():
            FreeCADGui.Control.closeDialog()
        self.panel = None


def attach(obj, spec, delete_on_reject=False):
    """Give `obj` (an op of row `spec`) our view provider."""
    vobj = obj.ViewObject
    if vobj is None:
        return None
    proxy = ViewProvider(vobj, spec, delete_on_reject)
    vobj.Proxy = proxy
    if proxy.Object is None:
        # FreeCAD calls attach() only for the first proxy a view object
        # gets; one restored without a proxy already had its turn.
        proxy.attach(vobj)
    return proxy


def needs_view_provider(obj):
    """The row of an IsoCAM op in the GUI that lacks our view provider (it
    was made by a script, or saved without a GUI), else None."""
    spec = operations.spec_for_proxy(getattr(obj, "Proxy", None))
    if spec is None:
        return None
    vobj = getattr(obj, "ViewObject", None)
    if vobj is None or isinstance(vobj.Proxy, ViewProvider):
        return None
    return spec
