#!/usr/bin/env python3
"""Draw what a posted ball-end program really leaves on the model: the
residual map measured by the independent simulator (tests/sim,
isocam_gcode_sim), seen from +z.

    python3 scripts/residual_map.py --brep tests/data/MAT.brep --faces 1 \\
        --radius 3 --gcode out/demo.ngc --png out/residual.png

runs the simulator (LinuxCNC's rs274 reads the G-code) and writes a PNG:
colour = material left above the design (> 0, reds) or overcut below it
(< 0, blues) in mm; grey where the ball cannot reach. The title gives the
measured maxima; the JSON summary goes to the file given by --json (and its
main figures to stdout). Without --gcode, --map draws a map file the
simulator already wrote (its --map option).
"""

import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "sim"))
import sim_command  # noqa: E402  (the simulator's command line)


def simulator(path):
    if path:
        return path
    build = os.environ.get("ISOCAM_BUILD_DIR") or os.path.join(ROOT, "build")
    return os.path.join(build, "tests", "sim", "isocam_gcode_sim")


def run_simulator(args, map_file):
    cmd = sim_command.command(
        simulator(args.sim),
        args.brep,
        args.faces,
        args.radius,
        args.gcode,
        tool_table=args.tool_table,
        spacing=args.spacing,
        scallop=args.scallop,
        extra=["--map", map_file, "--map-step", repr(args.step)],
    )
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit("residual_map: the simulator failed:\n" + proc.stderr)
    return json.loads(proc.stdout)


def read_map(path):
    import numpy as np

    with open(path) as f:
        header = f.readline()
    if "step" not in header:
        sys.exit("residual_map: %s is not a map of isocam_gcode_sim --map" % path)
    step = float(header.split("step")[1])
    data = np.loadtxt(path, comments="#", ndmin=2)
    if data.size == 0:
        sys.exit("residual_map: %s holds no point" % path)
    return step, data


def draw(step, data, png, summary=None, limit=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    x, y, v = data[:, 0], data[:, 1], data[:, 2]
    i = np.rint((x - x.min()) / step).astype(int)
    j = np.rint((y - y.min()) / step).astype(int)
    img = np.full((j.max() + 1, i.max() + 1), np.nan)
    img[j, i] = v
    reach = np.isfinite(v)
    if limit is None:
        limit = max(float(np.max(np.abs(v[reach]))) if reach.any() else 0.0, 1e-6)
    cmap = plt.get_cmap("RdBu_r").copy()
    cmap.set_bad("0.75")
    extent = (x.min() - step / 2, x.max() + step / 2, y.min() - step / 2, y.max() + step / 2)
    fig, ax = plt.subplots(figsize=(9, 8), dpi=130)
    im = ax.imshow(
        img,
        origin="lower",
        extent=extent,
        cmap=cmap,
        vmin=-limit,
        vmax=limit,
        interpolation="nearest",
    )
    fig.colorbar(
        im,
        ax=ax,
        shrink=0.85,
        label="residual (mm): > 0 material left, < 0 overcut; grey: out of reach",
    )
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    title = "measured residual of the posted program (top view, %g mm cells)" % step
    if summary:
        left, cut = summary["left"], summary["overcut"]
        for e, mark, name in ((left, "^", "most left"), (cut, "v", "deepest overcut")):
            if e["at"]:
                ax.plot(
                    e["at"][0],
                    e["at"][1],
                    mark,
                    ms=11,
                    mfc="none",
                    mec="k",
                    mew=1.5,
                    label="%s %.4f mm" % (name, e["max"]),
                )
        ax.legend(loc="upper right", fontsize=8)
        title += (
            "\nball r %g mm: most left %.4f mm, deepest overcut %.4f mm (rapids %.4f), "
            "%.1f %% reachable"
            % (
                summary["ball_radius"],
                left["max"],
                cut["max"],
                summary["rapid_overcut"]["max"],
                100 * summary["reachable_fraction"],
            )
        )
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--brep", help="the model (B-rep file)")
    p.add_argument("--faces", help="picked faces, FreeCAD numbers: 1,2,5")
    p.add_argument("--radius", type=float, help="ball radius (mm)")
    p.add_argument("--gcode", help="the posted program (.ngc)")
    p.add_argument("--tool-table", help="LinuxCNC tool table for rs274")
    p.add_argument("--scallop", type=float, help="coverage: fraction within this (mm)")
    p.add_argument("--spacing", type=float, default=0.05, help="sample spacing (mm)")
    p.add_argument("--step", type=float, default=0.2, help="map cell (mm)")
    p.add_argument("--limit", type=float, help="colour range +- (mm); default: the largest")
    p.add_argument("--map", help="draw this map file instead of running the simulator")
    p.add_argument("--json", help="write the simulator's summary here (with --map: read it)")
    p.add_argument("--sim", help="the isocam_gcode_sim program (default: in the build tree)")
    p.add_argument("--png", required=True, help="the picture to write")
    args = p.parse_args(argv)

    summary = None
    if args.map:
        map_file = args.map
        if args.json and os.path.isfile(args.json):  # the summary written with the map
            with open(args.json) as f:
                summary = json.load(f)
    else:
        missing = [n for n in ("brep", "faces", "radius", "gcode") if getattr(args, n) is None]
        if missing:
            p.error("without --map these are needed: " + ", ".join("--" + m for m in missing))
        map_file = os.path.splitext(args.png)[0] + ".map.txt"
        summary = run_simulator(args, map_file)
        if args.json:
            with open(args.json, "w") as out:
                json.dump(summary, out, indent=2)
        print(
            "most material left  %.5f mm at %s (face %d)"
            % (summary["left"]["max"], summary["left"]["at"], summary["left"]["face"])
        )
        print(
            "deepest overcut     %.5f mm at %s (face %d); by rapids %.5f mm"
            % (
                summary["overcut"]["max"],
                summary["overcut"]["at"],
                summary["overcut"]["face"],
                summary["rapid_overcut"]["max"],
            )
        )
        print(
            "reachable           %.2f %% of the picked area" % (100 * summary["reachable_fraction"])
        )
    step, data = read_map(map_file)
    draw(step, data, args.png, summary, args.limit)
    print("wrote %s" % args.png)


if __name__ == "__main__":
    main()
