// The material of a solid at height z as a region of line/arc loops: the
// planar section of its solids, edges connected into wires, fitted to arcs
// (curve_fit.cpp), and oriented by nesting depth (an even depth bounds
// material from outside: counter-clockwise; an odd depth a hole in it).
#include <BRepAlgoAPI_Section.hxx>
#include <BRep_Tool.hxx>
#include <ShapeAnalysis_FreeBounds.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_HSequenceOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>
#include <cmath>
#include <gp_Pln.hxx>

#include "isocam/errors.h"
#include "isocam/pocketing.h"
#include "pocketing/curve_fit.h"

namespace isocam {

using namespace pocket;

std::vector<Loop> section_region(const TopoDS_Shape& model, double z, double tol) {
  if (!(tol > 0)) throw InvalidArgument("tolerance must be > 0");
  std::vector<Loop> loops;
  TopTools_IndexedMapOfShape solids;
  TopExp::MapShapes(model, TopAbs_SOLID, solids);
  if (solids.Extent() == 0) return loops;
  Handle(TopTools_HSequenceOfShape) edges = new TopTools_HSequenceOfShape;
  Handle(TopTools_HSequenceOfShape) wires;
  try {
    BRepAlgoAPI_Section sec(model, gp_Pln(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1)), false);
    sec.Approximation(true);
    sec.Build();
    if (!sec.IsDone()) throw GeometryError("pocketing: the section of the model failed");
    for (TopExp_Explorer ex(sec.Shape(), TopAbs_EDGE); ex.More(); ex.Next())
      edges->Append(ex.Current());
    if (edges->Length() == 0) return loops;
    ShapeAnalysis_FreeBounds::ConnectEdgesToWires(edges, std::max(1e-4, 0.1 * tol), false, wires);
  } catch (const Standard_Failure& e) {
    throw GeometryError(std::string("pocketing: the section of the model failed (") +
                        e.GetMessageString() + ")");
  }
  for (int i = 1; i <= wires->Length(); ++i) {
    const TopoDS_Wire w = TopoDS::Wire(wires->Value(i));
    TopoDS_Vertex v1, v2;
    TopExp::Vertices(w, v1, v2);
    if (v1.IsNull() || v2.IsNull()) continue;
    if (!v1.IsSame(v2) &&
        BRep_Tool::Pnt(v1).Distance(BRep_Tool::Pnt(v2)) > std::max(1e-4, 0.1 * tol))
      continue;  // an open chain (a numerical gap in the section): not a profile
    Loop l = loop_of_wire(w, nullptr, tol);
    if (l.empty()) continue;
    if (std::abs(signed_area(l)) <= tol * tol) continue;
    loops.push_back(signed_area(l) > 0 ? l : reversed(l));
  }
  // Orientation by nesting depth.
  std::vector<Loop> out;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const Seg& s = loops[i].front();
    const P2 p = s.at(0.5);
    int depth = 0;
    for (std::size_t j = 0; j < loops.size(); ++j)
      if (j != i && winding_number({loops[j]}, p) != 0) ++depth;
    out.push_back(depth % 2 == 0 ? loops[i] : reversed(loops[i]));
  }
  return resolve_loops(out);
}

}  // namespace isocam
