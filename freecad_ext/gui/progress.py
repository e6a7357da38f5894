"""Progress and cancel for a core computation running during a recompute.

The operation runs the core in a worker thread (the binding releases the GIL)
and hands the thread and its ``isocam_core.Progress`` to :func:`wait`, which
keeps FreeCAD's window painted, shows a modal progress dialog with a Cancel
button once the work takes longer than :data:`SHOW_AFTER` seconds, and polls
``progress.fraction``. The core never calls Python; only this loop does.

Cancel by the user: ``progress.cancel()`` is requested, the worker is waited
for (the core checks the flag between steps), and then
``FreeCAD.Base.FreeCADAbort`` is raised. It derives from BaseException, so the
operation's own error handling (which empties the path) does not catch it: the
recompute stops with the operation's previous Path and certificate intact;
FreeCAD marks the operation touched (to be recomputed) and shows the reason.
A cancel requested by a script through ``progress.cancel()`` is not a user
cancel: the core raises its CancelledError and the operation reports an error.
"""

import time

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

SHOW_AFTER = 0.4  # s: shorter computations never flash a dialog
POLL = 0.05  # s
DIALOG_NAME = "IsoCAMProgress"  # objectName, for tests and style sheets

_user_cancels = 0


def user_cancels():
    """How many computations the user has cancelled so far in this session;
    a caller compares the count before and after a recompute."""
    return _user_cancels


class _Dialog(QtGui.QProgressDialog):
    def __init__(self, title):
        parent = FreeCADGui.getMainWindow()
        super().__init__(title, "Cancel", 0, 1000, parent)
        self.setObjectName(DIALOG_NAME)
        self.setWindowTitle("IsoCAM")
        self.setWindowModality(QtCore.Qt.ApplicationModal)
        self.setAutoClose(False)
        self.setAutoReset(False)
        self.setMinimumDuration(0)
        self.cancel_requested = False
        self.canceled.connect(self._on_cancel)

    def _on_cancel(self):
        self.cancel_requested = True
        self.setLabelText(self.labelText() + "\nCancelling...")


def _cancel_requested(dialog):
    # The Cancel button emits canceled(); Esc and cancel() only set
    # wasCanceled().
    return dialog.cancel_requested or dialog.wasCanceled()


def wait(worker, progress, title):
    """Block until `worker` ends, showing `title` and progress; see the module
    docstring for what a cancel by the user does."""
    global _user_cancels
    started = time.monotonic()
    dialog = None
    cancelled = False
    bar = FreeCADGui.getMainWindow().statusBar()
    try:
        while worker.is_alive():
            worker.join(POLL)
            percent = int(100 * progress.fraction)
            bar.showMessage("%s: %d %%" % (title, percent))
            if dialog is None and time.monotonic() - started > SHOW_AFTER:
                dialog = _Dialog(title)
                # FreeCAD sets a wait cursor around execute(); the dialog
                # must look clickable.
                QtGui.QApplication.setOverrideCursor(QtCore.Qt.ArrowCursor)
                dialog.show()
            if dialog is None:
                # Not yet modal: paint only, user input waits in the queue.
                QtGui.QApplication.processEvents(QtCore.QEventLoop.ExcludeUserInputEvents)
                continue
            dialog.setValue(int(1000 * progress.fraction))
            # The modal dialog blocks input to every other window, so only
            # its Cancel button (or Esc) can act here.
            QtGui.QApplication.processEvents(QtCore.QEventLoop.AllEvents)
            if _cancel_requested(dialog) and not progress.cancelled:
                progress.cancel()
        # Read before closing: closing a QProgressDialog emits canceled().
        cancelled = dialog is not None and _cancel_requested(dialog)
    finally:
        bar.clearMessage()
        if dialog is not None:
            dialog.canceled.disconnect(dialog._on_cancel)
            QtGui.QApplication.restoreOverrideCursor()
            dialog.close()
            dialog.deleteLater()
    if cancelled:
        _user_cancels += 1
        raise FreeCAD.Base.FreeCADAbort(
            "%s cancelled by the user; the operation keeps its previous path "
            "until it is recomputed" % title
        )
