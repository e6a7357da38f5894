"""Helpers for the GUI tests (a helper, not a test file): waiting while the
event loop runs, typing and clicking like a user, screenshots, dialogs the
test expects, and snapshots of a document to prove what did not change."""

import contextlib
import os
import time

import FreeCAD
import FreeCADGui
import Part
from PySide import QtCore, QtGui

SCREENSHOTS = os.environ.get("ISOCAM_SCREENSHOT_DIR") or os.getcwd()
DATA_DIR = os.environ.get("ISOCAM_TEST_DATA") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "data"
)

from freecad_ext import compat  # noqa: E402  (the runner put the addon on sys.path)

# The Path workbench under this FreeCAD's name (CAMWorkbench from 1.0 on).
PATH_WORKBENCH = compat.workbench_name()

_expected_dialogs = []  # predicates on a modal widget


# -- the event loop -------------------------------------------------------------


def pump(seconds=0.0):
    """Let FreeCAD process events for `seconds` (at least once)."""
    end = time.monotonic() + seconds
    while True:
        QtGui.QApplication.processEvents(QtCore.QEventLoop.AllEvents, 20)
        if time.monotonic() >= end:
            return
        time.sleep(0.01)


def wait_until(predicate, timeout, what):
    """Process events until predicate() is true; fail with a screenshot."""
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            path = screenshot("failure-waiting")
            raise AssertionError(
                "timed out after %g s waiting for %s (screenshot %s)" % (timeout, what, path)
            )
        pump(0.02)


def children(widget, cls):
    """`widget`'s descendants of Qt class `cls`, each checked by the class of
    the live C++ object. PySide's findChildren converts every child to Python
    and matches the wrapper's type; a wrapper left over from an object that
    FreeCAD deleted in C++ (a closed dialog's button box) can stand at the
    address of a new, different object, and a call through it crashed FreeCAD
    (SIGSEGV in QDialogButtonBox::button after a cancelled computation).
    QObject::inherits asks the live object's own meta-object. A child that
    FreeCAD deletes between the listing and that question (the task panel
    closing while we poll) raises RuntimeError and is no longer a child."""
    name = cls.staticMetaObject.className()
    found = []
    for child in widget.findChildren(cls):
        try:
            if child.inherits(name):
                found.append(child)
        except RuntimeError:
            pass
    return found


def later(seconds, function):
    """Run `function` from the event loop after `seconds` (also inside a
    modal dialog's or the progress loop's event processing)."""
    QtCore.QTimer.singleShot(int(seconds * 1000), function)


# -- the window ------------------------------------------------------------------


def prepare_main_window():
    """The main window over the whole screen, its docks shown."""
    window = FreeCADGui.getMainWindow()
    window.showMaximized()
    for name in ("Report view", "Combo View", "Model", "Tasks"):
        dock = window.findChild(QtGui.QDockWidget, name)
        if dock is not None:
            dock.show()
    pump(0.2)
    arrange_window()
    widen_combo_view()


def arrange_window():
    """Undo what FreeCAD 1.1 (Qt 6) does to the window after start-up, before
    each screenshot (idempotent).

    Its screen grabs came out "scaled": the screen is 1600 x 1000 at a device
    pixel ratio of 1 (measured), but 1.1 puts its main window back to 2/3 of
    the screen after the runner maximised it, and under Xvfb no window
    manager maximises it again, so the window filled the top-left 2/3 of a
    black grab. The geometry is set to the screen's. 1.1 also splits 0.20's
    "Combo View" into "Model" and "Tasks" docks and may float "Tasks": it is
    tabbed onto Model, where the Combo View's task tab was."""
    window = FreeCADGui.getMainWindow()
    screen = QtGui.QGuiApplication.primaryScreen().availableGeometry()
    if window.geometry() != screen:
        window.setGeometry(screen)
    model = window.findChild(QtGui.QDockWidget, "Model")
    tasks = window.findChild(QtGui.QDockWidget, "Tasks")
    if model is not None and tasks is not None:
        if tasks.isFloating() or tasks not in window.tabifiedDockWidgets(model):
            tasks.setFloating(False)
            window.addDockWidget(QtCore.Qt.LeftDockWidgetArea, tasks)
            window.tabifyDockWidget(model, tasks)
    pump(0.05)


def show_tasks():
    """FreeCAD 1.1: bring the "Tasks" dock to the front while a task dialog
    is open (up to 1.0 the Combo View switches to its task tab itself)."""
    tasks = FreeCADGui.getMainWindow().findChild(QtGui.QDockWidget, "Tasks")
    if tasks is not None and FreeCADGui.Control.activeDialog():
        arrange_window()
        tasks.show()
        tasks.raise_()


def widen_combo_view(width=440):
    """Room for the task panels (workbench switches may narrow it again)."""
    show_tasks()
    combo = combo_view()
    if combo is not None and combo.width() < width:
        FreeCADGui.getMainWindow().resizeDocks([combo], [width], QtCore.Qt.Horizontal)
        pump(0.1)


def screenshot(name, widget=None):
    """Save the screen (or `widget`'s area of it) as <name>.png; return the path.

    Taken from the X server, so the 3D view's OpenGL content is included.
    Pass widgets the test holds (a temporary PySide wrapper, e.g. of
    parentWidget(), may delete its widget when collected)."""
    os.makedirs(SCREENSHOTS, exist_ok=True)
    path = os.path.join(SCREENSHOTS, name + ".png")
    arrange_window()
    if not name.startswith("failure"):
        widen_combo_view()
    screen = QtGui.QGuiApplication.primaryScreen()
    if widget is None:
        pixmap = screen.grabWindow(0)
    else:
        corner = widget.mapToGlobal(QtCore.QPoint(0, 0))
        pixmap = screen.grabWindow(0, corner.x(), corner.y(), widget.width(), widget.height())
    pixmap.save(path)
    return path


def combo_view():
    """The dock that holds the task panels: "Combo View" (model tree and
    tasks in one) up to FreeCAD 1.0, "Tasks" (beside "Model") in 1.1."""
    window = FreeCADGui.getMainWindow()
    for name in ("Combo View", "Tasks"):
        dock = window.findChild(QtGui.QDockWidget, name)
        if dock is not None:
            return dock
    return None


def report_view_text():
    window = FreeCADGui.getMainWindow()
    dock = window.findChild(QtGui.QDockWidget, "Report view")
    if dock is None:
        return ""
    edit = dock.findChild(QtGui.QTextEdit)
    return edit.toPlainText() if edit is not None else ""


def dump_report_view(stream):
    stream.write("--- report view ---\n%s\n--- end of report view ---\n" % report_view_text())


# -- user actions ----------------------------------------------------------------


def isocam_toolbar():
    """The title of the toolbar that holds our commands: our own "IsoCAM"
    toolbar on FreeCAD 0.20, the workbench's "New Operations" from 0.21 on
    (where a workbench manipulator puts them)."""
    from freecad_ext.gui import commands

    if hasattr(FreeCADGui, "addWorkbenchManipulator"):
        return commands.OPERATIONS_TOOLBAR
    return commands.TOOLBAR


def isocam_menu_path():
    """Where our commands are in the menu bar: "&Path > IsoCAM" on 0.20,
    the "&CAM" menu's operations submenu (after FreeCAD's Adaptive) on 1.x."""
    from freecad_ext.gui import commands

    if hasattr(FreeCADGui, "addWorkbenchManipulator"):
        return ("&CAM" if compat.renamed_to_cam() else "&Path",)
    return ("&Path", commands.SUBMENU)


def trigger(action, timeout=10.0):
    """Press a toolbar or menu action as a user would: once it is enabled.
    FreeCAD refreshes its commands' enabled state from a timer (1.1: on
    demand), so it is asked to refresh first; QAction.trigger() on an action
    still shown disabled does nothing."""
    update = getattr(FreeCADGui, "updateCommands", None)
    if update is not None:
        update()
    wait_until(action.isEnabled, timeout, "%s to be enabled" % action.text())
    action.trigger()


def toolbar_action(toolbar_title, command):
    """The QAction of FreeCAD command `command` in the toolbar titled
    `toolbar_title`, or None."""
    window = FreeCADGui.getMainWindow()
    for bar in children(window, QtGui.QToolBar):
        if bar.windowTitle() != toolbar_title or not bar.isVisible():
            continue
        for action in bar.actions():
            if command in (action.objectName(), action.data()):
                return action
        for action in FreeCADGui.Command.get(command).getAction():
            if action in bar.actions():
                return action
    return None


def menu_action(menu_path, command):
    """The QAction of `command` under the menu bar path, e.g.
    ("&Path", "IsoCAM"); None if absent."""
    window = FreeCADGui.getMainWindow()
    actions = window.menuBar().actions()
    for title in menu_path:
        match = [a for a in actions if a.text() == title and a.menu() is not None]
        if not match:
            return None
        menu = match[0].menu()
        menu.aboutToShow.emit()  # FreeCAD fills some menus on demand
        actions = menu.actions()
    ours = FreeCADGui.Command.get(command).getAction()
    return _find_action(actions, ours)


def _find_action(actions, ours):
    """The first of `ours` among `actions` or in their submenus."""
    for action in actions:
        if action in ours:
            return action
    for action in actions:
        menu = action.menu()
        if menu is not None:
            menu.aboutToShow.emit()
            found = _find_action(menu.actions(), ours)
            if found is not None:
                return found
    return None


def type_text(widget, text, enter=False):
    """Replace `widget`'s text by typing `text` key by key, as a user would.

    enter=True presses Return afterwards; in a task panel FreeCAD takes that
    as OK."""
    activate(widget)
    widget.setFocus(QtCore.Qt.OtherFocusReason)
    pump()  # FreeCAD's spin boxes refresh their text on focus-in
    widget.selectAll()
    for char in text:
        key = ord(char.upper())  # Qt's key codes for printable ASCII
        for kind in (QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease):
            event = QtGui.QKeyEvent(kind, key, QtCore.Qt.NoModifier, char)
            QtGui.QApplication.sendEvent(widget, event)
        pump()
    if enter:
        for kind in (QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease):
            event = QtGui.QKeyEvent(kind, QtCore.Qt.Key_Return, QtCore.Qt.NoModifier)
            QtGui.QApplication.sendEvent(widget, event)
        pump()


def activate(widget):
    """Make `widget`'s window the active one. Xvfb runs no window manager,
    so after a dialog closes nothing gives the focus back by itself."""
    window = widget.window()
    if QtGui.QApplication.activeWindow() is not window:
        window.activateWindow()
        QtGui.QApplication.setActiveWindow(window)
        pump(0.05)


def click(button):
    """Click like a mouse: the button takes the focus first, so a field being
    edited finishes its editing (editingFinished) before the click acts."""
    activate(button)
    button.setFocus(QtCore.Qt.MouseFocusReason)
    pump()
    button.click()
    pump()


def button_labelled(widget, text):
    """The push button with label `text` inside `widget` (e.g. a dialog)."""
    for button in children(widget, QtGui.QPushButton):
        if button.text().replace("&", "") == text:
            return button
    raise AssertionError("no %r button in %r" % (text, widget.windowTitle()))


def choose_in_combo(combo, text):
    index = combo.findText(text)
    if index < 0:
        raise AssertionError("%r not offered in %s" % (text, combo.objectName()))
    combo.setCurrentIndex(index)
    pump()


def task_button(which):
    """The Task view's standard button `which` (QDialogButtonBox.Ok...).

    Looked for in the dock that holds the task panels, not in the whole
    main window: each findChildren converts every descendant to a Python
    wrapper, and tests poll this many times a second (the fewer wrappers
    made and dropped, the fewer chances to meet a stale one, see
    children())."""
    show_tasks()
    where = combo_view()
    if where is None:
        where = FreeCADGui.getMainWindow()
    for box in children(where, QtGui.QDialogButtonBox):
        try:
            button = box.button(which)
            if button is not None and button.isVisible():
                return button
        except RuntimeError:  # the box was deleted since children() listed it
            continue
    return None


# -- dialogs ---------------------------------------------------------------------


def dialog_text(widget):
    if isinstance(widget, QtGui.QMessageBox):
        return widget.text()
    if isinstance(widget, QtGui.QProgressDialog):
        return widget.labelText()
    return ""


def dialog_is_expected(widget):
    return any(predicate(widget) for predicate in _expected_dialogs)


@contextlib.contextmanager
def expect_dialog(predicate):
    """Within the block, modal dialogs matching `predicate` do not trip the
    runner's watchdog."""
    _expected_dialogs.append(predicate)
    try:
        yield
    finally:
        _expected_dialogs.remove(predicate)


def is_progress_dialog(widget):
    return widget.objectName() == "IsoCAMProgress"


def answer_message_box(seen, timeout=20.0):
    """From the event loop, wait for a QMessageBox, record its text in
    `seen` and close it (a user reading it and pressing OK)."""
    end = time.monotonic() + timeout

    def poll():
        box = QtGui.QApplication.activeModalWidget()
        if isinstance(box, QtGui.QMessageBox):
            seen.append(box.text())
            screenshot("message-box-%d" % len(seen))
            box.accept()
        elif time.monotonic() < end:
            later(0.1, poll)

    later(0.1, poll)


def answer_input_dialog(name, seen, value=None, accept=True, timeout=20.0):
    """From the event loop, wait for the QInputDialog with objectName `name`,
    record its label and value in `seen`, type `value` (if given) and press
    OK (accept) or Cancel, as a user would."""
    end = time.monotonic() + timeout

    def poll():
        dialog = QtGui.QApplication.activeModalWidget()
        if isinstance(dialog, QtGui.QInputDialog) and dialog.objectName() == name:
            seen.append((dialog.labelText(), dialog.doubleValue()))
            screenshot("input-dialog-%d" % len(seen))
            if value is not None:
                dialog.setDoubleValue(value)
            if accept:
                dialog.accept()
            else:
                dialog.reject()
        elif time.monotonic() < end:
            later(0.1, poll)

    later(0.1, poll)


# -- documents -------------------------------------------------------------------


def load_shape(filename):
    shape = Part.Shape()
    shape.read(os.path.join(DATA_DIR, filename))
    return shape


def degenerate_face():
    """A Bezier face whose poles lie on one line: no area; the core refuses
    it with a GeometryError naming the face."""
    surface = Part.BezierSurface()
    surface.increase(2, 2)
    for i in range(1, 4):
        for j in range(1, 4):
            surface.setPole(i, j, FreeCAD.Vector(10.0 * i + j, 0, 0))
    return surface.toShape()


def open_path_workbench(command):
    """Activate the Path (CAM) workbench and wait until IsoCAM's toolbar
    offers `command` (the addon adds it when the workbench first shows)."""
    FreeCADGui.activateWorkbench(PATH_WORKBENCH)
    wait_until(
        lambda: toolbar_action(isocam_toolbar(), command) is not None,
        20,
        "the IsoCAM toolbar in the Path workbench",
    )


def ops_of(doc, op_class):
    """The operations of `doc` whose proxy is an `op_class`."""
    return [o for o in doc.Objects if isinstance(getattr(o, "Proxy", None), op_class)]


def settle(doc, rounds=5):
    """Recompute `doc` until no object is left touched, letting the event
    loop run in between: FreeCAD 1.1 finishes a new Job's objects (its
    tool bits' bodies, the stock) from the event loop after the first
    recompute. A snapshot taken before that would see FreeCAD's own late
    changes as ours."""
    for _ in range(rounds):
        pump(0.3)
        if not any("Touched" in o.State for o in doc.Objects):
            return
        doc.recompute()


def snapshot(doc, skip=()):
    """What must not change: every object's name, type and label, its Path
    (as G-code) and its shape (as B-rep; not for tool bits, see
    _tool_bodies), except the objects in `skip`."""
    state = {}
    tool_bodies = _tool_bodies(doc)
    for obj in doc.Objects:
        if obj.Name in skip:
            continue
        path = obj.Path.toGCode() if hasattr(obj, "Path") else None
        shape = None
        if (
            obj.isDerivedFrom("Part::Feature")
            and not obj.Shape.isNull()
            and obj.Name not in tool_bodies
        ):
            shape = _without_flags(obj.Shape.exportBrepToString())
        state[obj.Name] = (obj.TypeId, obj.Label, path, shape)
    return state


def snapshot_changes(after, before):
    """[(object name, what changed)] between two snapshots; [] if none."""
    fields = ("type", "label", "path", "shape")
    changes = []
    for name in sorted(set(after) | set(before)):
        if name not in after or name not in before:
            changes.append((name, "added" if name in after else "removed"))
            continue
        for field, a, b in zip(fields, after[name], before[name]):
            if a != b:
                changes.append((name, field, _describe_change(a, b)))
    return changes


def _describe_change(after, before):
    """A short account of how two snapshot values differ."""
    if not (isinstance(after, str) and isinstance(before, str)):
        return "%r != %r" % (after, before)
    a, b = after.splitlines(), before.splitlines()
    first = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
    return "%d vs %d lines, first difference at line %d: %r vs %r" % (
        len(a),
        len(b),
        first,
        a[first] if first < len(a) else None,
        b[first] if first < len(b) else None,
    )


def _without_flags(brep):
    """A B-rep text without its shapes' flag lines (free, modified, checked,
    orientable, closed, infinite, convex: seven 0/1 digits). OpenCASCADE
    sets "checked" once a shape has been analysed (FreeCAD 1.1's Stock after
    a recompute of its Job), which is bookkeeping, not geometry."""
    return "\n".join(
        line for line in brep.splitlines() if not (len(line) == 7 and set(line) <= {"0", "1"})
    )


def _tool_bodies(doc):
    """Names of the tool bits of `doc`'s tool controllers and of what they
    are built from. FreeCAD 1.1 rebuilds a ToolBit's body (Body, Sketch,
    Revolution) after each recompute of the document, so their shapes are
    FreeCAD's to change; the bits' labels and types are still compared."""
    names = set()
    for obj in doc.Objects:
        tool = getattr(obj, "Tool", None)
        if tool is not None and hasattr(tool, "OutListRecursive"):
            names.add(tool.Name)
            names.update(o.Name for o in tool.OutListRecursive)
    return names


def set_view(doc_name, view="isometric", on=None):
    """Orient the 3D view and fit it to all, or to the objects `on`.

    (A path's preview starts at the origin, so fitting all of a Job whose
    model lies far from it shows mostly that first rapid.)"""
    gui_doc = FreeCADGui.getDocument(doc_name)
    gui_view = gui_doc.ActiveView
    getattr(gui_view, "view" + view.capitalize())()
    if on:
        FreeCADGui.Selection.clearSelection()
        for obj in on:
            FreeCADGui.Selection.addSelection(obj)
        FreeCADGui.SendMsgToActiveView("ViewSelection")
        FreeCADGui.Selection.clearSelection()
    else:
        gui_view.fitAll()
    pump(0.3)


def show_in_tree(obj):
    """Expand the model tree down to `obj` (selecting it does) and leave it
    unselected."""
    window = FreeCADGui.getMainWindow()
    tabs = combo_view().findChild(QtGui.QTabWidget)
    if tabs is not None:
        tabs.setCurrentIndex(0)
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(obj)
    pump(0.2)
    FreeCADGui.Selection.clearSelection()
    pump(0.1)
    return window
