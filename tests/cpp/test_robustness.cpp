// Robustness (issue 15): inputs that once crashed, hung or exhausted memory
// end in a clear error or a correct result.
#include <gtest/gtest.h>
#include <pthread.h>

#include <functional>
#include <string>

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <fstream>
#include <sstream>

#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "support/models.h"
#include "isocam/pocketing.h"
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
    const std::string e = read_error(full.substr(0, static_cast<std::size_t>(f * static_cast<double>(full.size()))));
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
  const std::string head = "DBRep_DrawableShape\nCASCADE Topology V1, (c) Matra-Datavision\n"
                           "Locations 0\nCurve2ds 0\nCurves 1\n6 1 1 0 0 0 ";
  for (const char* w : {"-1", "0", "nan"}) {
    const std::string e = read_error(head + w + " 1 0 0 1\nPolygon3D 0\n");
    EXPECT_NE(e.find(std::string("brep: ")), std::string::npos) << w;
    EXPECT_NE(e.find("at byte"), std::string::npos) << w << ": " << e;
  }
  EXPECT_NE(read_error(head + "1e50 1 0 0 1e-50\n").find("weights span"), std::string::npos);
}

}  // namespace
}  // namespace isocam
