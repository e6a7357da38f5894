// The global clearance query against an independent reference: for points
// near a model, ClearanceModel::clear(c, d) must say "clear" a little below
// the true distance from c to the trimmed model and "not clear" a little
// above it. The reference is the test support's cloud of the model (dense
// samples inside each face's wires, refined by local projection, and the
// faces' edges where the nearest point is on them), which shares no code
// with the core.
//
// Ball.brep has what the core's shortcuts must get right: periodic analytic
// faces (spheres, cylinders, tori) whose parameters differ from their NURBS
// form's, holes (a bore through two spheres), and B-spline faces of degree
// 2 x 12 (more control points along one direction than a bicubic's).
#include <gtest/gtest.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepTools.hxx>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/clearance.h"
#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"
#include "isocam/brep_io.h"
#include "support/checks.h"
#include "support/models.h"

namespace isocam {
namespace {

// Ball.brep's faces, their grids and domains, and the clearance model of
// them all (eps 1e-4 mm).
struct BallModel {
  std::vector<TopoDS_Face> faces = faces_of(test::load("Ball.brep"));
  std::vector<PatchGrid> grids;
  std::vector<TrimDomain> trims;
  ClearanceModel model{1e-4, 3.0};
  BallModel() {
    grids.reserve(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i)
      grids.push_back(PatchGrid::from_face(faces[i], static_cast<int>(i)));
    trims.reserve(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i)
      trims.emplace_back(faces[i], grids[i], static_cast<int>(i));
    for (std::size_t i = 0; i < faces.size(); ++i) model.add(grids[i], &trims[i]);
    model.build();
  }
  // A face drawn at random.
  std::size_t random_face(std::mt19937& rng) const {
    const double x = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    return static_cast<std::size_t>(x * static_cast<double>(faces.size())) % faces.size();
  }
};

TEST(ClearanceModel, AgreesWithTheTrimmedModelNearBall) {
  const BallModel ball;
  const std::vector<TopoDS_Face>& faces = ball.faces;
  const std::vector<PatchGrid>& grids = ball.grids;
  const ClearanceModel& model = ball.model;
  const test::ModelCloud cloud(faces, 0.1, true);

  // Points at 0.2 to 2 mm off random points of random faces, on either
  // side; the margin 0.01 mm is far above both the query's eps and the
  // reference's refinement error.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double margin = 0.01;
  int checked = 0, wrong_clear = 0, wrong_blocked = 0;
  for (int k = 0; k < 600; ++k) {
    const std::size_t f = ball.random_face(rng);
    double u0, u1, v0, v1;
    BRepTools::UVBounds(faces[f], u0, u1, v0, v1);
    const double u = u0 + (u1 - u0) * unit(rng), v = v0 + (v1 - v0) * unit(rng);
    BRepAdaptor_Surface surf(faces[f]);
    BRepLProp_SLProps props(surf, u, v, 1, 1e-9);
    if (!props.IsNormalDefined()) continue;
    const double off = (unit(rng) < 0.5 ? -1.0 : 1.0) * (0.2 + 1.8 * unit(rng));
    const gp_Pnt c(props.Value().XYZ() + props.Normal().XYZ() * off);
    const double d = cloud.distance(c);
    if (d < 2 * margin) continue;
    ++checked;
    ClearanceModel::Witness w;
    if (!model.clear(c, d - margin, &w)) {
      ++wrong_blocked;
      // The header allows "blocked" without a witness (a query out of its
      // work budget): that is reported as such, never dereferenced.
      if (!w.grid) {
        ADD_FAILURE() << "blocked at " << d - margin << " with no witness (work budget): point ("
                      << c.X() << ", " << c.Y() << ", " << c.Z() << ") off face " << f << " by "
                      << off << "; reference distance " << d;
        continue;
      }
      const std::size_t wf = static_cast<std::size_t>(w.grid - grids.data());
      const gp_Pnt wp = w.grid->eval(w.u, w.v);
      // in_face's 1e-6: the witness is a grid point of the face, on it to
      // rounding of the grid evaluation; the diagnostic cloud's 0.02 mm
      // spacing is finer than the 0.01 mm margin's scale needs for a hint.
      ADD_FAILURE()
          << "blocked at " << d - margin << ": point (" << c.X() << ", " << c.Y() << ", " << c.Z()
          << ") off face " << f << " by " << off << "; reference distance " << d
          << ", witness on face " << wf << " at (" << w.u << ", " << w.v << ") distance "
          << c.Distance(wp) << " in face " << test::in_face(faces[wf], wp, 1e-6) << " cloud there "
          << test::ModelCloud(std::vector<TopoDS_Face>{faces[wf]}, 0.02, true).distance(c);
    }
    if (model.clear(c, d + margin)) ++wrong_clear;
  }
  EXPECT_GT(checked, 400);

  // Polylines through such points (runs of up to 32 segments share one
  // subdivision) give each segment the answer a query of its own gives: the
  // set of pieces examined for a segment does not depend on the others.
  // Along each face's middle iso-line, at 0.5 to 1.5 mm off it, queried at
  // 1 mm: some segments blocked, some clear.
  std::vector<gp_Pnt> line;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    double u0, u1, v0, v1;
    BRepTools::UVBounds(faces[f], u0, u1, v0, v1);
    BRepAdaptor_Surface surf(faces[f]);
    for (int k = 0; k <= 20; ++k) {
      BRepLProp_SLProps props(surf, u0 + (u1 - u0) * k / 20.0, 0.5 * (v0 + v1), 1, 1e-9);
      if (!props.IsNormalDefined()) continue;
      const double off = 1.0 + 0.5 * std::sin(0.7 * k);
      line.push_back(props.Value().XYZ() + props.Normal().XYZ() * off);
    }
  }
  std::vector<char> together(line.size() - 1);
  model.clear_polyline(line.data(), line.size(), 1.0, together.data());
  int differ = 0, blocked = 0;
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    differ += together[k] != model.clear(line[k], line[k + 1], 1.0);
    blocked += !together[k];
  }
  EXPECT_EQ(differ, 0) << "of " << together.size();
  EXPECT_GT(blocked, 0);  // the 1 mm queries meet the model somewhere
  EXPECT_LT(blocked, static_cast<int>(together.size()));
  // Clear where the model is farther: no false collision (the house's roof
  // and Ball's bore were cut away by those).
  EXPECT_EQ(wrong_blocked, 0) << "of " << checked;
  // Not clear where a point of the trimmed model is nearer: no gouge.
  EXPECT_EQ(wrong_clear, 0) << "of " << checked;
}

// A witness of one reach query settles others without a query
// (witness_blocks_above(), which ConstantScallop's reach border uses on a
// sample's neighbours): wherever it says that the witness blocks a column,
// clear_above() of that column answers "not clear" too. Columns over
// points 1 mm off Ball's faces, queried at 1 mm, then columns up to 0.6 mm
// from each blocked one tested with its witness.
TEST(ClearanceModel, AWitnessBlocksOnlyColumnsTheQuerySaysAreBlocked) {
  const BallModel ball;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double d = 1.0;
  int blocked = 0, settled = 0, wrong = 0;
  for (int k = 0; k < 300; ++k) {
    const PatchGrid& g = ball.grids[ball.random_face(rng)];
    const double u = g.umin() + (g.umax() - g.umin()) * unit(rng);
    const double v = g.vmin() + (g.vmax() - g.vmin()) * unit(rng);
    const gp_Pnt c = g.eval(u, v).Translated(g.normal(u, v) * d);
    ClearanceModel::Witness w;
    if (ball.model.clear_above(c, d, &w) || !w.grid) continue;
    ++blocked;
    for (int j = 0; j < 8; ++j) {
      const gp_Pnt c1(c.X() + 0.6 * (2 * unit(rng) - 1), c.Y() + 0.6 * (2 * unit(rng) - 1),
                      c.Z() + 0.6 * (2 * unit(rng) - 1));
      if (!ball.model.witness_blocks_above(w, c1, d)) continue;
      ++settled;
      wrong += ball.model.clear_above(c1, d);
    }
  }
  EXPECT_GT(blocked, 50);
  EXPECT_GT(settled, 100);
  EXPECT_LT(settled, 8 * blocked);  // not every column: the test can tell
  EXPECT_EQ(wrong, 0) << "of " << settled;
  // No point, no answer: a witness of a query out of its budget.
  EXPECT_FALSE(ball.model.witness_blocks_above(ClearanceModel::Witness{}, gp_Pnt(0, 0, 0), d));
}

}  // namespace
}  // namespace isocam
