"""IsoCAM's FreeCAD glue: Path operations, setup helpers and version compatibility.

Thin by design (docs: ENGINEERING.md): every geometric algorithm lives in the
compiled ``isocam_core`` module; this package only maps FreeCAD properties to
core parameters and core results back to ``Path.Command``s. Everything that
differs between FreeCAD 0.20 (``PathScripts``) and 0.21/1.0 (``Path.*``) is
imported through :mod:`freecad_ext.compat` only.
"""
