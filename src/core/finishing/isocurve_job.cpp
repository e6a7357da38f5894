// The entry point of adaptive isocurve finishing, a short driver
// (adaptive_isocurve() at the end) over named phases, each with its own
// contract: plan_job (the arguments checked, the budgets split, the work
// budget), build_model (each face's patch grid, trimmed domain and the
// clearance model), choose_sides (the sides of open faces a vertical tool
// reaches), cut_pattern (ParallelPlanes, ConstantScallop, or
// Algorithm 1 / the uniform baseline per face and direction: plan_faces,
// choose_directions, cut_chosen, add_border_pieces), link_pieces (coverage.h), certify (the
// measured lengths and times, the two guarantees).
#include <TopoDS.hxx>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "finishing/constant_scallop.h"
#include "finishing/coverage.h"
#include "finishing/face_failure.h"
#include "finishing/face_side.h"
#include "finishing/job_budget.h"
#include "finishing/parallel_planes.h"
#include "finishing/reach_border.h"
#include "finishing/stepover.h"
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

std::string mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

void validate(const IsoParams& p) {
  auto bad = [](const std::string& s) { throw InvalidArgument(s); };
  if (!(p.ball_radius > 0) || !std::isfinite(p.ball_radius))
    bad("ball_radius must be > 0 mm (got " + std::to_string(p.ball_radius) + ")");
  if (!(p.scallop_height > 0) || !(p.scallop_height < p.ball_radius)) {
    std::ostringstream m;
    m << "scallop_height must be > 0 and < the ball radius (ball_radius = " << p.ball_radius
      << " mm; got " << p.scallop_height << ")";
    bad(m.str());
  }
  if (!(p.chord_tolerance >= 0) || !std::isfinite(p.chord_tolerance))
    bad("chord_tolerance must be >= 0 mm (0: derived from the budgets; got " +
        mm(p.chord_tolerance) + ")");
  if (!(p.overcut_tolerance > 0) || !(p.overcut_tolerance < p.ball_radius))
    bad("overcut_tolerance must be > 0 and < the ball radius " + mm(p.ball_radius) + " mm (got " +
        mm(p.overcut_tolerance) + ")");
  if (!(p.posted_resolution >= 0) || !(p.posted_resolution < 0.1))
    bad("posted_resolution must be >= 0 and < 0.1 mm (0.001: 3 decimals; got " +
        mm(p.posted_resolution) + ")");
  if (!(p.air_clearance > 0) || !std::isfinite(p.air_clearance))
    bad("air_clearance must be > 0 mm (got " + mm(p.air_clearance) + ")");
  const std::pair<const char*, double> rates[] = {
      {"feed_rate", p.feed_rate}, {"plunge_rate", p.plunge_rate}, {"rapid_rate", p.rapid_rate}};
  for (const auto& [name, v] : rates)
    if (!(v > 0) || !std::isfinite(v))
      bad(std::string(name) + " must be > 0 mm/min (got " + mm(v) + ")");
  if (p.max_depth < 1) bad("max_depth must be >= 1 (got " + std::to_string(p.max_depth) + ")");
  if (!(p.min_param_gap > 0) || !(p.min_param_gap < 1))
    bad("min_param_gap must be in (0, 1) (got " + std::to_string(p.min_param_gap) + ")");
  if (!std::isfinite(p.safe_z)) bad("safe_z must be a finite height");
  if (p.threads < 0)
    bad("threads must be >= 0 (0: one per core; got " + std::to_string(p.threads) + ")");
  if (!(p.gouge_tolerance > 0) || !(p.gouge_tolerance < p.ball_radius))
    bad("gouge_tolerance must be > 0 and < the ball radius (got " +
        std::to_string(p.gouge_tolerance) + ")");
  check_job_limits(p);
}

// The budgets split (see the header): the chord tolerance derived or
// checked, with the parts of both guarantees.
ErrorBudget split_budget(const IsoParams& p) {
  ErrorBudget b;
  b.gouge = p.gouge_tolerance;
  b.posted = 0.5 * std::sqrt(3.0) * p.posted_resolution;
  const double overcut_room = p.overcut_tolerance - b.gouge - b.posted;
  const double scallop_room = p.scallop_height - b.posted;
  if (!(overcut_room > 0))
    throw InvalidArgument("overcut_tolerance (" + mm(p.overcut_tolerance) +
                          " mm) must exceed gouge_tolerance + the posted rounding sqrt(3)/2 x "
                          "posted_resolution (" +
                          mm(b.gouge + b.posted) + " mm)");
  if (!(scallop_room > 0))
    throw InvalidArgument("scallop_height (" + mm(p.scallop_height) +
                          " mm) must exceed the posted rounding sqrt(3)/2 x posted_resolution (" +
                          mm(b.posted) + " mm)");
  if (p.chord_tolerance == 0) {
    b.chord = std::min(overcut_room, 0.1 * scallop_room);
    return b;
  }
  b.chord = p.chord_tolerance;
  if (b.chord > overcut_room)
    throw InvalidArgument("chord_tolerance (" + mm(b.chord) +
                          " mm) does not fit overcut_tolerance (" + mm(p.overcut_tolerance) +
                          " mm): at most overcut_tolerance - gouge_tolerance"
                          " - posted rounding = " +
                          mm(overcut_room) + " mm (0: derived)");
  if (!(b.chord < 0.9 * scallop_room))
    throw InvalidArgument("chord_tolerance (" + mm(b.chord) + " mm) does not fit scallop_height (" +
                          mm(p.scallop_height) +
                          " mm): under 0.9 x (scallop_height - posted rounding)"
                          " = " +
                          mm(0.9 * scallop_room) + " mm (0: derived)");
  return b;
}

struct FaceResult {
  std::shared_ptr<const PatchGrid> grid;       // working grid the pieces refer to
  std::shared_ptr<const StepoverField> field;  // its tolerances (on *grid)
  std::vector<PlannedCurve> planned;           // the curves' ball-centre polylines
  double planned_length = 0.0;                 // their length, before any is cut
  FaceCoverage coverage;
  IsoDirection dir = IsoDirection::V;
  FacePathStats stats;
  double lower_bound = 0.0;  // L* of the face
  double delta_max = 0.0;    // the largest iso-distance tolerance of the face
  // Why the face could not be planned or cut in this direction
  // (face_failure()); nothing if it was.
  std::optional<std::string> failed;
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
                             const ErrorBudget& budget, const ProgressSlice& progress) {
  FaceResult r;
  r.grid = std::make_shared<const PatchGrid>(dir == IsoDirection::U ? face.grid.transposed()
                                                                    : face.grid);
  r.dir = dir;
  r.field = std::make_shared<const StepoverField>(*r.grid, p, budget.centre_error());
  const StepoverField& field = *r.field;
  r.delta_max = field.max_delta();
  r.coverage = p.pattern == IsoPattern::Uniform
                   ? uniform_coverage(*r.grid, face.index, dir, field, p, progress)
                   : adaptive_coverage(*r.grid, face.index, dir, field, p, progress);
  r.coverage.curves = clip_to_face(r.coverage.curves, *face.trim);
  // The budget again, on what was computed (the estimate before the work
  // is a lower bound): each curve is at least one move.
  const auto over = [&](double n, const char* what) {
    if (n > p.max_moves) check_work_budget(n, p.max_moves, face_label(face.index) + ": " + what);
  };
  over(static_cast<double>(r.coverage.curves.size()), "the sub-isocurves planned");
  r.planned = plan_face(*r.grid, r.coverage.curves, p);
  double points = 0.0;
  for (const PlannedCurve& c : r.planned) {
    r.planned_length += c.line.length();
    points += static_cast<double>(c.line.pts.size());
  }
  over(points, "the points of the planned passes");
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
      throw InvalidArgument("faces: index " + std::to_string(f) +
                            " is out of range (the shape has " + std::to_string(count) +
                            " faces, indices 0.." + std::to_string(count - 1) + ")");
    if (!seen.insert(f).second)
      throw InvalidArgument("faces: index " + std::to_string(f) + " given twice");
  }
}

// ---- The phases of adaptive_isocurve(), in the order it runs them. ----

// The job's numbers: the user's parameters checked, the budgets split
// (the chord tolerance derived or checked) and the flat-ground stepover
// for the cusp the budget leaves (stepover.h). Refuses a job over the work
// budget before any work.
struct JobPlan {
  IsoParams params;  // the user's, with the chord tolerance used
  ErrorBudget budget;
  double delta = 0.0;
};

JobPlan plan_job(const std::vector<TopoDS_Face>& all, const std::vector<int>& faces,
                 const IsoParams& user_params) {
  check_faces(faces, all.size());
  validate(user_params);
  JobPlan job{user_params, split_budget(user_params), 0.0};
  job.params.chord_tolerance = job.budget.chord;
  job.delta = stepover_chord_with_error(job.params.ball_radius, job.params.scallop_height, 0.0,
                                        job.budget.centre_error());
  check_job_budget(all, faces, user_params, job.params, job.delta);
  return job;
}

// The faces the ball is kept clear of: every picked face, and with
// protect_unpicked_faces every other face of the model (the manufacturing
// offset of the union, section 3 of the paper). Each has its grid and
// trimmed domain; the clearance model refers to both, so they live in a
// deque, whose elements stay where they are while it grows.
struct ModelFaces {
  static constexpr std::size_t kNotBuilt = std::numeric_limits<std::size_t>::max();
  std::deque<PickedFace> faces;
  std::vector<std::size_t> picked;  // per picked face (in the order given), its place in faces
  // The other side of the picked open faces finished from both sides
  // (choose_sides()): places in faces, not in the clearance model (the
  // surface is there once).
  std::vector<std::size_t> other_side;
  // Per slot (below): why it is skipped (face_failure(); the phases add the
  // faces they fail on), empty if it is finished. habit 4: the rest goes on.
  // Each slot is skipped alone: the two sides of a face are finished or
  // skipped each on its own (a face is reported skipped when its first
  // side is).
  std::vector<std::string> skipped;

  // What the patterns plan, by slot: the picked faces (slot = place in the
  // faces given), then the other sides.
  std::size_t slots() const { return picked.size() + other_side.size(); }
  bool live(std::size_t s) const { return skipped[s].empty(); }
  const PickedFace& face(std::size_t s) const {
    return faces[s < picked.size() ? picked[s] : other_side[s - picked.size()]];
  }
  // A phase failed on slot s, which the clearance model still has.
  void skip(std::size_t s, const std::string& reason, std::vector<std::string>& warnings) {
    if (!live(s)) return;
    skipped[s] = reason;
    warnings.push_back(skipped_face_warning(reason, true));
  }
};

// Phase 1: the model. A face that cannot be built (a degenerate face, an
// OpenCASCADE failure) is left out of it with a warning: a picked one is
// skipped, an unpicked one left unprotected. The faces enter the model as
// they are oriented (the clearance does not depend on the side); then
// choose_sides() picks the sides of the open ones.
ModelFaces build_model(const std::vector<TopoDS_Face>& all, const std::vector<int>& faces,
                       const IsoParams& params, ClearanceModel& model,
                       std::vector<std::string>& warnings) {
  ModelFaces mf;
  mf.picked.assign(faces.size(), ModelFaces::kNotBuilt);
  mf.skipped.assign(faces.size(), std::string());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const int f = static_cast<int>(i);
    const auto at = std::find(faces.begin(), faces.end(), f);
    const bool is_picked = at != faces.end();
    if (!is_picked && !params.protect_unpicked_faces) continue;
    const std::size_t pos = static_cast<std::size_t>(at - faces.begin());
    const std::optional<std::string> failed = face_failure(f, [&] {
      PickedFace& pf =
          mf.faces.emplace_back(PickedFace{f, PatchGrid::from_face(all[i], f), std::nullopt});
      pf.trim.emplace(all[i], pf.grid, f);
      model.add(pf.grid, &*pf.trim);
    });
    if (failed && is_picked) {
      mf.skipped[pos] = *failed;
      warnings.push_back(skipped_face_warning(*failed, false));
    }
    if (failed) {
      if (!is_picked) warnings.push_back(*failed + "; it is not protected from the ball");
      continue;
    }
    if (is_picked) mf.picked[pos] = mf.faces.size() - 1;
  }
  model.build();
  return mf;
}

// Phase 1b: the sides of the picked open faces (bounding no solid, so the
// material may be on either side), those a vertical tool reaches
// (face_side.h): a face reached only on the side its orientation puts the
// material is taken reversed, one reached on both sides is finished from
// both (its other side planned as one more slot, mf.other_side), each said
// in the warnings.
void choose_sides(const TopoDS_Shape& shape, const std::vector<TopoDS_Face>& all,
                  const IsoParams& params, const ClearanceModel& model, ModelFaces& mf,
                  std::vector<std::string>& warnings) {
  const double clearance =
      model.query_distance(params.ball_radius - params.chord_tolerance - params.gouge_tolerance);
  for (std::size_t i = 0; i < mf.picked.size(); ++i) {
    if (!mf.live(i)) continue;
    PickedFace& pf = mf.faces[mf.picked[i]];
    const TopoDS_Face& face = all[static_cast<std::size_t>(pf.index)];
    if (!is_open_face(shape, face)) continue;
    const FaceSides sides =
        open_face_sides(pf.grid, *pf.trim, model, params.ball_radius, clearance);
    if (sides == FaceSides::Reversed) {
      pf.grid = pf.grid.other_side();
      warnings.push_back(face_label(pf.index) +
                         " is an open face whose orientation puts the ball where a vertical tool "
                         "does not reach: finished from its other side, the side a vertical tool "
                         "reaches (the face taken reversed)");
    } else if (sides == FaceSides::Both) {
      PickedFace& other =
          mf.faces.emplace_back(PickedFace{pf.index, pf.grid.other_side(), std::nullopt});
      other.trim.emplace(face, other.grid, pf.index);
      mf.other_side.push_back(mf.faces.size() - 1);
      mf.skipped.emplace_back();
      warnings.push_back(face_label(pf.index) +
                         " is an open face that a vertical tool reaches on both sides: finished "
                         "from both, each where the tool reaches");
    }
  }
}

// What a pattern hands to linking and to the certificate.
struct PatternCut {
  std::vector<CutPiece> pieces;
  std::vector<std::shared_ptr<const PatchGrid>> working;  // grids the pieces refer to
  double max_dist = 0.0;     // the largest distance between neighbouring passes
  double max_scallop = 0.0;  // the certified scallop (see the header per pattern)
};

// L* of the picked faces finished (the lower bound the certificate compares
// with).
double lower_bound_of(const ModelFaces& mf, const IsoParams& params) {
  double sum = 0.0;
  for (std::size_t i = 0; i < mf.picked.size(); ++i)
    if (mf.live(i))
      sum += lower_bound_length(mf.face(i).grid, &*mf.face(i).trim, params.ball_radius,
                                params.scallop_height);
  return sum;
}

// The slots (picked faces by their place in the faces given, then the
// other sides) not skipped so far.
std::vector<std::size_t> live_faces(const ModelFaces& mf) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < mf.slots(); ++i)
    if (mf.live(i)) out.push_back(i);
  return out;
}

// Phase 2, ParallelPlanes: all faces share one set of planes, so they are
// cut together (parallel_planes.cpp).
PatternCut cut_parallel_planes(ModelFaces& mf, const JobPlan& job, const ClearanceModel& model,
                               IsoResult& result, Progress* progress) {
  const std::vector<std::size_t> live = live_faces(mf);
  std::vector<PlaneFace> plane_faces;
  for (std::size_t i : live)
    plane_faces.push_back({mf.face(i).index, &mf.face(i).grid, &*mf.face(i).trim});
  PlanePieces cut = parallel_plane_pieces(plane_faces, job.delta, job.params, model, progress);
  for (std::size_t k = 0; k < live.size(); ++k)
    if (cut.failed[k]) mf.skip(live[k], *cut.failed[k], result.warnings);
  result.plane_axis = cut.axis;
  result.face_direction.assign(mf.picked.size(), IsoDirection::Auto);
  result.metrics.sub_isocurves = cut.curves;
  result.metrics.unreachable_length = cut.unreachable_length;
  result.metrics.unreachable_from_above_length = cut.unreachable_from_above;
  result.metrics.delta_max = job.delta;
  result.metrics.lower_bound_length = lower_bound_of(mf, job.params);
  PatternCut out;
  out.max_dist = cut.max_pass_distance;
  // Per face, the cusp of its largest pass distance on its most concave
  // ground (stepover.h; see the header).
  for (std::size_t k = 0; k < live.size(); ++k)
    if (!cut.failed[k])
      out.max_scallop = std::max(
          out.max_scallop,
          plane_pass_scallop(mf.face(live[k]).grid, &*mf.face(live[k]).trim, job.params.ball_radius,
                             cut.face_pass_distance[k], job.budget.centre_error()));
  out.pieces = std::move(cut.pieces);
  return out;
}

// Phase 2, ConstantScallop: its own engine per face (constant_scallop.cpp).
// The strips are spaced for the cusp the budget leaves (the centres' error
// e = chord + posted rounding taken out, as Adaptive does); its measured
// certificate includes e.
PatternCut cut_constant_scallop(ModelFaces& mf, const JobPlan& job, const ClearanceModel& model,
                                IsoResult& result, Progress* progress) {
  const std::vector<std::size_t> live = live_faces(mf);
  std::vector<ScallopFace> scallop_faces;
  for (std::size_t i : live)
    scallop_faces.push_back({mf.face(i).index, &mf.face(i).grid, &*mf.face(i).trim});
  ScallopPieces cut = constant_scallop_pieces(scallop_faces, job.params, model, progress);
  result.face_direction.assign(mf.picked.size(), IsoDirection::Auto);
  for (std::size_t k = 0; k < live.size(); ++k) {
    if (live[k] < mf.picked.size()) result.face_direction[live[k]] = cut.face_direction[k];
    if (cut.failed[k]) mf.skip(live[k], *cut.failed[k], result.warnings);
  }
  result.metrics.sub_isocurves = cut.curves;
  result.metrics.unreachable_length = cut.unreachable_length;
  result.metrics.unreachable_from_above_length = cut.unreachable_from_above;
  result.metrics.delta_max = cut.max_width;
  result.metrics.lower_bound_length = lower_bound_of(mf, job.params);
  result.warnings.insert(result.warnings.end(), cut.warnings.begin(), cut.warnings.end());
  PatternCut out;
  out.max_dist = cut.max_spacing;
  out.max_scallop = cut.guaranteed_scallop;
  out.pieces = std::move(cut.pieces);
  return out;
}

// Phase 2a, Adaptive and Uniform: every (slot, direction) planned as a task
// (the other sides of two-sided faces too) on several threads (two directions of one face share its
// trimmed domain, whose hatcher is locked); progress 0 to 0.6. Index: slot * directions +
// direction. A direction whose planning
// fails on the geometry has `failed` set; a face skipped before is not
// planned (`failed` set too).
std::vector<FaceResult> plan_faces(const ModelFaces& mf, const std::vector<IsoDirection>& dirs,
                                   const JobPlan& job, Progress* progress) {
  const std::size_t nd = dirs.size();
  std::vector<FaceResult> tried(mf.slots() * nd);
  TaskProgress planning(ProgressSlice(progress).sub(0.0, 0.6), tried.size());
  for_each_index(tried.size(), job.params.threads, [&](std::size_t k) {
    const std::size_t f = k / nd, di = k % nd;
    if (!mf.live(f)) {
      tried[k].failed = mf.skipped[f];
      planning.task(k).report(1.0);  // nothing to plan: the task is done
      return;
    }
    const PickedFace& face = mf.face(f);
    double lower_bound = 0.0;  // the face's L*, first: kept if this direction fails
    const std::optional<std::string> failed = face_failure(face.index, [&] {
      if (di == 0 && f < mf.picked.size())  // L* counts a face once
        lower_bound = lower_bound_length(face.grid, &*face.trim, job.params.ball_radius,
                                         job.params.scallop_height);
      tried[k] = face_in_direction(face, dirs[di], job.params, job.budget, planning.task(k));
    });
    tried[k].dir = dirs[di];
    tried[k].failed = failed;
    tried[k].lower_bound = lower_bound;
  });
  return tried;
}

const char* direction_name(IsoDirection d) { return d == IsoDirection::U ? "U" : "V"; }

// Phase 2b: per face, the first direction tried unless another plans
// strictly less (the face's L* kept whichever wins), among those that did
// not fail; a failed direction beside one that did not is a warning, a face
// on which all failed keeps the first failure.
std::vector<FaceResult> choose_directions(std::vector<FaceResult> tried, std::size_t nd,
                                          const ModelFaces& mf,
                                          std::vector<std::string>& warnings) {
  std::vector<FaceResult> chosen(tried.size() / nd);
  for (std::size_t f = 0; f < chosen.size(); ++f) {
    std::size_t best = f * nd;
    for (std::size_t di = 1; di < nd; ++di) {
      const FaceResult& t = tried[f * nd + di];
      if (!t.failed && (tried[best].failed || t.planned_length < tried[best].planned_length))
        best = f * nd + di;
    }
    if (mf.live(f) && !tried[best].failed)
      for (std::size_t di = 0; di < nd; ++di)
        if (tried[f * nd + di].failed)
          warnings.push_back(*tried[f * nd + di].failed + "; direction " +
                             direction_name(tried[f * nd + di].dir) + " left out, " +
                             direction_name(tried[best].dir) + " used");
    const double lower_bound = tried[f * nd].lower_bound;
    std::optional<std::string> first_failure = tried[f * nd].failed;
    chosen[f] = std::move(tried[best]);
    chosen[f].lower_bound = lower_bound;
    if (chosen[f].failed) chosen[f].failed = first_failure;
  }
  return chosen;
}

// Phase 2c: the chosen curves cut against the model, in ranges of
// kCurvesPerTask curves as tasks, merged in face and curve order, so that
// the result does not depend on the number of threads; each face's stats
// gathered. A face on which a range fails gets `failed` (the first range's
// reason) and none of its pieces. Progress 0.6 to 0.95.
constexpr std::size_t kCurvesPerTask = 8;  // small enough to balance two faces on many threads

std::vector<CutPiece> cut_chosen(std::vector<FaceResult>& chosen, const ModelFaces& mf,
                                 const JobPlan& job, const ClearanceModel& model,
                                 Progress* progress) {
  struct Range {
    std::size_t face, first, last;
  };
  std::vector<Range> ranges;
  for (std::size_t f = 0; f < chosen.size(); ++f)
    for (std::size_t i = 0; !chosen[f].failed && i < chosen[f].planned.size(); i += kCurvesPerTask)
      ranges.push_back({f, i, std::min(i + kCurvesPerTask, chosen[f].planned.size())});
  std::vector<std::vector<CutPiece>> cut(ranges.size());
  std::vector<FacePathStats> cut_stats(ranges.size());
  std::vector<std::optional<std::string>> failed(ranges.size());
  std::size_t cut_done = 0;
  std::mutex cut_lock;  // the count and the progress it reports
  for_each_index(ranges.size(), job.params.threads, [&](std::size_t k) {
    check_cancel(progress);
    const Range& rg = ranges[k];
    const FaceResult& fr = chosen[rg.face];
    failed[k] = face_failure(mf.face(rg.face).index, [&] {
      cut[k] = cut_planned(*fr.grid, fr.planned.data() + rg.first, fr.planned.data() + rg.last,
                           job.params, model, &cut_stats[k]);
    });
    const std::lock_guard<std::mutex> guard(cut_lock);
    report_progress(progress, 0.6 + 0.35 * double(++cut_done) / double(ranges.size()));
  });
  for (std::size_t k = 0; k < ranges.size(); ++k)
    if (failed[k] && !chosen[ranges[k].face].failed) chosen[ranges[k].face].failed = failed[k];
  std::vector<CutPiece> pieces;
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    if (chosen[ranges[k].face].failed) continue;
    FacePathStats& stats = chosen[ranges[k].face].stats;
    stats.curves += cut_stats[k].curves;
    stats.unreachable_length += cut_stats[k].unreachable_length;
    stats.unreachable_from_above += cut_stats[k].unreachable_from_above;
    std::move(cut[k].begin(), cut[k].end(), std::back_inserter(pieces));
  }
  return pieces;
}

// Phase 2d: the border passes (reach_border.h) of every face, as tasks;
// appended after the pieces they refine, in face order. Their curves count
// as sub-isocurves; their certificate enters the pattern's. A face on which
// they fail gets `failed` and loses its pieces (its coverage would not hold).
void add_border_pieces(std::vector<FaceResult>& chosen, const ModelFaces& mf, const JobPlan& job,
                       const ClearanceModel& model, PatternCut& out) {
  std::vector<BorderCut> border(chosen.size());
  std::vector<std::optional<std::string>> failed(chosen.size());
  for_each_index(chosen.size(), job.params.threads, [&](std::size_t f) {
    const FaceResult& fr = chosen[f];
    if (fr.failed) return;
    const PickedFace& face = mf.face(f);
    BorderFace bf{face.index,    fr.dir,      fr.dir == IsoDirection::V,
                  fr.grid.get(), &*face.trim, fr.field.get(),
                  &fr.coverage,  {}};
    for (const CutPiece& piece : out.pieces)
      if (piece.grid == fr.grid.get()) bf.cut.push_back(&piece);
    failed[f] = face_failure(face.index, [&] { border[f] = border_pieces(bf, job.params, model); });
  });
  for (std::size_t f = 0; f < chosen.size(); ++f) {
    if (!failed[f]) continue;
    chosen[f].failed = failed[f];
    const PatchGrid* grid = chosen[f].grid.get();
    out.pieces.erase(std::remove_if(out.pieces.begin(), out.pieces.end(),
                                    [&](const CutPiece& p) { return p.grid == grid; }),
                     out.pieces.end());
  }
  for (std::size_t f = 0; f < chosen.size(); ++f) {
    if (chosen[f].failed) continue;
    chosen[f].stats.curves += border[f].curves;
    out.max_scallop = std::max(out.max_scallop, border[f].max_scallop);
    std::move(border[f].pieces.begin(), border[f].pieces.end(), std::back_inserter(out.pieces));
  }
}

// Phase 2, Adaptive and Uniform (Algorithm 1 or the uniform baseline per
// face): plan, choose the direction, cut, the border passes; the faces'
// curves, directions and stats into the result (one direction per picked
// face: an other side's is not said).
PatternCut cut_isocurves(ModelFaces& mf, const JobPlan& job, const ClearanceModel& model,
                         IsoResult& result, Progress* progress) {
  const std::vector<IsoDirection> dirs = directions_to_try(job.params);
  std::vector<FaceResult> chosen =
      choose_directions(plan_faces(mf, dirs, job, progress), dirs.size(), mf, result.warnings);
  PatternCut out;
  out.pieces = cut_chosen(chosen, mf, job, model, progress);
  add_border_pieces(chosen, mf, job, model, out);
  result.face_direction.assign(mf.picked.size(), IsoDirection::Auto);
  for (std::size_t f = 0; f < chosen.size(); ++f) {
    FaceResult& best = chosen[f];
    if (best.failed) mf.skip(f, *best.failed, result.warnings);
    if (!mf.live(f)) continue;
    result.curves.insert(result.curves.end(), best.coverage.curves.begin(),
                         best.coverage.curves.end());
    if (f < mf.picked.size()) result.face_direction[f] = best.dir;
    result.metrics.sub_isocurves += best.stats.curves;
    result.metrics.unreachable_length += best.stats.unreachable_length;
    result.metrics.unreachable_from_above_length += best.stats.unreachable_from_above;
    out.max_dist = std::max(out.max_dist, best.coverage.max_iso_distance);
    out.max_scallop = std::max(out.max_scallop, best.coverage.guaranteed_scallop);
    result.metrics.lower_bound_length += best.lower_bound;
    result.metrics.delta_max = std::max(result.metrics.delta_max, best.delta_max);
    out.working.push_back(best.grid);
  }
  return out;
}

PatternCut cut_pattern(ModelFaces& mf, const JobPlan& job, const ClearanceModel& model,
                       IsoResult& result, Progress* progress) {
  switch (job.params.pattern) {
    case IsoPattern::ParallelPlanes:
      return cut_parallel_planes(mf, job, model, result, progress);
    case IsoPattern::ConstantScallop:
      return cut_constant_scallop(mf, job, model, result, progress);
    default:
      return cut_isocurves(mf, job, model, result, progress);
  }
}

// The safe height must clear every cutting point of the linked path.
void check_safe_z(const Toolpath& path, double safe_z) {
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < path.size(); ++i)
    if (path.kind[i] != static_cast<std::uint8_t>(MoveKind::Rapid)) top = std::max(top, path.z[i]);
  if (safe_z < top)
    throw InvalidArgument("safe_z (" + std::to_string(safe_z) +
                          " mm) is below the highest cutting point of the path (" +
                          std::to_string(top) + " mm)");
}

// Phase 4: the certificate: lengths and times measured on the linked path,
// the two guarantees from the pattern's cut and the budget.
void certify(IsoResult& result, const PatternCut& cut, const JobPlan& job) {
  IsoMetrics& m = result.metrics;
  if (m.unreachable_from_above_length > 0)
    result.warnings.push_back(
        mm(m.unreachable_from_above_length) +
        " mm of tool-centre path left out: a vertical tool cannot reach those places from above "
        "(undersides, places under an overhang); material is left there");
  report_lengths(measure(result.path), m);
  m.max_iso_distance = cut.max_dist;
  m.guaranteed_scallop = cut.max_scallop;
  m.guaranteed_overcut = job.budget.overcut();
  m.chord_tolerance = job.budget.chord;
  const PathTimes times = estimate_time(result.path, job.params.feed_rate, job.params.plunge_rate,
                                        job.params.rapid_rate);
  m.machine_time = times.total;
  m.cutting_time = times.feed;
}

// The picked faces skipped so far into the result; if that is every one,
// the job is an error naming each with its reason.
void record_skipped(const ModelFaces& mf, const std::vector<int>& faces, IsoResult& result) {
  result.skipped_faces.clear();
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (!mf.live(i)) result.skipped_faces.push_back(faces[i]);
  if (result.skipped_faces.size() == faces.size())
    throw_every_face_failed(
        std::vector<std::string>(mf.skipped.begin(), mf.skipped.begin() + faces.size()));
}

}  // namespace

// The driver: the job's numbers, the model, the pattern's pieces, linking
// (coverage.h: link_pieces), the certificate. A picked face that a phase
// fails on is skipped with a warning (face_failure.h).
IsoResult adaptive_isocurve(const TopoDS_Shape& shape, const std::vector<int>& faces,
                            const IsoParams& user_params, Progress* progress) {
  // The shape first: a shape without faces is that, whatever the numbers.
  if (shape.IsNull()) throw InvalidArgument("brep: the shape is empty (no faces)");
  const std::vector<TopoDS_Face> all = faces_of(shape);
  if (all.empty()) throw InvalidArgument("brep: the shape has no faces");
  const JobPlan job = plan_job(all, faces, user_params);
  IsoResult result;
  result.metrics.delta = job.delta;
  // Its accuracy is the gouge tolerance: the queries keep the ball at
  // r - chord_tolerance - gouge_tolerance (query_distance()).
  ClearanceModel model(job.params.gouge_tolerance, 2.0 * job.params.ball_radius);
  ModelFaces mf = build_model(all, faces, job.params, model, result.warnings);
  record_skipped(mf, faces, result);
  choose_sides(shape, all, job.params, model, mf, result.warnings);
  PatternCut cut = cut_pattern(mf, job, model, result, progress);
  record_skipped(mf, faces, result);
  result.path = link_pieces(std::move(cut.pieces), job.params, model);
  report_progress(progress, 1.0);
  check_safe_z(result.path, job.params.safe_z);
  certify(result, cut, job);
  return result;
}

}  // namespace isocam
