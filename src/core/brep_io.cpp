#include "isocam/brep_io.h"

#include <fstream>
#include <sstream>

#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include "brep_guard.h"
#include "isocam/errors.h"

namespace isocam {

TopoDS_Shape read_brep(const std::string& text) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InvalidArgument("brep: the B-rep text is empty");
  detail::check_brep_text(text);
  TopoDS_Shape shape;
  try {
    std::istringstream in(text);
    BRep_Builder builder;
    BRepTools::Read(shape, in, builder);
  } catch (const Standard_Failure& e) {
    throw InvalidArgument(std::string("brep: unreadable B-rep text (") + e.GetMessageString() + ")");
  }
  if (shape.IsNull()) throw InvalidArgument("brep: unreadable B-rep text (no shape in it)");
  return shape;
}

TopoDS_Shape read_brep_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidArgument("brep: cannot open file " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return read_brep(ss.str());
}

std::vector<TopoDS_Face> faces_of(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_FACE, map);
  std::vector<TopoDS_Face> faces;
  faces.reserve(static_cast<std::size_t>(map.Extent()));
  for (int i = 1; i <= map.Extent(); ++i) faces.push_back(TopoDS::Face(map(i)));
  return faces;
}

}  // namespace isocam
