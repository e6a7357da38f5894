// Shapes cross into the core as OpenCASCADE B-rep text (FreeCAD's
// Shape.exportBrepToString()). Face indices are 0-based positions in
// TopExp::MapShapes(shape, TopAbs_FACE), which is FreeCAD's FaceN order
// (FaceN == index N-1).
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

namespace isocam {

// Throws InvalidArgument("brep: ...") on empty or unreadable text.
TopoDS_Shape read_brep(const std::string& text);
TopoDS_Shape read_brep_file(const std::string& path);

// All faces in FreeCAD's FaceN order.
std::vector<TopoDS_Face> faces_of(const TopoDS_Shape& shape);

}  // namespace isocam
