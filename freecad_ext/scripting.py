"""Helpers to build and post a Path Job from a script (demo, tests, headless use).

These wrap FreeCAD's own factories (through :mod:`freecad_ext.compat`) with
the defaults a headless run needs: tool controllers with non-zero feeds (a G1
without a feed rate is an error for LinuxCNC) and a post list built without
FreeCAD's GUI post command.
"""

import Path

from freecad_ext import compat


def make_job(model, name="Job"):
    """A Job on the document object `model` (FreeCAD makes its Model clone and stock)."""
    with compat.active_document(model.Document):
        return compat.PathJob.Create(name, [model])


def make_tool_controller(
    job,
    shape_file,
    diameter,
    number=None,
    label=None,
    horiz_feed="1000 mm/min",
    vert_feed="300 mm/min",
    spindle_speed=10000.0,
):
    """A ToolBit of `shape_file` (e.g. "ballend.fcstd", "endmill.fcstd", as
    shipped with FreeCAD) and a tool controller for it, added to `job`."""
    number = job.Proxy.nextToolNumber() if number is None else number
    shape = shape_file.split(".")[0]
    bit = compat.make_tool_bit(job.Document, shape_file, diameter, "%s %g mm" % (shape, diameter))
    with compat.active_document(job.Document):  # the factory adds to it
        tc = compat.PathToolController.Create(
            label or "TC: %s %g mm" % (shape, diameter), tool=bit, toolNumber=number
        )
    tc.HorizFeed = horiz_feed
    tc.VertFeed = vert_feed
    tc.SpindleSpeed = spindle_speed
    job.Proxy.addToolController(tc)
    return tc


def make_ball_end_tool_controller(job, diameter, **kwargs):
    return make_tool_controller(job, "ballend.fcstd", diameter, **kwargs)


def make_bull_nose_tool_controller(job, diameter, corner_radius, **kwargs):
    """A bull nose (ToolBit shape bullnose.fcstd) of `diameter` and
    `corner_radius` (mm): FreeCAD 0.20 and 1.0's shape takes the flat
    bottom's radius, FlatRadius = diameter / 2 - corner_radius, 1.1's the
    CornerRadius (compat.set_corner_radius)."""
    tc = make_tool_controller(job, "bullnose.fcstd", diameter, **kwargs)
    compat.set_corner_radius(tc.Tool, corner_radius)
    return tc


class _FixtureSetup:
    """A pseudo Path object the post emits first: select the work offset and
    go to clearance height above the stock (what FreeCAD's post command does)."""

    def __init__(self, job, fixture):
        self.Name = self.Label = fixture
        clearance = job.Stock.Shape.BoundBox.ZMax + job.SetupSheet.ClearanceHeightOffset.Value
        self.Path = Path.Path([Path.Command(fixture), Path.Command("G0", {"Z": clearance})])


def post_list(job, postname="linuxcnc"):
    """Objects to post, as this FreeCAD's post command lists them (FreeCAD
    1.0+: its post processor's own list, see compat.post_list). On 0.20,
    FreeCAD's "order by fixture" layout: per fixture its set-up, then the
    active ops, each preceded by its tool controller when the tool changes."""
    objects = compat.post_list(job, postname)
    if objects is not None:
        return objects
    objects = []
    for fixture in job.Fixtures:
        objects.append(_FixtureSetup(job, fixture))
        current_tc = None
        for op in job.Operations.Group:
            if not compat.PathUtil.opProperty(op, "Active"):
                continue
            tc = compat.PathUtil.toolControllerForOp(op)
            if tc is not None and tc != current_tc:
                objects.append(tc)
                current_tc = tc
            objects.append(op)
    return objects


def post_job(job, filename, postname="linuxcnc", args="--no-show-editor"):
    """Post `job` with FreeCAD's post script `postname` to `filename`; returns the G-code."""
    script = compat.load_post_script(postname)
    return script.export(post_list(job, postname), filename, args)


# -- checking posted G-code with LinuxCNC's interpreter ---------------------


class Rs274Result:
    """Outcome of ``rs274 -g``: exit status, error lines, canonical calls."""

    def __init__(self, returncode, errors, canon):
        self.returncode = returncode
        self.errors = errors  # interpreter messages (stderr minus "executing")
        self.canon = canon  # the canonical machining calls, one per line

    @property
    def ok(self):
        return self.returncode == 0 and not self.errors

    def motions(self):
        """[(kind, x, y, z)] of the STRAIGHT_TRAVERSE (G0) / STRAIGHT_FEED
        (G1) calls, kind "G0" or "G1", in program units."""
        moves = []
        for line in self.canon:
            for call, kind in (("STRAIGHT_TRAVERSE(", "G0"), ("STRAIGHT_FEED(", "G1")):
                at = line.find(call)
                if at >= 0:
                    args = line[at + len(call) : line.rindex(")")].split(",")
                    moves.append((kind, *(float(a) for a in args[:3])))
        return moves


def run_rs274(ngc_file, tools, rs274="rs274", workdir=None):
    """Interpret `ngc_file` with LinuxCNC's stand-alone interpreter.

    `tools` maps tool number -> diameter (mm); they are written to a tool
    table with zero length offsets, so G43 leaves coordinates unchanged and
    the canonical calls are in the G-code's own (tool-tip) coordinates.
    Invocation: ``rs274 -t tool.tbl -g file.ngc`` (-g: batch, do not stop on
    M0/M1); errors go to stderr and make the exit status non-zero.
    """
    import os
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory(dir=workdir) as tmp:
        table = os.path.join(tmp, "tool.tbl")
        with open(table, "w") as out:
            for number, diameter in sorted(tools.items()):
                out.write("T%d P%d D%.4f Z+0.0000 ;\n" % (number, number, diameter))
        proc = subprocess.run(
            [rs274, "-t", table, "-g", ngc_file],
            stdin=subprocess.DEVNULL,
            capture_output=True,
            text=True,
            cwd=tmp,
        )
    errors = [line for line in proc.stderr.splitlines() if line.strip() not in ("", "executing")]
    return Rs274Result(proc.returncode, errors, proc.stdout.splitlines())
