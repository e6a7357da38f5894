"""The FreeCAD side of the corpus (used by fuzz.py --freecad N): each case runs
in its own headless freecadcmd (tests/fuzz/fc_case.py) with a Job holding the
three IsoCAM operations, makes one property of one op bad (or the model a bad
shape), recomputes, and checks that only that op is in error with a message
naming the property, that FreeCAD keeps running and that the document saves
and reopens with the other ops valid.
"""

import json
import os
import random
import re
import signal
import subprocess
import time

from fuzz import limit  # the same limits as the module cases (next to this file)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# (op, property, bad values, words the op's message must contain)
PROPERTIES = (
    ("AdaptiveIsocurve", "ScallopHeight", (1e-9, 0.0, 3.0, 1e300), ("ScallopHeight",)),
    # ChordTolerance 0 derives it from the budgets; 0.5 does not fit them.
    ("AdaptiveIsocurve", "ChordTolerance", (1e-12, 0.5), ("ChordTolerance",)),
    ("AdaptiveIsocurve", "OvercutTolerance", (1e-9, 3.0), ("OvercutTolerance",)),
    ("AdaptiveIsocurve", "ClearanceHeight", (-50.0,), ("ClearanceHeight",)),
    ("AdaptiveIsocurve", "SafeHeight", (1e300, -50.0), ("SafeHeight",)),
    ("AdaptiveIsocurve", "MaxMoves", (0, 10), ("MaxMoves",)),
    ("AdaptiveIsocurve", "Base", ("Face999",), ("Face999",)),
    ("SpiralPocket", "StepOver", (0,), ("StepOver",)),
    ("SpiralPocket", "Tolerance", (0.0, 1e-12), ("Tolerance",)),
    ("SpiralPocket", "ClearanceHeight", (-50.0,), ("ClearanceHeight",)),
    ("SpiralPocket", "MaxMoves", (0, 10), ("MaxMoves",)),
    ("SpiralPocket", "Base", ("Face999",), ("Face999",)),
    ("ZLevelRoughing", "StepOver", (0,), ("StepOver",)),
    ("ZLevelRoughing", "StepDown", (0.0, -1.0), ("StepDown",)),
    ("ZLevelRoughing", "ClearanceHeight", (-50.0,), ("ClearanceHeight",)),
    ("ZLevelRoughing", "MaxMoves", (0, 10), ("MaxMoves",)),
)
# Bad shapes as the Job's model: every op is then in error, FreeCAD runs on.
SHAPES = ("vertex", "edge", "wire", "empty", "face")


def generate(count, seed):
    rng = random.Random(seed)
    cases = []
    for op, prop, values, words in PROPERTIES:
        for v in values:
            cases.append({"op": op, "property": prop, "value": v, "expect": list(words)})
    for s in SHAPES:
        cases.append({"shape": s, "expect": []})
    rng.shuffle(cases)
    while len(cases) < count:
        op, prop, values, words = rng.choice(PROPERTIES)
        cases.append(
            {"op": op, "property": prop, "value": rng.choice(values), "expect": list(words)}
        )
    return cases[:count]


def run(count, seed, timeout, addon, work, memory_mb=6144):
    """Yields (class, report line) per case."""
    for i, case in enumerate(generate(count, seed)):
        folder = os.path.join(work, "f%03d" % i)
        os.makedirs(os.path.join(folder, "home"), exist_ok=True)
        case_file = os.path.join(folder, "case.json")
        with open(case_file, "w") as f:
            json.dump(case, f)
        env = dict(
            os.environ,
            HOME=os.path.join(folder, "home"),
            ISOCAM_ADDON_DIR=addon,
            ISOCAM_FUZZ_CASE=case_file,
            ISOCAM_FUZZ_DIR=folder,
            ISOCAM_TEST_DATA=os.path.join(ROOT, "tests", "data"),
        )
        for k in ("XDG_CONFIG_HOME", "XDG_DATA_HOME", "XDG_CACHE_HOME"):
            env.pop(k, None)
        started = time.monotonic()
        proc = subprocess.Popen(
            ["freecadcmd", os.path.join(HERE, "fc_case.py")],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            env=env,
            preexec_fn=limit(memory_mb),
        )
        timed_out = False
        try:
            out, _ = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, _ = proc.communicate()
            timed_out = True
        out = out.decode("utf-8", "replace")
        m = re.search(r"FUZZ-RESULT (\{.*\})$", out, re.M)
        if timed_out:
            cls, why = "HANG", "no result within the time limit"
        elif proc.returncode < 0:
            cls, why = "CRASH", "signal %s" % signal.Signals(-proc.returncode).name
        elif not m:
            cls, why = "CRASH", "freecadcmd ended without a result: " + out.strip()[-300:]
        else:
            res = json.loads(m.group(1))
            cls, why = res["class"], res["why"]
        what = (
            ("model %s" % case["shape"])
            if "shape" in case
            else "%s.%s = %r" % (case["op"], case["property"], case["value"])
        )
        yield cls, "f%03d %-7s %5.1fs freecad %s -> %s" % (
            i,
            cls,
            time.monotonic() - started,
            what,
            why[:200],
        )
