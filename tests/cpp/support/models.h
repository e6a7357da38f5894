// Test models: built in code, or read from tests/data.
#pragma once

#include <string>

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

namespace isocam::test {

std::string data_path(const std::string& name);
TopoDS_Shape load(const std::string& name);  // tests/data/<name>
TopoDS_Face face(const TopoDS_Shape& shape, int index);

// A ruled surface like Elber & Cohen's Figure 2: three cubic Bezier patches
// along u, 300 mm long; the ruling (v) is 100 mm wide at both ends and 5-10
// mm in the middle. Smooth (C1) at the patch joints, or with `creased` only
// C0 there (the normal jumps across the joints).
TopoDS_Face figure2_ruled_surface(bool creased = false);

// The shape scaled uniformly about the origin.
TopoDS_Shape scaled(const TopoDS_Shape& shape, double factor);

}  // namespace isocam::test
