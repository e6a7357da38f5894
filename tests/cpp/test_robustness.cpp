// Robustness (issue 15): inputs that once crashed, hung or exhausted memory
// end in a clear error or a correct result.
#include <gtest/gtest.h>
#include <pthread.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>
#include <algorithm>
#include <fstream>
#include <functional>
#include <gp_Pln.hxx>
#include <sstream>
#include <string>

#include "geometry/patch_grid.h"
#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "isocam/pocketing.h"
#include "support/models.h"
#include "support/pocket_models.h"

namespace isocam {
namespace {

// Runs f on a thread with a small stack (as a GUI's worker thread may have),
// so that recursion as deep as the input would overflow it; rethrows what f
// throws.
void on_small_stack(std::size_t bytes, const std::function<void()>& f) {
  struct Job {
    const std::function<void()>* f;
    std::exception_ptr error;
  } job{&f, nullptr};
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, bytes);
  pthread_t th;
  auto body = [](void* arg) -> void* {
    auto* j = static_cast<Job*>(arg);
    try {
      (*j->f)();
    } catch (...) {
      j->error = std::current_exception();
    }
    return nullptr;
  };
  ASSERT_EQ(pthread_create(&th, &attr, body, &job), 0);
  pthread_join(th, nullptr);
  pthread_attr_destroy(&attr);
  if (job.error) std::rethrow_exception(job.error);
}

// A square pocket at a tiny stepover: an offset tree thousands of levels
// deep, one node per level. Its ordering once recursed once per level.
TEST(Robustness, DeepOffsetTreeIsOrderedWithoutRecursion) {
  PocketParams p;
  p.tool_radius = 0.1;
  p.stepover = 0.004;
  p.tolerance = 0.01;
  p.safe_z = 10;
  const std::vector<Loop> region = make_region(test::rect(0, 0, 20, 20), {});
  PocketResult r;
  on_small_stack(256 * 1024, [&] { r = spiral_pocket(region, {0.0}, p); });
  // (20 - 2 r) / 2 / stepover levels below the first loop.
  EXPECT_GE(r.metrics.tree_depth, 2400);
  EXPECT_EQ(r.metrics.loops, r.metrics.tree_depth + 1);
  // One spiral: every loop is reached by a feed link from the one inside it.
  EXPECT_EQ(r.metrics.retracts, 0);
}

std::string slurp(const std::string& name) {
  std::ifstream in(test::data_path(name));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The message of the InvalidArgument that read_brep throws ("" if none).
std::string read_error(const std::string& text) {
  try {
    read_brep(text);
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(Robustness, GuardedReaderAcceptsTheBundledModels) {
  for (const char* name : {"MAT.brep", "face.brep", "Ball.brep", "shell1.brep", "wing.brep"})
    EXPECT_EQ(read_error(slurp(name)), "") << name;
  // With triangulations and polygons on them, as FreeCAD writes a shape it
  // has displayed.
  TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  BRepMesh_IncrementalMesh mesh(sphere, 0.5);
  std::ostringstream out;
  BRepTools::Write(sphere, out);
  ASSERT_NE(out.str().find("Triangulations 1"), std::string::npos);
  EXPECT_EQ(read_error(out.str()), "");
}

TEST(Robustness, GuardedReaderRejectsHugeCounts) {
  // A header that announces more than any text of its length can hold.
  const std::string text =
      "DBRep_DrawableShape\nCASCADE Topology V1, (c) Matra-Datavision\nLocations 999999999\n";
  const std::string e = read_error(text);
  EXPECT_NE(e.find("Locations count 999999999 exceeds"), std::string::npos) << e;
  EXPECT_NE(e.find("at byte 72"), std::string::npos) << e;
  // A B-spline surface of 10^5 x 10^5 poles in face.brep.
  std::string s = slurp("face.brep");
  const std::size_t k = s.find("Surfaces 21\n");
  ASSERT_NE(k, std::string::npos);
  s.insert(k + 12, "9 0 0 0 0 3 3 100000 100000 2 2\n");
  s.replace(k, 11, "Surfaces 22");
  EXPECT_NE(read_error(s).find("100000 x 100000 poles exceeds"), std::string::npos)
      << read_error(s);
}

TEST(Robustness, GuardedReaderRejectsTruncatedText) {
  const std::string full = slurp("MAT.brep");
  for (double f : {0.1, 0.5, 0.9}) {
    const std::string e =
        read_error(full.substr(0, static_cast<std::size_t>(f * static_cast<double>(full.size()))));
    EXPECT_NE(e.find("at byte"), std::string::npos) << f << ": " << e;
  }
}

TEST(Robustness, GuardedReaderRejectsNonFiniteNumbersAndBadWeights) {
  const std::string face = slurp("face.brep");
  // The first line of the Curves section: a line's coordinates.
  const std::size_t k = face.find("Curves ");
  ASSERT_NE(k, std::string::npos);
  const std::size_t line = face.find('\n', k) + 1;
  const std::size_t num = face.find_first_of("0123456789", line + 2);
  for (const char* bad : {"nan", "-inf", "1e308"}) {
    std::string s = face;
    s.replace(num, 1, bad);
    const std::string e = read_error(s);
    EXPECT_NE(e.find(bad), std::string::npos) << e;
    EXPECT_NE(e.find("at byte " + std::to_string(num)), std::string::npos) << e;
  }
  // A rational Bezier curve with weights w.
  const std::string head =
      "DBRep_DrawableShape\nCASCADE Topology V1, (c) Matra-Datavision\n"
      "Locations 0\nCurve2ds 0\nCurves 1\n6 1 1 0 0 0 ";
  for (const char* w : {"-1", "0", "nan"}) {
    const std::string e = read_error(head + w + " 1 0 0 1\nPolygon3D 0\n");
    EXPECT_NE(e.find(std::string("brep: ")), std::string::npos) << w;
    EXPECT_NE(e.find("at byte"), std::string::npos) << w << ": " << e;
  }
  EXPECT_NE(read_error(head + "1e50 1 0 0 1e-50\n").find("weights span"), std::string::npos);
}

// The message of the InvalidArgument that f throws ("" if none).
std::string invalid_argument(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

IsoParams iso(double r, double h) {
  IsoParams p;
  p.ball_radius = r;
  p.scallop_height = h;
  p.safe_z = 50;
  return p;
}

TEST(Robustness, ToleranceTooFineForTheModelIsRefused) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  IsoParams p = iso(3, 1e-9);
  p.posted_resolution = 0;  // else the posted rounding alone is over the budget
  std::string e = invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); });
  EXPECT_TRUE(has(e, "scallop_height = 1e-09 mm is too fine")) << e;
  EXPECT_TRUE(has(e, "exceeds 1e+06")) << e;
  p = iso(3, 0.05);
  p.chord_tolerance = 1e-12;
  e = invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); });
  EXPECT_TRUE(has(e, "chord_tolerance = 1e-12 mm")) << e;
  // A model 1e6 mm large at 0.01 mm names both.
  const TopoDS_Shape big = BRepPrimAPI_MakeSphere(5e5).Shape();
  e = invalid_argument([&] { adaptive_isocurve(big, {0}, iso(3, 0.01)); });
  EXPECT_TRUE(has(e, "scallop_height = 0.01 mm")) << e;
  EXPECT_TRUE(has(e, "extends 1.73205e+06 mm")) << e;
}

TEST(Robustness, WorkBudgetIsCheckedBeforeTheWork) {
  // The sphere at 0.05 mm needs some thousands of moves: a budget of 100
  // refuses it, naming the estimate and the limit.
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  IsoParams p = iso(3, 0.05);
  p.max_moves = 100;
  std::string e = invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); });
  EXPECT_TRUE(has(e, "work budget: about")) << e;
  EXPECT_TRUE(has(e, "exceed max_moves = 100")) << e;
  // The estimate is a lower bound (about 420 moves here); the planned
  // passes are held to the budget too.
  p = iso(3, 0.05);
  p.max_moves = 1000;
  e = invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); });
  EXPECT_TRUE(has(e, "the points of the planned passes")) << e;
  EXPECT_TRUE(has(e, "exceed max_moves = 1000")) << e;
  p.max_moves = std::nan("");
  EXPECT_TRUE(has(invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); }), "max_moves = nan"));
  // Spiral pocket: the 100 x 60 rectangle with a round island at a
  // stepover of 1e-5 mm is too fine for its size; at 1e-4 mm (some 3 10^6
  // moves) it is over the default budget.
  PocketParams pp;
  pp.tool_radius = 3;
  pp.stepover = 1e-5;
  pp.safe_z = 10;
  const std::vector<Loop> region =
      make_region(test::rect(0, 0, 100, 60), {test::circle(50, 30, 10, false)});
  e = invalid_argument([&] { spiral_pocket(region, {0.0}, pp); });
  EXPECT_TRUE(has(e, "stepover = 1e-05 mm is too fine")) << e;
  pp.stepover = 1e-4;
  e = invalid_argument([&] { spiral_pocket(region, {0.0}, pp); });
  EXPECT_TRUE(has(e, "work budget: about")) << e;
  EXPECT_TRUE(has(e, "stepover of 0.0001 mm")) << e;
  EXPECT_TRUE(has(e, "exceed max_moves = 1e+06")) << e;
  // A budget too small for what an ordinary job computes stops it while
  // it grows.
  pp.stepover = 2.4;
  pp.max_moves = 30;
  e = invalid_argument([&] { spiral_pocket(region, {0.0, -1.0, -2.0}, pp); });
  EXPECT_TRUE(has(e, "exceed max_moves = 30")) << e;
}

TEST(Robustness, ArgumentsOutsideTheirDomainAreRefused) {
  EXPECT_TRUE(
      has(invalid_argument([] { stepover_for_scallop(std::nan(""), 0.1); }), "ball_radius = nan"));
  EXPECT_TRUE(has(invalid_argument([] { stepover_for_scallop(3, 4); }), "scallop_height = 4"));
  EXPECT_TRUE(has(invalid_argument([] { scallop_for_stepover(3, 7); }), "delta = 7"));
  EXPECT_TRUE(has(invalid_argument([] { scallop_for_stepover(3, -1); }), "delta = -1"));
  EXPECT_DOUBLE_EQ(scallop_for_stepover(3, 6), 3.0);
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  IsoParams p = iso(1e300, 0.05);
  EXPECT_TRUE(has(invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); }), "ball_radius = "));
  p = iso(3, 0.05);
  p.safe_z = 1e300;
  EXPECT_TRUE(has(invalid_argument([&] { adaptive_isocurve(sphere, {0}, p); }), "safe_z = "));
  // A lone vertex: no faces, whatever the numbers say.
  const TopoDS_Shape vertex = BRepBuilderAPI_MakeVertex(gp_Pnt(0, 0, 0)).Shape();
  p = iso(0.0005, 0.0001);
  EXPECT_TRUE(has(invalid_argument([&] { adaptive_isocurve(vertex, {0}, p); }), "no faces"));
  PocketParams pp;
  pp.tool_radius = 1e300;
  EXPECT_TRUE(has(invalid_argument(
                      [&] { spiral_pocket(make_region(test::rect(0, 0, 10, 10), {}), {0.0}, pp); }),
                  "tool_radius = 1e+300"));
}

TEST(Robustness, ZLevelRoughingRefusesAModelThatIsNotASolid) {
  const TopoDS_Shape stock = BRepPrimAPI_MakeBox(gp_Pnt(-5, -5, -10), 90, 90, 50).Shape();
  RoughingParams rp;
  rp.pocket.tool_radius = 3;
  rp.pocket.stepover = 3;
  rp.pocket.safe_z = 50;
  rp.depths = {20, 10};
  TopoDS_Compound empty;
  BRep_Builder().MakeCompound(empty);
  // MAT's terrain face (its material side is not closed): once cleared the
  // stock through it.
  const std::vector<std::pair<TopoDS_Shape, std::string>> models = {
      {test::load("MAT.brep"), "(it has 1 faces and no solid)"},
      {BRepBuilderAPI_MakeVertex(gp_Pnt(0, 0, 0)).Shape(), "(it has 0 faces and no solid)"},
      {empty, "(it has 0 faces and no solid)"}};
  for (const auto& [model, says] : models) {
    const std::string e = invalid_argument([&] { zlevel_roughing(model, stock, rp); });
    EXPECT_TRUE(has(e, "model: not a solid " + says)) << e;
  }
}

// tests/data/face.brep is a reversed open face at z = 0: its orientation
// puts the ball under it, where a vertical tool cannot be. The op finishes
// it from its upper side, the only one a vertical tool reaches: every feed
// move's tip is on or above the face (no deeper than the stated overcut),
// nothing is left out as unreachable from above, and the result says the
// face was taken reversed. Whatever the pattern.
TEST(Robustness, OpenFaceTurnedDownIsFinishedFromAbove) {
  const TopoDS_Shape face = test::load("face.brep");
  for (IsoPattern pattern :
       {IsoPattern::Adaptive, IsoPattern::ParallelPlanes, IsoPattern::ConstantScallop}) {
    IsoParams p = iso(3, 0.05);
    p.pattern = pattern;
    const IsoResult r = adaptive_isocurve(face, {0}, p);
    double lowest = 1e300;
    int feeds = 0;
    for (std::size_t i = 0; i < r.path.size(); ++i)
      if (r.path.kind[i] == static_cast<std::uint8_t>(MoveKind::Feed)) {
        lowest = std::min(lowest, r.path.z[i]);
        ++feeds;
      }
    EXPECT_GT(feeds, 100) << int(pattern);
    EXPECT_GE(lowest, -r.metrics.guaranteed_overcut) << int(pattern);
    EXPECT_EQ(r.metrics.unreachable_from_above_length, 0.0) << int(pattern);
    EXPECT_GT(r.metrics.cutting_length, 0.5 * r.metrics.lower_bound_length) << int(pattern);
  }
}

// The face taken reversed is said; a sphere (a solid) and MAT (an open face
// turned up) give no such warning.
TEST(Robustness, OpenFaceTurnedDownIsReported) {
  auto warned = [](const TopoDS_Shape& s, double h) {
    IsoParams p = iso(3, h);
    const IsoResult r = adaptive_isocurve(s, {0}, p);
    for (const std::string& w : r.warnings)
      if (has(w,
              "Face1) is an open face whose orientation puts the ball where a vertical tool "
              "does not reach: finished from its other side"))
        return true;
    return false;
  };
  EXPECT_TRUE(warned(test::load("face.brep"), 0.5));
  EXPECT_FALSE(warned(BRepPrimAPI_MakeSphere(10.0).Shape(), 0.5));
  EXPECT_FALSE(warned(test::load("MAT.brep"), 0.5));
}

// A large plane has area: the degenerate-face test is relative to the
// surface's own derivatives, not to the model's size squared.
TEST(Robustness, LargePlaneIsNotDegenerate) {
  for (double side : {1.0, 1e3, 1e6}) {
    const TopoDS_Face plane = BRepBuilderAPI_MakeFace(gp_Pln(), 0, side, 0, side).Face();
    EXPECT_NO_THROW(PatchGrid::from_face(plane, 0)) << side;
  }
}

}  // namespace
}  // namespace isocam
