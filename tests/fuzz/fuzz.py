#!/usr/bin/env python3
"""The robustness corpus (issue 15): generated inputs for the isocam_core
module (and, with --freecad N, for the FreeCAD operations under freecadcmd),
each run in its own process under a time and an address-space limit, and
classified:

  CRASH    the process died of a signal (SIGSEGV, SIGABRT, ...)
  HANG     it did not end within --timeout seconds
  MEMORY   it ran out of the --memory-mb address space (MemoryError,
           std::bad_alloc) or was killed for it
  UNCLEAR  an error whose type is not (derived from) ValueError / RuntimeError /
           CancelledError, or whose message does not name the problem (the
           case's expected words, e.g. the argument)
  WRONG    a result with NaN or inf in a path or metric, or a bad input
           accepted without an error
  OK       a result, or a clear error

Any class but OK fails the run (exit status 1); the failing cases are kept
under --out as JSON (with their B-rep files) to reproduce with fuzz_child.py.

  tests/fuzz/fuzz.py --cases 300 --seed 1        # the fixed CI set (ctest fuzz.module)
  ./run fuzz                                     # 900 module cases + FreeCAD cases

The cases: random mutations of the bundled B-rep models (truncation, numbers
replaced by NaN / inf / 1e308 / -1 / huge counts, lines deleted or doubled,
bytes flipped), rational weights -1 / 0 / NaN / 1e300, degenerate and extreme
surfaces (all poles in one point, poles 1e7 mm away, models scaled by 1e-4 and
1e6 through their location), parameter edges of every entry (NaN, inf, 0,
negative, 1e-12, 1e300) and degenerate profiles for spiral_pocket.
"""

import argparse
import collections
import json
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.environ.get("ISOCAM_TEST_DATA", os.path.join(ROOT, "tests", "data"))
# The children run with the Python that runs this harness (ctest and ./run
# fuzz start it with the Python the module is built for).
PYTHON = sys.executable

MODELS = ("face.brep", "Ball.brep", "wing.brep", "MAT.brep", "shell1.brep")
BAD_NUMBERS = (
    "nan",
    "-nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "-1",
    "0",
    "1e-308",
    "999999999",
    "4294967296",
    "1e300",
    "abc",
)
SECTIONS = (
    "Locations",
    "Curve2ds",
    "Curves",
    "Polygon3D",
    "PolygonOnTriangulations",
    "Surfaces",
    "Triangulations",
    "TShapes",
)
EDGE_VALUES = (
    float("nan"),
    float("inf"),
    float("-inf"),
    0.0,
    -1.0,
    1e-300,
    1e-12,
    1e-9,
    1e300,
    1e7,
)
CLEAR_TYPES = ("ValueError", "RuntimeError", "CancelledError")
# Words that say nothing about the input: a message made only of them (or a
# C++ library's own) is not clear.
VAGUE = re.compile(r"^(std::|bad_alloc|vector|basic_string|unknown|Standard_|$)", re.I)


def read(name):
    with open(os.path.join(DATA, name)) as f:
        return f.read()


# -- B-rep mutations -----------------------------------------------------------


NUMBER = re.compile(r"(?<![\w.+-])[-+]?\d+(\.\d*)?([eE][-+]?\d+)?(?![\w.])")


def mutate(text, rng):
    """One random mutation of B-rep text and what it did."""
    kind = rng.choice(
        (
            "truncate",
            "number",
            "count",
            "delete_line",
            "double_line",
            "flip_byte",
            "swap_lines",
            "number",
            "weights",
            "poles",
        )
    )
    if kind == "truncate":
        k = rng.randrange(len(text))
        return text[:k], "truncated at byte %d" % k
    if kind == "number":
        nums = list(NUMBER.finditer(text))
        m = rng.choice(nums)
        bad = rng.choice(BAD_NUMBERS)
        return text[: m.start()] + bad + text[m.end() :], "number at byte %d -> %s" % (
            m.start(),
            bad,
        )
    if kind == "count":
        found = [m for m in re.finditer(r"(%s) (\d+)" % "|".join(SECTIONS), text)]
        m = rng.choice(found)
        n = rng.choice(
            (10**9, 10**6, int(m.group(2)) + 1, max(0, int(m.group(2)) - 1), 2**31)
        )
        return (text[: m.start(2)] + str(n) + text[m.end(2) :], "%s count -> %d" % (m.group(1), n))
    lines = text.split("\n")
    if kind == "delete_line":
        k = rng.randrange(len(lines))
        del lines[k]
        return "\n".join(lines), "line %d deleted" % k
    if kind == "double_line":
        k = rng.randrange(len(lines))
        lines.insert(k, lines[k])
        return "\n".join(lines), "line %d doubled" % k
    if kind == "swap_lines":
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        return "\n".join(lines), "lines %d and %d swapped" % (i, j)
    if kind == "flip_byte":
        k = rng.randrange(len(text))
        c = chr(rng.randrange(32, 127))
        return text[:k] + c + text[k + 1 :], "byte %d -> %r" % (k, c)
    if kind == "weights":
        # Make the first B-spline or Bezier surface rational with weights w.
        m = re.search(r"^9 0 0 (\d) (\d) (\d+) (\d+) (\d+) (\d+) (\d+) (\d+)", text, re.M)
        if not m:
            return mutate(text, rng)
        w = rng.choice(("-1", "0", "nan", "1e300", "1e-300"))
        head = "9 1 1 " + text[m.start(1) : m.end()]
        rest = text[m.end() :]
        nu, nv = int(m.group(5)), int(m.group(6))
        toks = rest.split()
        out, k = [], 0
        for _ in range(nu * nv):
            out.append(" ".join(toks[k : k + 3]) + " " + w)
            k += 3
        return (
            text[: m.start()] + head + "\n" + " ".join(out) + " " + " ".join(toks[k:]),
            "surface weights -> %s" % w,
        )
    # poles: collapse or blow up the first B-spline surface's poles.
    m = re.search(r"^9 (\d) (\d) (\d) (\d) (\d+) (\d+) (\d+) (\d+) (\d+) (\d+)", text, re.M)
    if not m or m.group(1) != "0" or m.group(2) != "0":
        return mutate(text, rng)
    nu, nv = int(m.group(7)), int(m.group(8))
    toks = text[m.end() :].split()
    how = rng.choice(("point", "far", "huge", "flat_row"))
    for i in range(nu * nv):
        x = toks[3 * i : 3 * i + 3]
        if how == "point":
            x = ["1", "2", "3"]
        elif how == "far":
            x = [str(float(v) + 1e7) for v in x]
        elif how == "huge":
            x = [str(float(v) * 1e6) for v in x]
        elif how == "flat_row" and i % nv == 0:
            x = toks[0:3]
        toks[3 * i : 3 * i + 3] = x
    return text[: m.end()] + "\n" + " ".join(toks) + "\n", "surface poles: %s" % how


def located(text, matrix):
    """The text with its top shape placed by a new location (3 x 4 matrix)."""
    m = re.search(r"^Locations (\d+)\n", text, re.M)
    n = int(m.group(1))
    entry = "1\n" + "\n".join(" ".join(repr(float(v)) for v in row) for row in matrix) + "\n"
    text = text[: m.start()] + "Locations %d\n" % (n + 1) + entry + text[m.end() :]
    # The last line names the top shape: "+<index> <location>".
    body = text.rstrip("\n").split("\n")
    last = body[-1].split()
    body[-1] = "%s %d" % (last[0], n + 1)
    return "\n".join(body) + "\n"


def scaled(text, f):
    return located(text, [[f, 0, 0, 0], [0, f, 0, 0], [0, 0, f, 0]])


def moved(text, d):
    return located(text, [[1, 0, 0, d], [0, 1, 0, d], [0, 0, 1, 0]])


# -- cases ----------------------------------------------------------------------

BOUNDARY = [[0, 0, 0, 0, 0], [100, 0, 0, 0, 0], [100, 60, 0, 0, 0], [0, 60, 0, 0, 0]]
ISLAND = [[60, 30, 50, 30, -1], [40, 30, 50, 30, -1]]


class Case(dict):
    """A JSON-able case: call, args, expect (words a clear error names),
    must_fail (a bad input that must not be accepted), files (B-rep texts)."""


def iso_case(brep, params=None, expect=(), must_fail=False, faces=(0,), note=""):
    p = {"ball_radius": 3.0, "scallop_height": 0.05, "safe_z": 100.0}
    p.update(params or {})
    return Case(
        call="adaptive_isocurve",
        files={"brep": brep},
        args={"faces": list(faces), "params": p},
        expect=list(expect),
        must_fail=must_fail,
        note=note,
    )


def pocket_params(**kw):
    p = {"tool_radius": 3.0, "stepover": 2.4, "safe_z": 50.0}
    p.update(kw)
    return p


def brep_cases(rng):
    """A random mutation of a bundled model, through a random entry."""
    name = rng.choice(MODELS)
    text = read(name)
    muts = []
    for _ in range(rng.choice((1, 1, 1, 2, 3))):
        text, what = mutate(text, rng)
        muts.append(what)
    note = "%s: %s" % (name, "; ".join(muts))
    expect = (
        "brep",
        "face",
        "Face",
        "OpenCASCADE",
        "degenerate",
        "budget",
        "too fine",
        "out of range",
        "no ",
        "not",
    )
    entry = rng.choice(("iso", "iso", "region", "pocket"))
    if name in ("MAT.brep", "shell1.brep") and entry == "iso":
        entry = "region"  # finishing them takes seconds; their reading is the point
    if entry == "iso":
        return iso_case(text, expect=expect, note=note)
    if entry == "region":
        return Case(
            call="face_region",
            files={"brep": text},
            args={"face": 0, "tolerance": 0.01},
            expect=list(expect),
            note=note,
        )
    return Case(
        call="pocket_faces",
        files={"brep": text},
        args={"faces": [0], "params": pocket_params(), "depths": [0.0]},
        expect=list(expect),
        note=note,
    )


def param_cases(rng):
    """An edge value for one argument of one entry."""
    v = rng.choice(EDGE_VALUES)
    which = rng.choice(("iso", "iso", "pocket", "pocket", "rough", "fn"))
    if which == "iso":
        key = rng.choice(
            (
                "ball_radius",
                "scallop_height",
                "chord_tolerance",
                "safe_z",
                "gouge_tolerance",
                "min_param_gap",
                "max_moves",
            )
        )
        bad = not (v == v) or abs(v) == float("inf") or v <= 0
        if key == "safe_z":
            bad = not (v == v) or abs(v) > 1e6
        if key == "chord_tolerance":
            # 0 derives it from the budgets; every other edge value is either
            # too fine for the model or does not fit the overcut budget.
            bad = v != 0.0
        return iso_case(
            read(rng.choice(("face.brep", "wing.brep"))),
            {key: v},
            expect=[key, "budget", "too fine", "below"],
            must_fail=bad,
            note="%s = %r" % (key, v),
        )
    if which == "pocket":
        key = rng.choice(
            (
                "tool_radius",
                "stepover",
                "tolerance",
                "floor_tolerance",
                "safe_z",
                "min_arc_chord",
                "max_moves",
            )
        )
        bad = not (v == v) or abs(v) == float("inf") or (v <= 0 and key not in ("safe_z",))
        if key == "safe_z":
            bad = bad or v <= 0 or v > 1e6
        if key == "min_arc_chord":
            bad = not (v == v) or abs(v) == float("inf") or v < 0
        depths = [0.0]
        if rng.random() < 0.5:
            return Case(
                call="spiral_pocket",
                files={},
                args={
                    "boundary": BOUNDARY,
                    "islands": [ISLAND],
                    "params": pocket_params(**{key: v}),
                    "depths": depths,
                },
                expect=[key, "budget", "too fine", "depths"],
                must_fail=bad,
                note="spiral_pocket %s = %r" % (key, v),
            )
        return Case(
            call="pocket_faces",
            files={"brep": read("face.brep")},
            args={"faces": [0], "params": pocket_params(**{key: v}), "depths": [-5.0]},
            expect=[key, "budget", "too fine", "depths"],
            must_fail=bad,
            note="pocket_faces %s = %r" % (key, v),
        )
    if which == "rough":
        key = rng.choice(("stock_to_leave", "depth", "stepover", "tool_radius"))
        args = {"params": pocket_params(stepover=3.0), "depths": [5.0, 0.0], "stock_to_leave": 0.5}
        if key == "stock_to_leave":
            args["stock_to_leave"] = v
        elif key == "depth":
            args["depths"] = [v, 0.0]
        else:
            args["params"][key] = v
        return Case(
            call="zlevel_roughing",
            files={"model": read("Ball.brep"), "stock": "@box"},
            args=args,
            expect=[key if key != "depth" else "depths", "budget", "too fine"],
            note="zlevel_roughing %s = %r" % (key, v),
        )
    r = rng.choice((3.0, float("nan"), -1.0, 0.0, 1e300))
    x = rng.choice((0.1, float("nan"), 7.0, -1.0, 0.0, 3.0, 1e-300))
    if rng.random() < 0.5:
        bad = not (r > 0 and r < 1e300 and 0 < x <= r) if r == r and x == x else True
        return Case(
            call="stepover_for_scallop",
            files={},
            args={"r": r, "h": x},
            expect=["ball_radius", "scallop_height"],
            must_fail=bad,
            note="stepover_for_scallop(%r, %r)" % (r, x),
        )
    bad = not (r > 0 and r < 1e300 and 0 <= x <= 2 * r) if r == r and x == x else True
    return Case(
        call="scallop_for_stepover",
        files={},
        args={"r": r, "delta": x},
        expect=["ball_radius", "delta"],
        must_fail=bad,
        note="scallop_for_stepover(%r, %r)" % (r, x),
    )


def shape_cases(rng):
    """Models scaled or moved far, tiny tolerances, degenerate profiles."""
    kind = rng.choice(("scaled", "moved", "tiny_tol", "profile", "deep"))
    expect = [
        "too fine",
        "budget",
        "brep",
        "face",
        "Face",
        "stepover",
        "tolerance",
        "profile",
        "boundary",
        "not",
        "no ",
        "out of range",
        "safe_z",
        "depths",
    ]
    if kind == "scaled":
        f = rng.choice((1e-4, 1e-3, 1e3, 1e6))
        name = rng.choice(("face.brep", "Ball.brep", "wing.brep"))
        text = scaled(read(name), f)
        call = rng.choice(("iso", "pocket", "rough"))
        if call == "iso":
            return iso_case(text, expect=expect, note="%s scaled by %g" % (name, f))
        if call == "pocket":
            return Case(
                call="pocket_faces",
                files={"brep": text},
                args={"faces": [0], "params": pocket_params(), "depths": [0.0]},
                expect=expect,
                note="pocket_faces on %s scaled by %g" % (name, f),
            )
        return Case(
            call="zlevel_roughing",
            files={"model": text, "stock": "@box:%g" % f},
            args={
                "params": pocket_params(stepover=3.0, safe_z=50 * f + 50),
                "depths": [5 * f, 0.0],
            },
            expect=expect,
            note="zlevel_roughing on Ball.brep scaled by %g" % f,
        )
    if kind == "moved":
        d = rng.choice((1e5, 1e7, -1e7, 1e9))
        name = rng.choice(("face.brep", "wing.brep"))
        return iso_case(moved(read(name), d), expect=expect, note="%s moved by %g" % (name, d))
    if kind == "tiny_tol":
        name = rng.choice(("face.brep", "Ball.brep", "wing.brep"))
        key, v = rng.choice(
            (
                ("scallop_height", 1e-9),
                ("scallop_height", 1e-6),
                ("chord_tolerance", 1e-12),
                ("chord_tolerance", 1e-8),
            )
        )
        return iso_case(
            read(name), {key: v}, expect=[key, "budget"], note="%s %s = %g" % (name, key, v)
        )
    if kind == "profile":
        prof = rng.choice(
            (
                [[0, 0, 0, 0, 0], [0, 0, 0, 0, 0], [1, 0, 0, 0, 0]],  # zero-length
                [[0, 0, 0, 0, 0], [10, 10, 0, 0, 0], [10, 0, 0, 0, 0], [0, 10, 0, 0, 0]],  # bowtie
                [[0, 0, 0, 0, 0], [1e7, 0, 0, 0, 0], [1e7, 1e7, 0, 0, 0]],
                [[0, 0, 0, 0, 0], [float("nan"), 0, 0, 0, 0], [5, 5, 0, 0, 0]],
                [[0, 0, 1e9, 0, 1], [10, 0, 1e9, 0, 1]],  # arc about a far centre
                [[0, 0, 0, 0, 0], [1e-6, 0, 0, 0, 0], [1e-6, 1e-6, 0, 0, 0], [0, 1e-6, 0, 0, 0]],
                [[0, 0, 0, 0, 7], [1, 0, 0, 0, 0], [1, 1, 0, 0, 0]],  # dir 7
                [[0, 0, 5, 5, 1], [10, 0, 5, 5, 1]],  # arc, wrong radius
            )
        )
        return Case(
            call="spiral_pocket",
            files={},
            args={"boundary": prof, "islands": [], "params": pocket_params(), "depths": [0.0]},
            expect=expect,
            note="profile %r" % (prof,),
        )
    s = rng.choice((0.001, 0.004, 1e-5, 1e-4))
    return Case(
        call="spiral_pocket",
        files={},
        args={
            "boundary": BOUNDARY,
            "islands": [ISLAND],
            "params": pocket_params(tool_radius=0.1, stepover=s),
            "depths": [0.0],
        },
        expect=expect,
        note="deep offset tree, stepover %g" % s,
    )


def generate(count, seed):
    rng = random.Random(seed)
    cases = []
    # The named cases first, then random ones.
    face, ball = read("face.brep"), read("Ball.brep")
    cases.append(
        iso_case(
            "DBRep_DrawableShape\nCASCADE Topology V1, (c) Matra-Datavision\n"
            "Locations 99999999\nCurve2ds 0\n",
            expect=["brep"],
            must_fail=True,
            note="header announcing huge counts",
        )
    )
    cases.append(
        iso_case(
            face[: len(face) // 2],
            expect=["brep"],
            must_fail=True,
            note="face.brep truncated half way",
        )
    )
    cases.append(
        iso_case(
            ball,
            {"scallop_height": 1e-9},
            expect=["scallop_height"],
            must_fail=True,
            note="Ball.brep scallop 1e-9",
        )
    )
    cases.append(
        iso_case(
            ball,
            {"chord_tolerance": 1e-12},
            expect=["chord_tolerance"],
            must_fail=True,
            note="Ball.brep chord 1e-12",
        )
    )
    cases.append(
        iso_case(
            face,
            {"ball_radius": 1e300},
            expect=["ball_radius"],
            must_fail=True,
            note="ball radius 1e300",
        )
    )
    cases.append(
        iso_case(face, {"safe_z": 1e300}, expect=["safe_z"], must_fail=True, note="safe_z 1e300")
    )
    cases.append(
        Case(
            call="stepover_for_scallop",
            files={},
            args={"r": float("nan"), "h": 0.1},
            expect=["ball_radius"],
            must_fail=True,
            note="stepover_for_scallop(nan, 0.1)",
        )
    )
    cases.append(
        Case(
            call="scallop_for_stepover",
            files={},
            args={"r": 3.0, "delta": 7.0},
            expect=["delta"],
            must_fail=True,
            note="scallop_for_stepover(3, 7)",
        )
    )
    cases.append(
        Case(
            call="zlevel_roughing",
            files={"model": read("MAT.brep"), "stock": "@box"},
            args={"params": pocket_params(stepover=3.0), "depths": [20.0, 10.0]},
            expect=["not a solid"],
            must_fail=True,
            note="zlevel on MAT (a face)",
        )
    )
    gens = (brep_cases, brep_cases, param_cases, shape_cases)
    while len(cases) < count:
        cases.append(rng.choice(gens)(rng))
    for i, c in enumerate(cases):
        c["id"] = "m%04d" % i
    return cases[:count]


# -- running and classifying ----------------------------------------------------


def box_brep(scale=1.0):
    """The stock for roughing cases: tests/data/fuzz_stock_box.brep, a box
    5 mm around Ball.brep (written by FreeCAD), scaled with the model."""
    key = "box:%g" % scale
    if key not in _BOX_CACHE:
        text = read("fuzz_stock_box.brep")
        _BOX_CACHE[key] = scaled(text, scale) if scale != 1 else text
    return _BOX_CACHE[key]


_BOX_CACHE = {}


def limit(memory_mb):
    def apply():
        os.setsid()
        lim = memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

    return apply


def classify(case, proc_rc, out, timed_out):
    if timed_out:
        return "HANG", "no result within the time limit"
    m = re.search(r"FUZZ-RESULT (\{.*\})$", out, re.M)
    if proc_rc < 0:
        return "CRASH", "signal %s" % signal.Signals(-proc_rc).name
    if not m:
        if "bad_alloc" in out or "MemoryError" in out or "Cannot allocate" in out:
            return "MEMORY", out.strip()[-300:]
        return "CRASH", "exit status %d without a result: %s" % (proc_rc, out.strip()[-300:])
    res = json.loads(m.group(1))
    if res["outcome"] == "ok":
        if not res.get("finite", True):
            return "WRONG", "NaN or inf in the result"
        if case.get("must_fail"):
            return "WRONG", "bad input accepted without an error"
        return "OK", "result"
    typ, msg = res["type"], res["message"]
    if typ == "MemoryError" or "bad_alloc" in msg:
        return "MEMORY", "%s: %s" % (typ, msg)
    if not set(res.get("kinds", [typ])) & set(CLEAR_TYPES) or VAGUE.match(msg.strip()):
        return "UNCLEAR", "%s: %s" % (typ, msg)
    expect = case.get("expect") or []
    if expect and not any(w in msg for w in expect):
        return "UNCLEAR", "%s: %s (expected a mention of one of %s)" % (typ, msg, expect)
    return "OK", "%s: %s" % (typ, msg)


def run_case(case, work, timeout, memory_mb, addon):
    folder = os.path.join(work, case["id"])
    os.makedirs(folder, exist_ok=True)
    args = dict(case["args"])
    for key, text in case["files"].items():
        if text.startswith("@box"):
            text = box_brep(float(text.split(":")[1]) if ":" in text else 1.0)
        path = os.path.join(folder, key + ".brep")
        with open(path, "w") as f:
            f.write(text)
        args[key] = path
    case_file = os.path.join(folder, "case.json")
    with open(case_file, "w") as f:
        json.dump({"call": case["call"], "args": args, "note": case.get("note", "")}, f)
    env = dict(os.environ, ISOCAM_ADDON_DIR=addon, OMP_NUM_THREADS="1")
    started = time.monotonic()
    timed_out = False
    proc = subprocess.Popen(
        [PYTHON, os.path.join(HERE, "fuzz_child.py"), case_file],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        env=env,
        preexec_fn=limit(memory_mb),
    )
    try:
        out, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, _ = proc.communicate()
        timed_out = True
    out = out.decode("utf-8", "replace")
    cls, why = classify(case, proc.returncode, out, timed_out)
    return cls, why, time.monotonic() - started, folder


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=150.0)
    ap.add_argument("--memory-mb", type=int, default=4096)
    ap.add_argument("--freecad", type=int, default=0, help="FreeCAD cases (freecadcmd) too")
    ap.add_argument("--out", default=None, help="folder for the failing cases")
    ap.add_argument(
        "--addon",
        default=os.environ.get("ISOCAM_ADDON_DIR", os.path.join(ROOT, "build", "addon", "IsoCAM")),
    )
    ap.add_argument("-v", "--verbose", action="store_true")
    a = ap.parse_args(argv)
    cases = generate(a.cases, a.seed)
    work = tempfile.mkdtemp(prefix="isocam-fuzz.")
    started = time.monotonic()
    counts = collections.Counter()
    failures = []
    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = [
            (c, pool.submit(run_case, c, work, a.timeout, a.memory_mb, a.addon)) for c in cases
        ]
        for case, fut in futures:
            cls, why, secs, folder = fut.result()
            counts[cls] += 1
            line = "%s %-7s %5.1fs %s -> %s" % (
                case["id"],
                cls,
                secs,
                case.get("note", "")[:90],
                why[:160],
            )
            if cls != "OK":
                failures.append((case, folder, line))
                print(line, flush=True)
            elif a.verbose:
                print(line, flush=True)
    if a.freecad:
        import fuzz_freecad  # noqa: E402  (next to this file)

        for cls, line in fuzz_freecad.run(a.freecad, a.seed, a.timeout * 2, a.addon, work):
            counts[cls] += 1
            if cls != "OK" or a.verbose:
                print(line, flush=True)
            if cls != "OK":
                failures.append((None, None, line))
    total = sum(counts.values())
    print(
        "fuzz: %d cases (seed %d) in %.0f s: %s"
        % (
            total,
            a.seed,
            time.monotonic() - started,
            ", ".join(
                "%s %d" % (k, counts.get(k, 0))
                for k in ("OK", "CRASH", "HANG", "MEMORY", "UNCLEAR", "WRONG")
            ),
        )
    )
    if failures and a.out:
        os.makedirs(a.out, exist_ok=True)
        for case, folder, _line in failures:
            if folder:
                shutil.copytree(
                    folder, os.path.join(a.out, os.path.basename(folder)), dirs_exist_ok=True
                )
        print(
            "fuzz: failing cases kept in %s (rerun one: %s %s <case>/case.json)"
            % (a.out, PYTHON, os.path.join(HERE, "fuzz_child.py"))
        )
    shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.path.insert(0, HERE)
    sys.exit(main())
