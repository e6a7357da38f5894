// The entry point of adaptive isocurve finishing: checks the arguments,
// builds each picked face's patch grid, trimmed domain and the clearance
// model, runs Algorithm 1 (or the uniform baseline) per face and direction,
// and assembles the path and its certificate.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include <Standard_Failure.hxx>

#include "finishing/constant_scallop.h"
#include "finishing/coverage.h"
#include "finishing/stepover.h"
#include "finishing/parallel_planes.h"
#include "finishing/task_pool.h"
#include "geometry/trim_domain.h"
#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"

namespace isocam {
namespace {

// A picked face: its grid, and its trimmed domain (which refers to the grid,
// so the two live together and are built in place).
struct PickedFace {
  int index;
  PatchGrid grid;
  std::optional<TrimDomain> trim;
};

void validate(const IsoParams& p) {
  auto bad = [](const std::string& s) { throw InvalidArgument(s); };
  if (!(p.ball_radius > 0) || !std::isfinite(p.ball_radius))
    bad("ball_radius must be > 0 mm (got " + std::to_string(p.ball_radius) + ")");
  if (!(p.scallop_height > 0) || !(p.scallop_height < p.ball_radius))
    bad("scallop_height must be > 0 and < the ball radius " + std::to_string(p.ball_radius) +
        " mm (got " + std::to_string(p.scallop_height) + ")");
  if (!(p.chord_tolerance > 0) || !std::isfinite(p.chord_tolerance))
    bad("chord_tolerance must be > 0 mm (got " + std::to_string(p.chord_tolerance) + ")");
  if (p.max_depth < 1) bad("max_depth must be >= 1 (got " + std::to_string(p.max_depth) + ")");
  if (!(p.min_param_gap > 0) || !(p.min_param_gap < 1))
    bad("min_param_gap must be in (0, 1) (got " + std::to_string(p.min_param_gap) + ")");
  if (!std::isfinite(p.safe_z)) bad("safe_z must be a finite height");
  if (p.threads < 0) bad("threads must be >= 0 (0: one per core; got " + std::to_string(p.threads) + ")");
  if (!(p.gouge_tolerance > 0) || !(p.gouge_tolerance < p.ball_radius))
    bad("gouge_tolerance must be > 0 and < the ball radius (got " + std::to_string(p.gouge_tolerance) + ")");
}

struct FaceResult {
  std::shared_ptr<const PatchGrid> grid;  // working grid the pieces refer to
  std::vector<PlannedCurve> planned;      // the curves' ball-centre polylines
  double planned_length = 0.0;            // their length, before any is cut
  FaceCoverage coverage;
  IsoDirection dir = IsoDirection::V;
  FacePathStats stats;
  double lower_bound = 0.0;  // L* of the face
  double delta_max = 0.0;    // the largest iso-distance tolerance of the face
};

// The coverage's curves clipped to the face's trimmed domain (Elber &
// Cohen, section 3: isocurves of the untrimmed surface, then trimmed).
std::vector<SubIsocurve> clip_to_face(const std::vector<SubIsocurve>& curves,
                                      const TrimDomain& trim) {
  std::vector<SubIsocurve> out;
  for (const SubIsocurve& c : curves) {
    for (const Interval& iv : trim.inside(c.dir == IsoDirection::V, c.level, c.t0, c.t1)) {
      SubIsocurve piece = c;
      piece.t0 = iv.lo;
      piece.t1 = iv.hi;
      out.push_back(piece);
    }
  }
  return out;
}

FaceResult face_in_direction(const PickedFace& face, IsoDirection dir, const IsoParams& p,
                             const ProgressSlice& progress) {
  FaceResult r;
  r.grid = std::make_shared<const PatchGrid>(dir == IsoDirection::U ? face.grid.transposed()
                                                                     : face.grid);
  r.dir = dir;
  const StepoverField field(*r.grid, p);
  r.delta_max = field.max_delta();
  r.coverage = p.pattern == IsoPattern::Uniform
                   ? uniform_coverage(*r.grid, face.index, dir, field, p, progress)
                   : adaptive_coverage(*r.grid, face.index, dir, field, p, progress);
  r.coverage.curves = clip_to_face(r.coverage.curves, *face.trim);
  r.planned = plan_face(*r.grid, r.coverage.curves, p);
  for (const PlannedCurve& c : r.planned) r.planned_length += c.line.length();
  return r;
}

// The directions tried on each face: the requested one, or for Auto both
// (the shorter planned length wins, see adaptive_isocurve()).
std::vector<IsoDirection> directions_to_try(const IsoParams& params) {
  if (params.direction == IsoDirection::Auto) return {IsoDirection::V, IsoDirection::U};
  return {params.direction};
}

void check_faces(const std::vector<int>& faces, std::size_t count) {
  if (faces.empty()) throw InvalidArgument("faces: no face given");
  std::set<int> seen;
  for (int f : faces) {
    if (f < 0 || f >= static_cast<int>(count))
      throw InvalidArgument("faces: index " + std::to_string(f) + " is out of range (the shape has " +
                            std::to_string(count) + " faces, indices 0.." +
                            std::to_string(count - 1) + ")");
    if (!seen.insert(f).second) throw InvalidArgument("faces: index " + std::to_string(f) + " given twice");
  }
}

}  // namespace

IsoResult adaptive_isocurve(const TopoDS_Shape& shape, const std::vector<int>& faces,
                            const IsoParams& params, Progress* progress) {
  validate(params);
  if (shape.IsNull()) throw InvalidArgument("brep: the shape is empty");
  const std::vector<TopoDS_Face> all = faces_of(shape);
  if (all.empty()) throw InvalidArgument("brep: the shape has no faces");
  check_faces(faces, all.size());
  const double delta = stepover_for_scallop(params.ball_radius, params.scallop_height);
  IsoResult result;
  result.metrics.delta = delta;
  // Every picked face gets its grid and trimmed domain and is kept clear of
  // the ball; with protect_unpicked_faces so is every other face of the
  // model (the manufacturing offset of the union, section 3 of the paper).
  std::vector<PickedFace> model_faces;
  model_faces.reserve(all.size());
  std::vector<std::size_t> picked(faces.size(), all.size());
  // Its accuracy is the gouge tolerance: the queries keep the ball at
  // r - chord_tolerance - gouge_tolerance (query_distance()).
  ClearanceModel model(params.gouge_tolerance, 2.0 * params.ball_radius);
  for (std::size_t i = 0; i < all.size(); ++i) {
    const int f = static_cast<int>(i);
    const auto at = std::find(faces.begin(), faces.end(), f);
    if (at == faces.end() && !params.protect_unpicked_faces) continue;
    try {
      model_faces.push_back({f, PatchGrid::from_face(all[i], f), std::nullopt});
      model_faces.back().trim.emplace(all[i], model_faces.back().grid, f);  // reserve(): stable
      model.add(model_faces.back().grid, &*model_faces.back().trim);
    } catch (const Standard_Failure& e) {
      if (at != faces.end())
        throw GeometryError(face_label(f) + ": OpenCASCADE failed: " + e.GetMessageString());
      result.warnings.push_back(face_label(f) + " is not protected from the ball: " +
                                e.GetMessageString());
      continue;
    } catch (const GeometryError& e) {
      if (at != faces.end()) throw;
      result.warnings.push_back(face_label(f) + " is not protected from the ball: " + e.what());
      continue;
    }
    if (at != faces.end()) picked[static_cast<std::size_t>(at - faces.begin())] = model_faces.size() - 1;
  }
  model.build();
  double max_dist = 0.0, max_scallop = 0.0;
  const double nf = double(faces.size());
  std::vector<std::shared_ptr<const PatchGrid>> working;  // keeps the pieces' grids alive
  std::vector<CutPiece> pieces;
  // ParallelPlanes: all faces share one set of planes, so they are cut
  // together (parallel_planes.cpp) and the per-face work below has none.
  const bool planes = params.pattern == IsoPattern::ParallelPlanes;
  if (planes) {
    std::vector<PlaneFace> plane_faces;
    for (std::size_t k : picked)
      plane_faces.push_back({model_faces[k].index, &model_faces[k].grid, &*model_faces[k].trim});
    PlanePieces cut = parallel_plane_pieces(plane_faces, delta, params, model, progress);
    result.plane_axis = cut.axis;
    result.face_direction.assign(picked.size(), IsoDirection::Auto);
    result.metrics.sub_isocurves = cut.curves;
    result.metrics.unreachable_length = cut.unreachable_length;
    max_dist = cut.max_pass_distance;
    // Not a certificate: the flat-ground scallop of the largest pass
    // distance (see the header).
    max_scallop = scallop_for_stepover(params.ball_radius, max_dist);
    result.metrics.delta_max = delta;
    for (std::size_t k : picked)
      result.metrics.lower_bound_length +=
          lower_bound_length(model_faces[k].grid, &*model_faces[k].trim, params.ball_radius,
                             params.scallop_height);
    pieces = std::move(cut.pieces);
  }
  // ConstantScallop: its own engine per face (constant_scallop.cpp); its
  // pieces join the others' linking below.
  const bool scallop = params.pattern == IsoPattern::ConstantScallop;
  if (scallop) {
    std::vector<ScallopFace> scallop_faces;
    for (std::size_t k : picked)
      scallop_faces.push_back({model_faces[k].index, &model_faces[k].grid, &*model_faces[k].trim});
    ScallopPieces cut = constant_scallop_pieces(scallop_faces, params, model, progress);
    result.face_direction = cut.face_direction;
    result.metrics.sub_isocurves = cut.curves;
    result.metrics.unreachable_length = cut.unreachable_length;
    result.metrics.delta_max = cut.max_width;
    max_dist = cut.max_spacing;
    max_scallop = cut.guaranteed_scallop;
    result.warnings.insert(result.warnings.end(), cut.warnings.begin(), cut.warnings.end());
    for (std::size_t k : picked)
      result.metrics.lower_bound_length +=
          lower_bound_length(model_faces[k].grid, &*model_faces[k].trim, params.ball_radius,
                             params.scallop_height);
    pieces = std::move(cut.pieces);
  }
  // Faces, and the directions of one face under Auto, are independent until
  // linking: plan them as tasks (face, direction) on several threads (two
  // directions of one face share its trimmed domain, whose hatcher is
  // locked) and pick each face's direction by the length planned. Then the
  // chosen curves are cut against the model, in ranges of a few curves as
  // tasks again, and merged in face and curve order, so that the result
  // does not depend on the number of threads.
  const std::vector<IsoDirection> dirs = directions_to_try(params);
  const std::size_t nd = dirs.size();
  const std::size_t tasks = planes || scallop ? 0 : picked.size() * nd;
  const ProgressSlice planning = ProgressSlice(progress).sub(0.0, 0.6);
  std::vector<FaceResult> tried(tasks);
  for_each_index(tasks, params.threads, [&](std::size_t k) {
    const std::size_t f = k / nd, di = k % nd;
    const PickedFace& face = model_faces[picked[f]];
    try {
      const double lo = (double(f) + double(di) / double(nd)) / nf;
      const double hi = (double(f) + double(di + 1) / double(nd)) / nf;
      tried[k] = face_in_direction(face, dirs[di], params, planning.sub(lo, hi));
      if (di == 0)
        tried[k].lower_bound = lower_bound_length(face.grid, &*face.trim, params.ball_radius,
                                                  params.scallop_height);
    } catch (const Standard_Failure& e) {
      throw GeometryError(face_label(face.index) + ": OpenCASCADE failed: " + e.GetMessageString());
    }
  });
  // Per face, the first direction tried unless another plans strictly less.
  std::vector<FaceResult> done(planes || scallop ? 0 : picked.size());
  for (std::size_t f = 0; f < done.size(); ++f) {
    std::size_t best = f * nd;
    for (std::size_t di = 1; di < nd; ++di)
      if (tried[f * nd + di].planned_length < tried[best].planned_length) best = f * nd + di;
    const double lower_bound = tried[f * nd].lower_bound;  // of the face, not the direction
    done[f] = std::move(tried[best]);
    done[f].lower_bound = lower_bound;
  }
  struct Range {
    std::size_t face, first, last;
  };
  std::vector<Range> ranges;
  for (std::size_t f = 0; f < done.size(); ++f)
    for (std::size_t i = 0; i < done[f].planned.size(); i += 8)
      ranges.push_back({f, i, std::min(i + 8, done[f].planned.size())});
  std::vector<std::vector<CutPiece>> cut(ranges.size());
  std::vector<FacePathStats> cut_stats(ranges.size());
  std::size_t cut_done = 0;
  std::mutex cut_lock;  // the count and the progress it reports
  for_each_index(ranges.size(), params.threads, [&](std::size_t k) {
    check_cancel(progress);
    const Range& rg = ranges[k];
    const FaceResult& fr = done[rg.face];
    try {
      cut[k] = cut_planned(*fr.grid, fr.planned.data() + rg.first, fr.planned.data() + rg.last,
                           params, model, &cut_stats[k]);
    } catch (const Standard_Failure& e) {
      throw GeometryError(face_label(model_faces[picked[rg.face]].index) +
                          ": OpenCASCADE failed: " + e.GetMessageString());
    }
    const std::lock_guard<std::mutex> guard(cut_lock);
    report_progress(progress, 0.6 + 0.35 * double(++cut_done) / double(ranges.size()));
  });
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    done[ranges[k].face].stats.curves += cut_stats[k].curves;
    done[ranges[k].face].stats.unreachable_length += cut_stats[k].unreachable_length;
    std::move(cut[k].begin(), cut[k].end(), std::back_inserter(pieces));
  }
  for (FaceResult& best : done) {
    result.curves.insert(result.curves.end(), best.coverage.curves.begin(), best.coverage.curves.end());
    result.face_direction.push_back(best.dir);
    result.metrics.sub_isocurves += best.stats.curves;
    result.metrics.unreachable_length += best.stats.unreachable_length;
    max_dist = std::max(max_dist, best.coverage.max_iso_distance);
    max_scallop = std::max(max_scallop, best.coverage.guaranteed_scallop);
    result.metrics.lower_bound_length += best.lower_bound;
    result.metrics.delta_max = std::max(result.metrics.delta_max, best.delta_max);
    working.push_back(best.grid);
  }
  result.path = link_pieces(std::move(pieces), params, model);
  report_progress(progress, 1.0);
  double top = -1e300;
  for (std::size_t i = 0; i < result.path.size(); ++i)
    if (result.path.kind[i] != static_cast<std::uint8_t>(MoveKind::Rapid)) top = std::max(top, result.path.z[i]);
  if (params.safe_z < top)
    throw InvalidArgument("safe_z (" + std::to_string(params.safe_z) +
                          " mm) is below the highest cutting point of the path (" +
                          std::to_string(top) + " mm)");
  const PathLengths len = measure(result.path);
  result.metrics.cutting_length = len.feed;
  result.metrics.rapid_length = len.rapid;
  result.metrics.plunge_length = len.plunge;
  result.metrics.retracts = len.retracts;
  result.metrics.max_iso_distance = max_dist;
  result.metrics.guaranteed_scallop = max_scallop;
  return result;
}

}  // namespace isocam
