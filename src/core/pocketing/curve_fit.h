// B-rep edges and wires to line/arc profiles in XY (curve_fit.cpp).
#pragma once

#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>

#include "pocketing/geom2d.h"

namespace isocam::pocket {

// Appends the edge (in its orientation) projected on XY: exact for lines and
// horizontal circles, arcs within `tol` for other curves; chained exactly
// to the end of `out`.
void append_edge(const TopoDS_Edge& edge, double tol, Loop& out);

// The wire as a closed loop (in the face's orientation when a face is
// given); empty for a wire of degenerate edges only.
Loop loop_of_wire(const TopoDS_Wire& wire, const TopoDS_Face* face, double tol);

}  // namespace isocam::pocket
