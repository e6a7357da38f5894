// Test models: built in code, or read from tests/data.
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

namespace isocam::test {

std::string data_path(const std::string& name);
TopoDS_Shape load(const std::string& name);  // tests/data/<name>
TopoDS_Face face(const TopoDS_Shape& shape, int index);

// A ruled surface like Elber & Cohen's Figure 2: three cubic Bezier patches
// along u, 300 mm long; the ruling (v) is 100 mm wide at both ends and 5-10
// mm in the middle. Smooth (C1) at the patch joints, or with `creased` only
// C0 there (the normal jumps across the joints).
TopoDS_Face figure2_ruled_surface(bool creased = false);

// The hill alone: a B-spline face over 150 x 150 mm, a bump 25 mm high
// with a gentle wave on it (3 mm), smooth (C2).
TopoDS_Face smooth_hill();

// Elber & Cohen's "house on the hill", built in code: the smooth hill (a
// solid 30 mm deep under it) fused with a 40 x 30 mm house with a
// gable roof (no overhang: a 3-axis job has no face that looks down) that
// stands on the slope. The hill's top face gets a hole where
// the house stands and the walls are trimmed by the hill: several trimmed
// faces meeting at concave corners (walls and hill) and convex ones (eaves,
// ridge).
TopoDS_Shape house_on_the_hill();
// Its faces a finishing job picks: the hill's top face and the house's
// faces above the ground (not the block's sides and bottom).
std::vector<int> house_on_the_hill_picked(const TopoDS_Shape& shape);

// A compound of the shapes, in their order (face i of it is the i-th face
// met, as FreeCAD's FaceN).
TopoDS_Shape compound(const std::vector<TopoDS_Shape>& shapes);

// The shape scaled uniformly about the origin.
TopoDS_Shape scaled(const TopoDS_Shape& shape, double factor);

}  // namespace isocam::test
