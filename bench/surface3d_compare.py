"""Benchmark (issue 10): FreeCAD's own 3D Surface operation (OpenCamLib's
drop-cutter, FreeCAD 1.0) side by side with IsoCAM's Adaptive Isocurve, on
the same models, stock, ball end and feeds, every program measured the same
way from its posted G-code by the independent simulator (tests/sim,
isocam_gcode_sim): machine time at the program's feeds and 5000 mm/min
rapids, cutting and rapid length, the most material left on the faces where
the ball can reach and the deepest overcut.

`./run bench` runs it in three steps (this file, three modes, chosen by
ISOCAM_S3D_MODE; ISOCAM_S3D_OUT names the folder the steps share):

  isocam   under the host's freecadcmd, with the IsoCAM addon
           (ISOCAM_ADDON_DIR): one Job per model with an Adaptive Isocurve op
           at ScallopHeight h; recompute timed, posted with linuxcnc.
  surface  under freecadcmd of FreeCAD 1.0 in the trixie chroot (Debian ships
           OpenCamLib there): one Job per model and stepover with FreeCAD's
           3D Surface (Planar, Line, single pass, whole model); timed, posted.
  report   plain python3 on the host: runs isocam_gcode_sim (ISOCAM_SIM,
           with rs274 from LinuxCNC) on every posted program, writes
           bench/surface3d_results.json and .md and the README's table.

The 3D Surface runs per model: the stepover whose flat-ground cusp is h (the
nominal setting for the same scallop, as IsoCAM's delta), then finer ones;
the report names the coarsest whose measured material left is no more than
IsoCAM's, the "same measured scallop" of the issue.
"""

import json
import math
import os
import subprocess
import sys
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DATA = os.path.join(ROOT, "tests", "data")
sys.path.insert(0, os.path.join(ROOT, "tests", "sim"))
import sim_command  # noqa: E402  (the simulator's command line)

OUT = os.environ.get("ISOCAM_S3D_OUT") or os.path.join(ROOT, "out", "surface3d")

# The bench's rates for every program (as isocam_finish_bench's estimate):
# XY feed 1200 mm/min, pure Z feed 400, rapids 5000; no acceleration.
HORIZ_FEED, VERT_FEED, RAPID_RATE = 1200.0, 400.0, 5000.0


class Case:
    """One model: its file in tests/data, the faces IsoCAM finishes (None: all;
    3D Surface always takes the whole model, which is these faces), the ball
    radius and scallop height of the IsoCAM bench job, 3D Surface's sample
    interval along its lines (mm) and mesh deflection (mm; None: FreeCAD's
    default, the Job's GeometryTolerance / 4), the finer stepovers tried (% of
    the diameter) and the simulator's sample spacing on the faces (mm)."""

    def __init__(self, name, faces, radius, scallop, sample_interval, deflection, finer, spacing):
        self.name = name
        self.faces = faces
        self.radius = radius
        self.scallop = scallop
        self.sample_interval = sample_interval
        self.deflection = deflection
        self.finer = finer
        self.spacing = spacing

    @property
    def key(self):
        return self.name.split(".")[0]

    def nominal_stepover(self):
        """The stepover (% of the diameter) whose cusp on flat ground is h:
        delta = 2 sqrt(2 r h - h^2), IsoCAM's flat-ground spacing."""
        r, h = self.radius, self.scallop
        return round(100.0 * 2.0 * math.sqrt(2.0 * r * h - h * h) / (2.0 * r), 2)

    def stepovers(self):
        return [self.nominal_stepover()] + list(self.finer)


# MAT's one face holds 6160 Bezier patches: FreeCAD's default mesh deflection
# (0.0025 mm) makes OpenCASCADE's mesher take more than 6 GB (23 GB when not
# capped), and 0.02 mm takes about 2.5 GB and 160 s on this machine, once for
# the model and once for the "safe" mesh of each run. MAT is run at 0.02 mm
# for that reason, which bounds what 3D Surface can reach there (a mesh
# inscribed in the surface: up to 0.02 mm left in valleys, cut on ridges).
# Its finer run is 4 %: 2 % ran over 30 min of wall time without finishing
# (4 % takes about 19 min).
CASES = [
    Case("MAT.brep", [1], 3.0, 0.01, 0.1, 0.02, (4.0,), 0.05),
    Case("shell1.brep", None, 2.0, 0.01, 0.1, None, (3.0,), 0.04),
    Case("Ball.brep", None, 1.0, 0.01, 0.1, None, (5.0,), 0.04),
]


def stepover_key(stepover):
    return ("%g" % stepover).replace(".", "p")


# -- FreeCAD side (modes isocam and surface) ---------------------------------


def _freecad_runs(mode):
    import FreeCAD
    import Part

    sys.path.insert(0, ROOT)  # freecad_ext.scripting (pure Python) from the source tree
    addon = os.environ.get("ISOCAM_ADDON_DIR")
    if mode == "isocam" and addon:
        sys.path.insert(0, addon)
    from freecad_ext import compat, scripting

    os.makedirs(OUT, exist_ok=True)
    version = ".".join(FreeCAD.Version()[:3])

    def job_for(case, label):
        doc = FreeCAD.newDocument(label)
        shape = Part.Shape()
        shape.read(os.path.join(DATA, case.name))
        model = doc.addObject("Part::Feature", case.key)
        model.Shape = shape
        job = scripting.make_job(model)
        tc = scripting.make_ball_end_tool_controller(
            job,
            2 * case.radius,
            horiz_feed="%g mm/min" % HORIZ_FEED,
            vert_feed="%g mm/min" % VERT_FEED,
        )
        # The ball end alone: FreeCAD 1.0's findToolController fails headless
        # when a Job holds more than one (its default end mill and this).
        for other in [t for t in job.Tools.Group if t != tc]:
            job.Tools.removeObject(other)
            doc.removeObject(other.Name)
        doc.recompute()  # the Job, stock and tool first: not timed
        return doc, job, tc

    def faces_of(case, job):
        """FreeCAD's face numbers (1-based) the programs are measured on."""
        return list(case.faces or range(1, len(job.Model.Group[0].Shape.Faces) + 1))

    def timed_recompute(doc):
        wall, cpu = time.monotonic(), time.process_time()
        doc.recompute()
        return time.monotonic() - wall, time.process_time() - cpu

    def finish(doc, job, op, name, meta):
        if "Invalid" in op.State:
            raise RuntimeError("%s: the op is invalid after recompute" % name)
        ngc = os.path.join(OUT, name + ".ngc")
        scripting.post_job(job, ngc)
        meta.update(
            {
                "freecad": version,
                "ngc": os.path.basename(ngc),
                "tool_number": op.ToolController.ToolNumber,
                "commands": len(op.Path.Commands),
            }
        )
        with open(os.path.join(OUT, name + ".json"), "w") as out:
            json.dump(meta, out, indent=1)
        print(
            "%s: %.1f s wall, %.1f s CPU, %d commands"
            % (name, meta["wall_s"], meta["cpu_s"], meta["commands"])
        )
        sys.stdout.flush()
        FreeCAD.closeDocument(doc.Name)

    only = os.environ.get("ISOCAM_S3D_CASES")  # e.g. "MAT,shell1" to run a few
    for case in CASES:
        if only and case.key not in only.split(","):
            continue
        base = {
            "model": case.name,
            "radius": case.radius,
            "scallop_height": case.scallop,
        }
        if mode == "isocam":
            from freecad_ext import adaptive_isocurve

            doc, job, tc = job_for(case, "IsoCAM_" + case.key)
            op = adaptive_isocurve.Create(
                adaptive_isocurve.OP_NAME, parentJob=job, toolController=tc
            )
            clone = job.Model.Group[0]
            op.Base = [(clone, ["Face%d" % f for f in faces_of(case, job)])]
            op.ScallopHeight = case.scallop
            wall, cpu = timed_recompute(doc)
            meta = dict(
                base,
                op="IsoCAM Adaptive Isocurve",
                faces=faces_of(case, job),
                wall_s=wall,
                cpu_s=cpu,
            )
            meta["guaranteed_scallop"] = op.GuaranteedScallop.Value
            meta["guaranteed_overcut"] = op.GuaranteedOvercut.Value
            meta["op_machine_time_min"] = op.MachineTime / 60.0
            finish(doc, job, op, "%s-isocam" % case.key, meta)
        else:
            Surface = compat._import_first("Path.Op.Surface", "PathScripts.PathSurface")
            stepovers = case.stepovers()
            if os.environ.get("ISOCAM_S3D_STEPOVERS"):  # e.g. "4,2": a few, to try settings
                stepovers = [float(s) for s in os.environ["ISOCAM_S3D_STEPOVERS"].split(",")]
            for stepover in stepovers:
                doc, job, tc = job_for(case, "Surface_%s_%s" % (case.key, stepover_key(stepover)))
                with compat.active_document(doc):
                    op = Surface.Create("Surface", parentJob=job)
                op.ToolController = tc
                # The whole model (no Base): every face, in its bound box.
                op.ScanType = "Planar"
                op.LayerMode = "Single-pass"
                op.CutPattern = "Line"
                op.CutPatternAngle = 0.0
                op.BoundBox = "Stock"
                # Off, the cutter's centre may go a radius beyond the model's
                # outline, so the ball reaches the faces up to their edges
                # as IsoCAM's does; on (FreeCAD's default) it stays a radius
                # inside and leaves a band of up to r uncut along every
                # open edge (MAT: 1 to 3 mm wide, material left >= 0.5 mm).
                op.BoundaryEnforcement = False
                op.StepOver = stepover
                op.SampleInterval = case.sample_interval
                op.DepthOffset = 0.0
                if case.deflection is not None:
                    op.LinearDeflection = case.deflection
                wall, cpu = timed_recompute(doc)
                meta = dict(
                    base,
                    op="FreeCAD 3D Surface",
                    faces=faces_of(case, job),
                    stepover_percent=stepover,
                    stepover_mm=2 * case.radius * stepover / 100.0,
                    sample_interval=op.SampleInterval.Value,
                    linear_deflection=op.LinearDeflection.Value,
                    optimize_linear_paths=bool(op.OptimizeLinearPaths),
                    boundary_enforcement=bool(op.BoundaryEnforcement),
                    wall_s=wall,
                    cpu_s=cpu,
                )
                finish(doc, job, op, "%s-surface-%s" % (case.key, stepover_key(stepover)), meta)


# -- the report (mode report, plain python3) ---------------------------------


def rule_machine_time(canon_path):
    """Machine time (min) of a program from rs274's canonical moves, by the
    bench's one rule for every program, whatever feeds it asks for: a feed
    straight along Z at VERT_FEED, any other feed at HORIZ_FEED, a rapid at
    RAPID_RATE; no acceleration. The first move is left out (its start, the
    machine's position before the program, is unknown). Also returns the
    feed lengths along Z alone and otherwise, and the rapid length (mm)."""
    import re

    call = re.compile(r"(STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED)\(([^)]*)\)")
    pos = None
    z_feed = xy_feed = rapid = 0.0
    with open(canon_path) as f:
        for line in f:
            m = call.search(line)
            if not m:
                continue
            if m.group(1) == "ARC_FEED":
                raise RuntimeError("%s: arcs are not estimated by rule_machine_time" % canon_path)
            new = [float(v) for v in m.group(2).split(",")[:3]]
            if pos is not None:
                d = math.dist(pos, new)
                if m.group(1) == "STRAIGHT_TRAVERSE":
                    rapid += d
                elif abs(new[0] - pos[0]) < 1e-9 and abs(new[1] - pos[1]) < 1e-9:
                    z_feed += d
                else:
                    xy_feed += d
            pos = new
    minutes = z_feed / VERT_FEED + xy_feed / HORIZ_FEED + rapid / RAPID_RATE
    return minutes, z_feed, xy_feed, rapid


def _simulate(case, meta, sim, rs274):
    """The simulator's JSON summary of one posted program; kept beside it
    (<name>.sim.json) and reused while newer than the program."""
    ngc = os.path.join(OUT, meta["ngc"])
    kept = ngc[: -len(".ngc")] + ".sim.json"
    if os.path.exists(kept) and os.path.getmtime(kept) > os.path.getmtime(ngc):
        with open(kept) as f:
            return json.load(f)
    table = os.path.join(OUT, "tool%d.tbl" % meta["tool_number"])
    sim_command.write_tool_table(table, meta["tool_number"], 2 * case.radius)
    cmd = sim_command.command(
        sim,
        os.path.join(DATA, case.name),
        meta["faces"],
        case.radius,
        ngc,
        rs274=rs274,
        tool_table=table,
        spacing=case.spacing,
        scallop=case.scallop,
        extra=[
            "--rapid-rate",
            repr(RAPID_RATE),
            "--threads",
            "2",
            "--canon-out",
            ngc[: -len(".ngc")] + ".canon",
        ],
    )
    started = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError("%s: isocam_gcode_sim failed: %s" % (meta["ngc"], proc.stderr.strip()))
    print("%s: simulated in %.0f s" % (meta["ngc"], time.monotonic() - started))
    sys.stdout.flush()
    with open(kept, "w") as out:
        out.write(proc.stdout)
    return json.loads(proc.stdout)


def _row(meta, sim):
    row = dict(meta)
    minutes, z_feed, xy_feed, rapid = rule_machine_time(
        os.path.join(OUT, meta["ngc"][: -len(".ngc")] + ".canon")
    )
    row.update(
        {
            "machine_time_min": minutes,
            "z_feed_length": z_feed,
            "xy_feed_length": xy_feed,
            "rule_rapid_length": rapid,
            "sim_machine_time_min": sim["machine_time_min"],
            "feed_time_min": sim["feed_time_min"],
            "cutting_length": sim["lengths"]["cutting"],
            "feed_length": sim["lengths"]["feed"],
            "plunge_length": sim["lengths"]["plunge"],
            "rapid_length": sim["lengths"]["rapid"],
            "moves": sim["moves"]["total"],
            "measured_left": sim["left"]["max"],
            "measured_left_at": sim["left"]["at"],
            "measured_overcut": sim["overcut"]["max"],
            "measured_overcut_at": sim["overcut"]["at"],
            "rapid_overcut": sim["rapid_overcut"]["max"],
            "within_scallop_fraction": sim["coverage"],
            "reachable_fraction": sim["reachable_fraction"],
            "uncovered_samples": sim["uncovered_samples"],
            "picked_samples": sim["picked_samples"],
        }
    )
    return row


def _summary(case, iso, surfaces):
    """The issue's comparison for one model: the coarsest 3D Surface run whose
    measured material left is no more than IsoCAM's."""
    same = [
        s
        for s in surfaces
        if s["measured_left"] <= iso["measured_left"] and s["uncovered_samples"] == 0
    ]
    out = {
        "model": case.name,
        "isocam_left": iso["measured_left"],
        "isocam_machine_time_min": iso["machine_time_min"],
    }
    if same:
        best = max(same, key=lambda s: s["stepover_percent"])
        out.update(
            {
                "surface_stepover_percent": best["stepover_percent"],
                "surface_left": best["measured_left"],
                "surface_machine_time_min": best["machine_time_min"],
                "reached": True,
            }
        )
    else:
        finest = min(surfaces, key=lambda s: s["stepover_percent"])
        if finest["uncovered_samples"]:
            out["surface_uncovered_samples"] = finest["uncovered_samples"]
        out.update(
            {
                "surface_stepover_percent": finest["stepover_percent"],
                "surface_left": finest["measured_left"],
                "surface_machine_time_min": finest["machine_time_min"],
                "reached": False,
            }
        )
    return out


def _table(rows, summaries, machine):
    lines = [
        "Measured by `./run bench` on %s. Each program is posted with FreeCAD's linuxcnc post and "
        "measured by tests/sim's isocam_gcode_sim (rs274's canonical moves, the ball swept over points "
        "sampled on the faces). Machine time: one rule for every program, from those canonical moves "
        "(rule_machine_time): feeds straight along Z at %g mm/min, other feeds at %g, rapids at %g, "
        "no acceleration (3D Surface's own program feeds its plunges at the XY feed; the "
        "simulator's time at the programs' own feeds is in the JSON); cutting length: fed length without "
        "the entry plunges; material left: the most, where the ball can reach the picked faces "
        "(capped at 0.5 mm; beyond it a point counts as uncovered), within h: the part of the "
        "reachable area left within the scallop height h; overcut: the deepest cut below any face. "
        "Compute: the op's recompute, wall and CPU time (IsoCAM on the host's FreeCAD, 3D Surface on "
        "FreeCAD 1.0 with OpenCamLib in the trixie chroot; the same machine). 3D Surface: Planar, "
        "Line at 0 degrees, single pass, the whole model in the stock's bound box, OptimizeLinearPaths "
        "on (FreeCAD's default), BoundaryEnforcement off (the cutter may pass the outline by a radius, "
        "so the ball reaches the faces' edges); stepover, sample interval and mesh deflection (LinearDeflection) as "
        "shown." % (machine, VERT_FEED, HORIZ_FEED, RAPID_RATE),
        "",
        "| model | operation | stepover / sample interval / mesh deflection (mm) | compute wall / CPU (s) | machine time (min) "
        "| cutting (mm) | rapid (mm) | moves | material left (mm) | within h | overcut (mm) | rapid overcut (mm) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["op"].startswith("IsoCAM"):
            step = "adaptive (h %g)" % r["scallop_height"]
        else:
            step = "%.3f (%g %%) / %g / %g" % (
                r["stepover_mm"],
                r["stepover_percent"],
                r["sample_interval"],
                r["linear_deflection"],
            )
        within = (
            "-"
            if r["within_scallop_fraction"] is None
            else "%.2f %%" % (100 * r["within_scallop_fraction"])
        )
        left = "%.4f" % r["measured_left"]
        if r["uncovered_samples"]:
            left = ">= 0.5 (%d points)" % r["uncovered_samples"]
        lines.append(
            "| %s (r %g, h %g) | %s | %s | %.1f / %.1f | %.1f | %.0f | %.0f | %d | %s | %s | %.4f | %.4f |"
            % (
                r["model"],
                r["radius"],
                r["scallop_height"],
                r["op"],
                step,
                r["wall_s"],
                r["cpu_s"],
                r["machine_time_min"],
                r["cutting_length"],
                r["rapid_length"],
                r["moves"],
                left,
                within,
                r["measured_overcut"],
                r["rapid_overcut"],
            )
        )
    lines.append("")
    lines.append(
        "At the same measured material left (the coarsest 3D Surface run leaving no more than IsoCAM):"
    )
    lines.append("")
    for s in summaries:
        if s["reached"]:
            lines.append(
                "- %s: IsoCAM %.1f min (left %.4f mm); 3D Surface at %g %% %.1f min (left %.4f mm): "
                "IsoCAM takes %.0f %% of its machine time."
                % (
                    s["model"],
                    s["isocam_machine_time_min"],
                    s["isocam_left"],
                    s["surface_stepover_percent"],
                    s["surface_machine_time_min"],
                    s["surface_left"],
                    100 * s["isocam_machine_time_min"] / s["surface_machine_time_min"],
                )
            )
        else:
            lines.append(
                "- %s: IsoCAM %.1f min (left %.4f mm); no 3D Surface run reached it: the finest, %g %%, "
                "takes %.1f min and leaves %s mm."
                % (
                    s["model"],
                    s["isocam_machine_time_min"],
                    s["isocam_left"],
                    s["surface_stepover_percent"],
                    s["surface_machine_time_min"],
                    ">= 0.5" if s.get("surface_uncovered_samples") else "%.4f" % s["surface_left"],
                )
            )
    return "\n".join(lines) + "\n"


def _splice_readme(md):
    path = os.path.join(ROOT, "README.md")
    begin, end = "<!-- surface3d-bench:begin -->\n", "<!-- surface3d-bench:end -->"
    with open(path) as f:
        text = f.read()
    a, b = text.find(begin), text.find(end)
    if a < 0 or b < a:
        print("README.md has no %s ... %s section; table not spliced" % (begin.strip(), end))
        return
    with open(path, "w") as f:
        f.write(text[: a + len(begin)] + md + text[b:])


def _report():
    sim = os.environ.get("ISOCAM_SIM") or os.path.join(
        ROOT, "build", "tests", "sim", "isocam_gcode_sim"
    )
    rs274 = os.environ.get("ISOCAM_RS274", "rs274")
    machine = (
        os.environ.get("ISOCAM_S3D_MACHINE") or "this project's machine (%d cores)" % os.cpu_count()
    )
    rows, summaries, missing = [], [], []
    for case in CASES:
        metas = []
        for name in ["%s-isocam" % case.key] + [
            "%s-surface-%s" % (case.key, stepover_key(s)) for s in case.stepovers()
        ]:
            path = os.path.join(OUT, name + ".json")
            if not os.path.exists(path):
                # A run that failed or was stopped: reported as missing.
                missing.append(name)
                continue
            with open(path) as f:
                metas.append(json.load(f))
        case_rows = [_row(m, _simulate(case, m, sim, rs274)) for m in metas]
        rows += case_rows
        iso = [r for r in case_rows if r["op"].startswith("IsoCAM")]
        surfaces = [r for r in case_rows if not r["op"].startswith("IsoCAM")]
        if iso and surfaces:
            summaries.append(_summary(case, iso[0], surfaces))
    if not rows:
        raise RuntimeError("no posted program in %s: run the isocam and surface steps first" % OUT)
    results = {
        "rates": {"horiz_feed": HORIZ_FEED, "vert_feed": VERT_FEED, "rapid": RAPID_RATE},
        "rows": rows,
        "same_measured_scallop": summaries,
        "missing": missing,
    }
    with open(os.path.join(HERE, "surface3d_results.json"), "w") as out:
        json.dump(results, out, indent=1)
    md = _table(rows, summaries, machine)
    if missing:
        md += "\nNot measured in this run (failed or stopped): %s.\n" % ", ".join(missing)
    with open(os.path.join(HERE, "surface3d_results.md"), "w") as out:
        out.write(md)
    _splice_readme(md)
    print(md)


def _main():
    mode = os.environ.get("ISOCAM_S3D_MODE", "")
    status = 0
    try:
        if mode in ("isocam", "surface"):
            _freecad_runs(mode)
        elif mode == "report":
            _report()
        else:
            raise SystemExit("ISOCAM_S3D_MODE must be isocam, surface or report, got '%s'" % mode)
    except BaseException:
        traceback.print_exc()
        status = 1
    sys.stdout.flush()
    sys.stderr.flush()
    # freecadcmd runs this file as a module and ignores uncaught exceptions.
    os._exit(status)


_main()
