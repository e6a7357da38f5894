"""Runs inside freecadcmd (started by run_in_freecad.sh): loads the unittest
file named by $ISOCAM_TEST_FILE, runs it, writes PASS or FAIL to
$ISOCAM_RESULT_FILE and leaves with a matching exit status.

freecadcmd imports this file as a module (not as __main__), so the work is done
at import time.
"""

import importlib.util
import os
import sys
import traceback
import unittest


def _load(test_file):
    name = os.path.splitext(os.path.basename(test_file))[0]
    spec = importlib.util.spec_from_file_location(name, test_file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def _run():
    addon_dir = os.environ.get("ISOCAM_ADDON_DIR")
    if addon_dir:
        sys.path.insert(0, addon_dir)
    test_file = os.environ["ISOCAM_TEST_FILE"]
    sys.path.insert(0, os.path.dirname(test_file))  # shared test helpers
    suite = unittest.defaultTestLoader.loadTestsFromModule(_load(test_file))
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(suite)
    return result.wasSuccessful() and result.testsRun > 0


def _main():
    passed = False
    try:
        passed = _run()
    except BaseException:  # an import error or a crash of the test module
        traceback.print_exc(file=sys.stdout)
    with open(os.environ["ISOCAM_RESULT_FILE"], "w") as out:
        out.write("PASS" if passed else "FAIL")
    sys.stdout.flush()
    sys.stderr.flush()
    # Leave now: FreeCAD's own shutdown may swallow the status.
    os._exit(0 if passed else 1)


_main()
