"""The command line of isocam_gcode_sim (main.cpp), built in one place for
its Python callers: the FreeCAD tests (tests/freecad/sim_support.py), the
3D Surface bench (bench/surface3d_compare.py) and the residual map
(scripts/residual_map.py). Pure Python: no FreeCAD, no core."""


def write_tool_table(path, number, diameter):
    """A LinuxCNC tool table with one tool of `diameter` mm and no length
    offset, so rs274's canonical moves stay in tool-tip coordinates."""
    with open(path, "w") as out:
        out.write("T%d P%d D%.4f Z+0.0000 ;\n" % (number, number, diameter))


def command(
    sim,
    brep,
    faces,
    radius,
    gcode,
    rs274=None,
    tool_table=None,
    spacing=None,
    scallop=None,
    extra=(),
):
    """The argument list: `faces` a sequence of face indices or a
    comma-separated string; the optional arguments only when given."""
    if not isinstance(faces, str):
        faces = ",".join(str(f) for f in faces)
    cmd = [sim, "--brep", brep, "--faces", faces, "--radius", repr(radius), "--gcode", gcode]
    for flag, value in (("--rs274", rs274), ("--tool-table", tool_table)):
        if value:
            cmd += [flag, value]
    for flag, value in (("--spacing", spacing), ("--scallop", scallop)):
        if value:
            cmd += [flag, repr(value)]
    return cmd + list(extra)
