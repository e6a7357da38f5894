"""IsoCAM demo: adaptive isocurve finishing of the MAT terrain in a FreeCAD Path Job.

Run with FreeCAD's console (./run demo does this after building and linking
the addon):

    freecadcmd scripts/demo.py

It loads tests/data/MAT.brep (one bicubic B-spline face, 77 x 80 x 33 mm),
makes a Job with a 6 mm ball-end tool and an Adaptive Isocurve op on the face
(scallop 0.01 mm), posts it with FreeCAD's linuxcnc post-processor, checks the
G-code with LinuxCNC's rs274 interpreter when it is installed, and writes to
out/ (next to scripts/):
    demo.ngc    the G-code
    demo.png    the path over the model (top view and oblique view)
    demo.FCStd  the FreeCAD document, to open in the GUI
The exit status is non-zero on any failure.

freecadcmd runs this file as an imported module (not as __main__) and ignores
uncaught exceptions, hence the explicit os._exit at the end.
"""

import os
import shutil
import sys
import time
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "out")
MODEL = os.path.join(ROOT, "tests", "data", "MAT.brep")
BALL_DIAMETER = 6.0  # mm
SCALLOP = 0.01  # mm


def import_glue():
    """freecad_ext from FreeCAD's Mod/IsoCAM link, else from the build tree."""
    try:
        from freecad_ext import adaptive_isocurve, scripting
    except ImportError:
        candidates = [
            os.environ.get("ISOCAM_ADDON_DIR"),
            os.path.join(ROOT, "build", "addon", "IsoCAM"),
        ]
        for folder in candidates:
            if folder and os.path.isdir(os.path.join(folder, "freecad_ext")):
                sys.path.insert(0, folder)
                break
        from freecad_ext import adaptive_isocurve, scripting
    return adaptive_isocurve, scripting


def build_job(adaptive_isocurve, scripting):
    import FreeCAD
    import Part

    doc = FreeCAD.newDocument("IsoCAMDemo")
    shape = Part.Shape()
    shape.read(MODEL)
    model = doc.addObject("Part::Feature", "MAT")
    model.Shape = shape
    job = scripting.make_job(model)
    # The bench's rates (XY feed 1200 mm/min, pure Z 400, rapids 5000).
    tc = scripting.make_ball_end_tool_controller(
        job, BALL_DIAMETER, horiz_feed="1200 mm/min", vert_feed="400 mm/min"
    )
    op = adaptive_isocurve.Create(adaptive_isocurve.OP_NAME, parentJob=job, toolController=tc)
    op.Base = [(job.Model.Group[0], ["Face1"])]
    op.ScallopHeight = SCALLOP
    return doc, job, tc, op


def check_with_rs274(scripting, ngc, tc):
    rs274 = shutil.which("rs274")
    if rs274 is None:
        print("rs274: not installed (package linuxcnc-uspace), G-code not checked")
        return True
    run = scripting.run_rs274(ngc, {tc.ToolNumber: BALL_DIAMETER}, rs274=rs274)
    motions = run.motions()
    feeds = sum(1 for m in motions if m[0] == "G1")
    print(
        "rs274 -t <tool table> -g %s: exit status %d, %d errors, %d motions "
        "(%d G1, %d G0)"
        % (
            os.path.relpath(ngc, ROOT),
            run.returncode,
            len(run.errors),
            len(motions),
            feeds,
            len(motions) - feeds,
        )
    )
    for line in run.errors[:10]:
        print("rs274:", line)
    return run.ok


def path_polylines(path):
    """Split a Path into (cutting polylines, rapid segments), lists of (N,3) arrays.

    Plunges (vertical G1 entries) are left out of the polylines, and so is
    everything before the first move with x, y and z known.
    """
    import numpy as np

    feeds, rapids, current = [], [], []
    pos = None
    for c in path.Commands:
        if c.Name not in ("G0", "G1"):
            continue
        p = c.Parameters
        if pos is None:
            if not all(k in p for k in "XYZ"):
                continue
            pos = (p["X"], p["Y"], p["Z"])
            continue
        new = (p.get("X", pos[0]), p.get("Y", pos[1]), p.get("Z", pos[2]))
        vertical = new[:2] == pos[:2]
        if c.Name == "G1" and not vertical:
            current = current or [pos]
            current.append(new)
        else:
            if len(current) > 1:
                feeds.append(np.array(current))
            current = []
            if c.Name == "G0":
                rapids.append(np.array([pos, new]))
        pos = new
    if len(current) > 1:
        feeds.append(np.array(current))
    return feeds, rapids


def draw(op, face, png):
    """Top view (height-shaded model, passes, rapids) and an oblique view."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import LineCollection
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    def mesh(deflection):
        verts, tris = face.tessellate(deflection)
        return np.array([(v.x, v.y, v.z) for v in verts]), np.array(tris)

    feeds, rapids = path_polylines(op.Path)
    fig = plt.figure(figsize=(16, 7.6), dpi=120)

    top = fig.add_subplot(1, 2, 1)
    xyz, tris = mesh(0.2)
    shade = top.tripcolor(xyz[:, 0], xyz[:, 1], tris, xyz[:, 2], cmap="terrain", shading="gouraud")
    top.add_collection(LineCollection([f[:, :2] for f in feeds], colors="k", linewidths=0.25))
    top.add_collection(
        LineCollection([r[:, :2] for r in rapids], colors="tab:red", linewidths=0.4, alpha=0.5)
    )
    top.autoscale()
    top.set_aspect("equal")
    top.set_xlabel("x (mm)")
    top.set_ylabel("y (mm)")
    top.set_title("top view: cutting passes (black), rapids: hops and moves to SafeHeight (red)")
    fig.colorbar(shade, ax=top, shrink=0.8, label="model height z (mm)")

    side = fig.add_subplot(1, 2, 2, projection="3d")
    xyz, tris = mesh(0.4)
    side.plot_trisurf(
        xyz[:, 0],
        xyz[:, 1],
        xyz[:, 2],
        triangles=tris,
        cmap="terrain",
        linewidth=0,
        alpha=0.6,
    )
    # Two-point segments, not the ragged polylines: matplotlib 3.10's
    # Line3DCollection turns its segments into one array (matplotlib issue
    # 30418), which polylines of different lengths cannot make.
    segments = [np.stack([f[:-1], f[1:]], axis=1) for f in feeds[::3] if len(f) > 1]
    side.add_collection3d(Line3DCollection(np.concatenate(segments), colors="k", linewidths=0.35))
    side.view_init(elev=38, azim=-58)
    side.set_box_aspect(tuple(np.ptp(xyz, axis=0)))
    side.set_xlabel("x (mm)")
    side.set_ylabel("y (mm)")
    side.set_zlabel("z (mm)")
    side.set_title("oblique view, true scale: every 3rd cutting pass (tool tip)")

    fig.suptitle(
        "IsoCAM adaptive isocurve finishing of the MAT terrain, %g mm ball end, "
        "scallop %g mm\n%d sub-isocurves, cutting length %.0f mm, "
        "guaranteed scallop %.4f mm"
        % (
            BALL_DIAMETER,
            SCALLOP,
            op.SubIsocurves,
            op.CuttingLength.Value,
            op.GuaranteedScallop.Value,
        )
    )
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


def main():
    started = time.monotonic()
    adaptive_isocurve, scripting = import_glue()
    os.makedirs(OUT, exist_ok=True)
    doc, job, tc, op = build_job(adaptive_isocurve, scripting)

    computed = time.monotonic()
    doc.recompute()
    compute_seconds = time.monotonic() - computed
    if "Invalid" in op.State or not op.Path.Commands:
        print("demo: the operation failed: %s" % op.getStatusString())
        return 1

    ngc = os.path.join(OUT, "demo.ngc")
    scripting.post_job(job, ngc)
    ok = check_with_rs274(scripting, ngc, tc)
    drawn = time.monotonic()
    draw(op, job.Model.Group[0].Shape.Faces[0], os.path.join(OUT, "demo.png"))
    print("demo: picture drawn in %.1f s" % (time.monotonic() - drawn))
    fcstd = os.path.join(OUT, "demo.FCStd")
    if os.path.exists(fcstd):
        os.remove(fcstd)  # else FreeCAD keeps the old one as demo.FCStd1
    doc.saveAs(fcstd)

    print("")
    print("IsoCAM demo: MAT.brep, %g mm ball end, scallop %g mm" % (BALL_DIAMETER, SCALLOP))
    print("  direction used       %s" % op.DirectionUsed)
    print("  sub-isocurves        %d" % op.SubIsocurves)
    print("  retracts             %d" % op.Retracts)
    print("  cutting length       %.1f mm" % op.CuttingLength.Value)
    print("  rapid length         %.1f mm" % op.RapidLength.Value)
    print(
        "  iso-distance bound   %.4f mm flat, %.4f mm largest (%s bound)"
        % (
            op.IsoDistanceTolerance.Value,
            op.IsoDistanceToleranceMax.Value,
            op.ScallopBound,
        )
    )
    print("  max iso-distance     %.4f mm" % op.MaxIsoDistance.Value)
    print(
        "  guaranteed scallop   %.5f mm (material left, everything included; asked %.5f)"
        % (op.GuaranteedScallop.Value, op.ScallopHeight.Value)
    )
    print(
        "  guaranteed overcut   %.5f mm (asked %.5f; chords %.5f mm, posted %d decimals)"
        % (
            op.GuaranteedOvercut.Value,
            op.OvercutTolerance.Value,
            op.ChordToleranceUsed.Value,
            op.PostPrecision,
        )
    )
    print(
        "  machine time         %.1f min (cutting %.1f min, ratio %.2f; CycleTime %s)"
        % (
            op.MachineTime / 60.0,
            op.CuttingTime / 60.0,
            op.MachineTime / op.CuttingTime if op.CuttingTime > 0 else 0.0,
            op.CycleTime,
        )
    )
    print(
        "  lower bound L*       %.1f mm (cutting length / L* = %.2f)"
        % (op.LowerBoundLength.Value, op.LengthRatio)
    )
    print("  left unreachable     %.1f mm of centre path" % op.UnreachableLength.Value)
    print("  path commands        %d" % len(op.Path.Commands))
    print("  op recompute         %.2f s" % compute_seconds)
    print("  wall time (total)    %.2f s" % (time.monotonic() - started))
    print("  wrote                out/demo.ngc, out/demo.png, out/demo.FCStd")
    if not ok:
        print("demo: rs274 rejected the G-code")
        return 1
    return 0


def _run():
    try:
        status = main()
    except BaseException:
        traceback.print_exc()
        status = 1
    sys.stdout.flush()
    sys.stderr.flush()
    import FreeCAD

    if not FreeCAD.GuiUp:  # in the GUI (run as a macro) just report
        os._exit(status)
    print("demo: exit status %d" % status)


_run()
