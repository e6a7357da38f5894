// TrimDomain::contains() against OpenCASCADE's exact face classifier
// (BRepClass_FaceClassifier on the point in space, which projects it onto
// the face and classifies on the edges' own curves; the core uses neither).
// Points anywhere on the faces' parameter rectangles, and points on either
// side of the boundary at 1e-3, 1e-5 and 1e-7 of the range from where it
// crosses an iso-line of the grid: where the core decides by the winding
// number of the p-curves' Bezier spans, the one place it can go wrong; and
// points on the sides of the faces' parameter rectangles, on the boundary
// where a side bounds the face (contains() counts the boundary in). Each
// point is asked of contains() and of contains_uncached() (which skips the
// cache of answers).
#include <gtest/gtest.h>

#include <BRepClass_FaceClassifier.hxx>
#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"
#include "isocam/brep_io.h"
#include "support/models.h"

namespace isocam {
namespace {

// The reference's answer at grid point (u, v): IN, OUT or ON (within `tol`
// mm in space).
TopAbs_State reference(const TopoDS_Face& face, const PatchGrid& grid, double u, double v,
                       double tol = 1e-7) {
  BRepClass_FaceClassifier c(face, grid.eval(u, v), tol);
  return c.State();
}

struct Tally {
  int checked = 0, near_edge = 0, on_boundary = 0, wrong = 0;
  std::string first_wrong;
};

void check_point(const TopoDS_Face& face, const PatchGrid& grid, const TrimDomain& trim, double u,
                 double v, Tally* t) {
  const TopAbs_State ref = reference(face, grid, u, v);
  if (ref == TopAbs_ON) return;
  ++t->checked;
  const bool in = ref == TopAbs_IN;
  if (trim.contains(u, v) != in || trim.contains_uncached(u, v) != in) {
    if (t->wrong++ == 0)
      t->first_wrong = "face " + std::to_string(trim.face_label()) + " at (" + std::to_string(u) +
                       ", " + std::to_string(v) + ")";
  }
}

// Random points of each face's grid rectangle, and pairs across the
// boundary on iso-lines: where two of 48 samples along the line differ, the
// crossing is bisected to 1e-12 of the range and points at `offsets` of the
// range on both sides are checked.
Tally check_model(const std::vector<TopoDS_Face>& faces, int points_per_face, int lines_per_face) {
  Tally t;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const PatchGrid grid = PatchGrid::from_face(faces[i], static_cast<int>(i));
    const TrimDomain trim(faces[i], grid, static_cast<int>(i));
    const double u0 = grid.umin(), u1 = grid.umax(), v0 = grid.vmin(), v1 = grid.vmax();
    for (int k = 0; k < points_per_face; ++k)
      check_point(faces[i], grid, trim, u0 + (u1 - u0) * unit(rng), v0 + (v1 - v0) * unit(rng), &t);
    // On the sides of the grid's rectangle: on the face's boundary where
    // that side bounds the face (the reference says ON within 1e-9 mm:
    // contains() must say yes), else inside or outside.
    for (int k = 0; k < points_per_face; ++k) {
      const double s = unit(rng);
      const double u = k % 4 == 0 ? u0 : k % 4 == 1 ? u1 : u0 + (u1 - u0) * s;
      const double v = k % 4 == 2 ? v0 : k % 4 == 3 ? v1 : v0 + (v1 - v0) * s;
      const TopAbs_State ref = reference(faces[i], grid, u, v, 1e-9);
      if (ref != TopAbs_ON) {
        check_point(faces[i], grid, trim, u, v, &t);
        continue;
      }
      ++t.on_boundary;
      if ((!trim.contains(u, v) || !trim.contains_uncached(u, v)) && t.wrong++ == 0)
        t.first_wrong = "face " + std::to_string(i) + " on its boundary at (" + std::to_string(u) +
                        ", " + std::to_string(v) + ")";
    }
    for (int line = 0; line < lines_per_face; ++line) {
      const bool along_u = line % 2 == 0;
      const double level = along_u ? v0 + (v1 - v0) * unit(rng) : u0 + (u1 - u0) * unit(rng);
      const double a = along_u ? u0 : v0, b = along_u ? u1 : v1;
      auto at = [&](double s) {
        return along_u ? reference(faces[i], grid, s, level) : reference(faces[i], grid, level, s);
      };
      const int n = 48;
      TopAbs_State prev = at(a);
      for (int k = 1; k <= n; ++k) {
        const double sa = a + (b - a) * (k - 1) / n, sb = a + (b - a) * k / n;
        const TopAbs_State cur = at(sb);
        if (prev == TopAbs_ON || cur == TopAbs_ON || cur == prev) {
          prev = cur;
          continue;
        }
        double lo = sa, hi = sb;
        while (hi - lo > 1e-12 * (b - a)) {
          const double m = 0.5 * (lo + hi);
          (at(m) == prev ? lo : hi) = m;
        }
        for (double off : {1e-3, 1e-5, 1e-7})
          for (double side : {-1.0, 1.0}) {
            const double s = std::clamp(0.5 * (lo + hi) + side * off * (b - a), a, b);
            const int before = t.checked;
            if (along_u)
              check_point(faces[i], grid, trim, s, level, &t);
            else
              check_point(faces[i], grid, trim, level, s, &t);
            t.near_edge += t.checked - before;
          }
        prev = cur;
      }
    }
  }
  return t;
}

// No point where contains() and the reference disagree, and at least the
// given numbers of points near an edge and on the boundary checked (the
// sampling reaches what it should).
void expect_agreement(const std::vector<TopoDS_Face>& faces, int points_per_face,
                      int lines_per_face, int min_near_edge, int min_on_boundary) {
  const Tally t = check_model(faces, points_per_face, lines_per_face);
  EXPECT_EQ(t.wrong, 0) << t.first_wrong;
  EXPECT_GT(t.near_edge, min_near_edge);
  EXPECT_GT(t.on_boundary, min_on_boundary);
}

TEST(TrimDomain, ContainsAgreesWithTheExactClassifierOnBall) {
  // Spheres, cylinders and tori with seams and poles, a bore, B-spline faces.
  expect_agreement(faces_of(test::load("Ball.brep")), 60, 12, 500, 50);
}

TEST(TrimDomain, ContainsAgreesWithTheExactClassifierOnTheHouseOnTheHill) {
  // The hill's B-spline top face with the house's hole; planar walls
  // trimmed by the hill.
  expect_agreement(faces_of(test::house_on_the_hill()), 60, 24, 500, 50);
}

TEST(TrimDomain, ContainsAgreesWithTheExactClassifierOnShell1) {
  // 99 faces, most of them bounded by their parameter rectangles; one
  // whose p-curves leave a gap of 1.4e-5 of its range at a corner.
  expect_agreement(faces_of(test::load("shell1.brep")), 20, 4, 100, 500);
}

TEST(TrimDomain, WindingIsUsedWhereTheWiresCloseAsLoops) {
  // Every face of these models has closed loops of p-curves with an exact
  // Bezier form: the winding number must be in use on all of them (a
  // self-check that disagreed with the classifier would switch it off).
  for (const char* name : {"Ball.brep", "shell1.brep", "MAT.brep", "house on the hill"}) {
    const std::vector<TopoDS_Face> faces = faces_of(
        std::string(name) == "house on the hill" ? test::house_on_the_hill() : test::load(name));
    int used = 0;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const PatchGrid grid = PatchGrid::from_face(faces[i], static_cast<int>(i));
      used += TrimDomain(faces[i], grid, static_cast<int>(i)).uses_winding() ? 1 : 0;
    }
    EXPECT_EQ(used, static_cast<int>(faces.size())) << name;
  }
}

}  // namespace
}  // namespace isocam
