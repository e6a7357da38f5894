"""The regression figures of the tests, read from tests/data/expected.txt
(beside the models they are measured on; the file's header gives the line
format), for the Python and FreeCAD tests; tests/cpp/support/expected.cpp
reads the same file for the C++ tests.

    expected_figures.check(self, "GcodeSim/Ball", "reachable_fraction", 0.29)

fails the test case with a message naming the case, the quantity, the
measured and expected values, by how much they differ and the entry's line
and reason. A missing entry, or a file that does not parse, fails too.
"""

import math
import os

FILE = "expected.txt"
RELATIONS = {
    "=": None,  # within the tolerance: see _holds
    "<": lambda m, v: m < v,
    "<=": lambda m, v: m <= v,
    ">": lambda m, v: m > v,
    ">=": lambda m, v: m >= v,
}


def _path():
    data = os.environ.get("ISOCAM_TEST_DATA") or os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "data"
    )
    return os.path.join(data, FILE)


def _number(text):
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise ValueError("%r is not a number" % text)
    return value


def _parse(text):
    """(case, quantity, figure) of one entry line:
    <case> <quantity> <relation> <value> [+- <tolerance>] # <reason>."""
    body, hash_, reason = text.partition("#")
    reason = reason.strip()
    if not hash_ or not reason:
        raise ValueError("no # reason")
    t = body.split()
    if len(t) not in (4, 6):
        raise ValueError("want <case> <quantity> <relation> <value> [+- <tol>]")
    case, quantity, relation = t[0], t[1], t[2]
    if relation not in RELATIONS:
        raise ValueError("relation %r is none of = < <= > >=" % relation)
    value = _number(t[3])
    if (relation == "=") != (len(t) == 6):
        raise ValueError("= wants +- <tolerance>" if relation == "=" else "a bound takes no +-")
    tolerance = 0.0
    if relation == "=":
        tolerance = _number(t[5])
        if t[4] != "+-" or tolerance < 0:
            raise ValueError("want +- <tolerance >= 0>")
    return case, quantity, dict(relation=relation, value=value, tolerance=tolerance, reason=reason)


_table = None


def _read():
    """{(case, quantity): figure}; raises ValueError naming the bad line."""
    table = {}
    with open(_path()) as f:
        for n, text in enumerate(f, 1):
            stripped = text.strip()
            if not stripped or stripped.startswith("#"):
                continue
            try:
                case, quantity, figure = _parse(stripped)
            except ValueError as e:
                raise ValueError("%s:%d: %s" % (FILE, n, e)) from None
            if (case, quantity) in table:
                raise ValueError("%s:%d: a second entry for %s %s" % (FILE, n, case, quantity))
            figure["line"] = n
            table[(case, quantity)] = figure
    return table


def _holds(f, measured):
    if f["relation"] == "=":
        return abs(measured - f["value"]) <= f["tolerance"]
    return RELATIONS[f["relation"]](measured, f["value"])


def check(testcase, case, quantity, measured):
    """Fail `testcase` unless `measured` meets the figure of (case, quantity)."""
    global _table
    if _table is None:
        try:
            _table = _read()
        except OSError as e:
            testcase.fail("cannot read %s: %s" % (_path(), e))
        except ValueError as e:
            testcase.fail("tests/data/%s" % e)
    f = _table.get((case, quantity))
    if f is None:
        testcase.fail("no entry for %s %s in tests/data/%s" % (case, quantity, FILE))
    want = "%s %g" % (f["relation"], f["value"])
    if f["relation"] == "=":
        want += " +- %g" % f["tolerance"]
    where = "%s:%d" % (FILE, f["line"])
    if _holds(f, measured):
        print("    figure %s %s: %g (%s, %s)" % (case, quantity, measured, want, where))
        return
    off = measured - f["value"]
    message = "%s %s: measured %g, expected %s (%s): off by %g" % (
        case,
        quantity,
        measured,
        want,
        where,
        off,
    )
    if f["value"] != 0:
        message += " (%g %%)" % (100 * off / abs(f["value"]))
    testcase.fail(message + "; the entry's reason: " + f["reason"])
