"""Runs inside the FreeCAD GUI (started by run_gui_test.sh): loads the unittest
file named by $ISOCAM_TEST_FILE once the main window's event loop runs, runs
it, writes PASS or FAIL to $ISOCAM_RESULT_FILE and leaves FreeCAD with a
matching exit status. Test output goes to $ISOCAM_LOG_FILE (FreeCAD's GUI
sends Python's stdout to its report view).

The tests start once FreeCAD's start-up is over (FreeCAD may run this file
before that), or the run fails after STARTUP_TIMEOUT with a screenshot.

Watchdogs keep a test from hanging:
* a Qt timer, which also fires inside modal dialogs' event loops: a modal
  dialog that is neither IsoCAM's progress dialog nor announced by the test
  (gui_support.expect_dialog) and stays up for DIALOG_GRACE seconds, or the
  whole run exceeding $ISOCAM_GUI_TIMEOUT, fails the test with a screenshot
  and the dialog's text;
* a thread, for when the GUI thread is stuck outside any event loop: it ends
  the process (without a screenshot) a little later -- if the stuck code
  lets Python threads run; otherwise `timeout` in run_gui_test.sh does.
"""

import faulthandler
import importlib.util
import os
import sys
import threading
import time
import traceback
import unittest

from PySide import QtCore, QtGui

DIALOG_GRACE = 8.0  # s an unexpected modal dialog may stay up
TIMEOUT = float(os.environ.get("ISOCAM_GUI_TIMEOUT", "150"))
STARTED = time.monotonic()

_log = open(os.environ["ISOCAM_LOG_FILE"], "a", buffering=1)
# A crash of FreeCAD (SIGSEGV) prints the Python line it came from in the log,
# before FreeCAD's own handler prints the C++ stack.
faulthandler.enable(file=_log, all_threads=False)


def _finish(passed, reason="", gui_thread=True):
    if reason:
        _log.write("gui_runner: %s\n" % reason)
    if reason and gui_thread:
        try:
            import gui_support

            gui_support.dump_report_view(_log)
        except Exception:
            pass
    _log.flush()
    with open(os.environ["ISOCAM_RESULT_FILE"], "w") as out:
        out.write("PASS" if passed else "FAIL")
    os._exit(0 if passed else 1)


class _Watchdog(QtCore.QObject):
    def __init__(self):
        super().__init__()
        self.dialog_since = {}
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(self.tick)
        self.timer.start(250)

    def tick(self):
        import gui_support

        elapsed = time.monotonic() - STARTED
        if elapsed > TIMEOUT:
            path = gui_support.screenshot("failure-timeout")
            _finish(False, "timed out after %.0f s; screenshot %s" % (elapsed, path))
        modal = QtGui.QApplication.activeModalWidget()
        # IsoCAM's progress dialog ends with its computation (TIMEOUT guards
        # that); anything else must be expected by the test.
        if (
            modal is None
            or gui_support.is_progress_dialog(modal)
            or gui_support.dialog_is_expected(modal)
        ):
            self.dialog_since.clear()
            return
        since = self.dialog_since.setdefault(id(modal), time.monotonic())
        if time.monotonic() - since > DIALOG_GRACE:
            path = gui_support.screenshot("failure-dialog")
            _finish(
                False,
                "an unexpected dialog stayed open: %r %r; screenshot %s"
                % (modal.windowTitle(), gui_support.dialog_text(modal), path),
            )


def _last_resort():
    time.sleep(TIMEOUT + 15)
    _finish(
        False,
        "the GUI thread did not respond; killed without screenshot",
        gui_thread=False,
    )


class _ImmediateResult(unittest.TextTestResult):
    """Prints each failure as it happens: a watchdog may end the run before
    the summary."""

    def addError(self, test, err):
        super().addError(test, err)
        self.stream.write(self._exc_info_to_string(err, test))

    def addFailure(self, test, err):
        super().addFailure(test, err)
        self.stream.write(self._exc_info_to_string(err, test))


def _load(test_file):
    name = os.path.splitext(os.path.basename(test_file))[0]
    spec = importlib.util.spec_from_file_location(name, test_file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def _run():
    import gui_support

    gui_support.prepare_main_window()
    test_file = os.environ["ISOCAM_TEST_FILE"]
    suite = unittest.defaultTestLoader.loadTestsFromModule(_load(test_file))
    runner = unittest.TextTestRunner(stream=_log, verbosity=2, resultclass=_ImmediateResult)
    result = runner.run(suite)
    _log.write("gui_runner: %.1f s\n" % (time.monotonic() - STARTED))
    gui_support.dump_report_view(_log)
    return result.wasSuccessful() and result.testsRun > 0


def _main():
    passed = False
    try:
        passed = _run()
    except BaseException:
        traceback.print_exc(file=_log)
    _finish(passed)


sys.path.insert(0, os.path.dirname(os.environ["ISOCAM_TEST_FILE"]))  # gui_support
STARTUP_TIMEOUT = 60.0  # s


def _started():
    """FreeCAD's start-up is over: the main window is up, the start-up
    workbench is active and IsoCAM's InitGui.py has registered its commands
    (if package.xml or InitGui.py are broken, it never does)."""
    import FreeCADGui

    window = FreeCADGui.getMainWindow()
    if window is None or not window.isVisible():
        return False
    try:
        FreeCADGui.activeWorkbench().name()
    except Exception:  # "No active workbench" while starting
        return False
    return "IsoCAM_AdaptiveIsocurve" in FreeCADGui.listCommands()


def _start_when_ready():
    """Poll from the event loop, returning at once each time: FreeCAD may
    run this file (and process events) before its start-up has finished,
    and a test run nested inside that would block the rest of it."""
    if _started():
        QtCore.QTimer.singleShot(0, _main)
    elif time.monotonic() - STARTED > STARTUP_TIMEOUT:
        import gui_support

        path = gui_support.screenshot("failure-startup")
        _finish(False, "FreeCAD or IsoCAM did not start; screenshot %s" % path)
    else:
        QtCore.QTimer.singleShot(200, _start_when_ready)


_watchdog = _Watchdog()
threading.Thread(target=_last_resort, daemon=True).start()
QtCore.QTimer.singleShot(0, _start_when_ready)
