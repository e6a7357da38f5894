// The constant-scallop pattern's driver: the front of paths per face and
// direction (scallop_front.cpp), the measured certificate, the clip to the
// trimmed face, the ball centres and the clearance cuts (see
// constant_scallop.h for the contract).
#include "finishing/constant_scallop.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>

#include "finishing/face_failure.h"
#include "finishing/stepover.h"
#include "finishing/task_pool.h"
#include "isocam/errors.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

using Path = std::vector<FrontPiece>;

// Samples of the face about `step` apart (by the patch's corner-to-corner
// sides; at most 512 a side per patch), inside its wires: f(u, v).
template <class F>
void for_each_sample(const PatchGrid& g, const TrimDomain& trim, bool transposed, double step,
                     F f) {
  const auto& ub = g.ubreaks();
  const auto& vb = g.vbreaks();
  for (int j = 0; j < g.patches_v(); ++j)
    for (int i = 0; i < g.patches_u(); ++i) {
      const std::size_t iu = static_cast<std::size_t>(i), jv = static_cast<std::size_t>(j);
      const gp_Pnt c00 = g.eval(ub[iu], vb[jv]);
      const double su =
          std::max(c00.Distance(g.eval(ub[iu + 1], vb[jv])),
                   g.eval(ub[iu], vb[jv + 1]).Distance(g.eval(ub[iu + 1], vb[jv + 1])));
      const double sv =
          std::max(c00.Distance(g.eval(ub[iu], vb[jv + 1])),
                   g.eval(ub[iu + 1], vb[jv]).Distance(g.eval(ub[iu + 1], vb[jv + 1])));
      const int nu = std::clamp(static_cast<int>(std::ceil(su / step)), 1, 512);
      const int nv = std::clamp(static_cast<int>(std::ceil(sv / step)), 1, 512);
      for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nv; ++b) {
          const double s = (a + 0.5) / nu, t = (b + 0.5) / nv;
          const double u = ub[iu] + s * (ub[iu + 1] - ub[iu]),
                       v = vb[jv] + t * (vb[jv + 1] - vb[jv]);
          if (transposed ? trim.contains(v, u) : trim.contains(u, v)) f(u, v);
        }
    }
}

// The normal curvature at the sample (u, v) towards the nearest contact
// point: across the feed of the path that cuts there.
double towards_path(const PatchGrid& g, const PathIndex& index, double u, double v) {
  const gp_Pnt x = g.eval(u, v);
  gp_Pnt at;
  index.distance(x, &at);
  if (x.Distance(at) < 1e-12) return 0.0;
  return normal_curvature(g, {u, v}, gp_Vec(x, at));
}

// Definition 1 measured on the face: each sample at distance d from the
// nearest contact polyline; the ball there leaves at most the cusp of
// contact points 2 d apart on the normal curvature at the sample towards
// the path (towards_path()). Samples on concave ground tighter than the
// ball, where it cannot touch, count in neither number; samples within
// `ok` / 2 of a path (no worse than the adjacent pairs) skip the curvature.
void sample_coverage(const PatchGrid& g, const TrimDomain& trim, bool transposed,
                     const PathIndex& index, double r, double step, double ok, double* max_gap,
                     double* scallop) {
  for_each_sample(g, trim, transposed, step, [&](double u, double v) {
    // Stops at a segment nearer than the largest gap so far and ok / 2:
    // such a sample changes neither number.
    const double d = index.distance(g.eval(u, v), nullptr, std::min(*max_gap, 0.5 * ok));
    if (2 * d <= ok) {
      *max_gap = std::max(*max_gap, d);
      return;
    }
    // Concave ground tighter than the ball: it cannot touch there (its
    // offset folds; the clearance cut reports that path as unreachable).
    const double kappa = towards_path(g, index, u, v);
    if (kappa * r <= -1.0) return;
    *max_gap = std::max(*max_gap, d);
    *scallop = std::max(*scallop, scallop_for_chord(r, 2 * d, kappa));
  });
}

// The paths of one face in a working grid, with the measured spacing.
struct FacePaths {
  std::vector<Path> paths;
  double length = 0.0;  // of the contact polylines
  double max_spacing = 0.0, scallop = 0.0, max_width = 0.0;
  int min_hits = 0, seeds = 0;
  bool capped = false;
  std::shared_ptr<PathIndex> index;  // all the paths' contact polylines
};

struct Tracer {
  const PatchGrid& g;
  const TrimDomain& trim;
  bool transposed;
  const StripWidth& width;
  const IsoParams& p;
  const ProgressSlice& progress;
  double flat;
  FrontSettings s;
  FacePaths out;
  std::size_t max_paths = 0, samples = 0;

  // Paths from `front` until no point moves (or the cap).
  void propagate(std::vector<FrontPiece> front) {
    while (!front.empty()) {
      progress.check();
      if (out.paths.size() >= max_paths || samples > 20000000) {
        out.capped = true;
        out.paths.push_back(front);
        return;
      }
      for (const FrontPiece& pc : front) out.index->add(pc);
      FrontStep step = advance_front(g, &front, width, s, *out.index);
      out.min_hits += step.min_hits;
      for (const FrontPiece& pc : front) {
        samples += pc.size();
        for (std::size_t k = 1; k < pc.size(); ++k) out.length += pc[k - 1].p.Distance(pc[k].p);
      }
      // The certificate: each point with a successor against the next path.
      PathIndex next(flat);
      for (const FrontPiece& pc : step.next) next.add(pc);
      for (const FrontPiece& pc : front)
        for (const FrontPoint& q : pc) {
          // Concave ground tighter than the ball: it cannot touch there.
          if (!q.has_next || q.kappa * p.ball_radius <= -1.0) continue;
          out.max_width = std::max(out.max_width, q.spacing);
          const double c = next.distance(q.p);
          out.max_spacing = std::max(out.max_spacing, c);
          out.scallop = std::max(out.scallop, scallop_for_chord(p.ball_radius, c, q.kappa));
        }
      out.paths.push_back(std::move(front));
      front = std::move(step.next);
    }
  }

  // A short iso-v path through (u, v), about 4 flat stepovers long, both
  // ways round (its front then spreads to both sides).
  std::vector<FrontPiece> seed(double u, double v) const {
    const double speed = g.d1(u, v).su.Magnitude();
    const double du = speed > 0 ? 0.5 * flat / speed : 0.0;
    FrontPiece pc;
    for (int k = -4; k <= 4; ++k) {
      FrontPoint x;
      x.uv = {std::clamp(u + k * du, g.umin(), g.umax()), v};
      x.p = g.eval(x.uv.u, x.uv.v);
      if (pc.empty() || x.p.Distance(pc.back().p) > 1e-9) pc.push_back(x);
    }
    if (pc.size() < 2) return {};
    resample(g, &pc, s.sample_max);
    FrontPiece back(pc.rbegin(), pc.rend());
    for (std::size_t k = 0; k < pc.size(); ++k) pc[k].came = frame_at(g, pc, k).across;
    for (std::size_t k = 0; k < back.size(); ++k) back[k].came = frame_at(g, back, k).across;
    return {pc, back};
  }

  // "Start new paths there": where the front left ground uncovered (it split
  // at a fold, turned back, or a wedge stayed between its parts), seeds on
  // the samples of the face (inside its wires) whose distance to the paths
  // leaves a cusp over h, a few rounds.
  void fill_gaps() {
    for (int round = 0; round < 4; ++round) {
      std::vector<FrontPiece> front;
      for_each_sample(g, trim, transposed, flat, [&](double u, double v) {
        const double d = out.index->distance(g.eval(u, v));
        if (2 * d <= s.min_spacing) return;
        const double kappa = towards_path(g, *out.index, u, v);
        if (kappa * p.ball_radius <= -1.0) return;  // the ball cannot touch there
        if (2 * d <= stepover_chord(p.ball_radius, p.scallop_height, kappa)) return;
        for (FrontPiece& pc : seed(u, v)) {
          out.index->add(pc);
          front.push_back(std::move(pc));
        }
        ++out.seeds;
      });
      if (front.empty()) return;
      progress.check();
      propagate(std::move(front));
    }
  }
};

FacePaths trace_paths(const PatchGrid& g, const TrimDomain& trim, bool transposed,
                      const StripWidth& width, const IsoParams& p, const ProgressSlice& progress) {
  const double flat = stepover_for_scallop(p.ball_radius, p.scallop_height);
  Tracer t{g, trim, transposed, width, p, progress, flat, {}, {}};
  t.s.sample_max = flat;
  t.s.min_spacing = 0.02 * flat;
  t.max_paths = static_cast<std::size_t>(8.0 * g.size() / t.s.min_spacing) + 100;
  t.out.index = std::make_shared<PathIndex>(flat);
  t.propagate(start_front(g, flat, t.s.sample_max));
  progress.report(0.8);
  t.fill_gaps();
  return std::move(t.out);
}

// Contact points of a piece as a curve: parameter t in [k, k+1] runs
// straight in (u, v) from sample k to k+1 (working grid).
ParamPt uv_at(const FrontPiece& pc, double t) {
  const std::size_t k = std::min(static_cast<std::size_t>(std::max(t, 0.0)), pc.size() - 2);
  const double f = t - double(k);
  return {pc[k].uv.u + f * (pc[k + 1].uv.u - pc[k].uv.u),
          pc[k].uv.v + f * (pc[k + 1].uv.v - pc[k].uv.v)};
}

class PieceCutter {
 public:
  PieceCutter(const PatchGrid& g, const TrimDomain& trim, bool transposed, const IsoParams& p,
              const ClearanceModel& model)
      : g_(g),
        trim_(trim),
        transposed_(transposed),
        p_(p),
        model_(model),
        clearance_(model.query_distance(p.ball_radius - p.chord_tolerance - p.gouge_tolerance)) {}

  // The clear pieces of centre path over the parts of `pc` inside the face.
  // `clipped` receives the contact polyline of each part inside the face.
  void cut(const FrontPiece& pc, std::vector<CutPiece>* out, int* curves, double* unreachable,
           double* from_above, PathIndex* clipped) const {
    for (const auto& [a, b] : inside_runs(pc)) {
      FrontPiece contact;
      for (double t = a;; t = std::min(b, std::floor(t) + 1.0)) {
        FrontPoint x;
        x.uv = uv_at(pc, t);
        x.p = g_.eval(x.uv.u, x.uv.v);
        contact.push_back(x);
        if (t >= b) break;
      }
      clipped->add(contact);
      std::vector<gp_Pnt> pts;
      std::vector<double> ts;
      auto f = [&](double t) { return centre(uv_at(pc, t)); };
      for (double k = std::floor(a); k < b; k += 1.0) {
        const double lo = std::max(a, k), hi = std::min(b, k + 1.0);
        if (hi - lo < 1e-12) continue;
        std::vector<double> tk;
        const std::vector<gp_Pnt> seg = linearize(f, lo, hi, p_.chord_tolerance, {}, 1, &tk);
        for (std::size_t i = pts.empty() ? 0 : 1; i < seg.size(); ++i) {
          pts.push_back(seg[i]);
          ts.push_back(tk[i]);
        }
      }
      double full = 0;
      for (std::size_t i = 1; i < pts.size(); ++i) full += pts[i - 1].Distance(pts[i]);
      if (pts.size() < 2 || full <= 1e-6) continue;
      ++*curves;
      double kept = 0;
      for (CutPiece& piece :
           clear_pieces(pts, ts, f, model_, clearance_, p_.chord_tolerance, from_above)) {
        kept += piece.length();
        out->push_back(std::move(piece));
      }
      *unreachable += full - kept;
    }
  }

 private:
  gp_Pnt centre(const ParamPt& uv) const {
    const SurfaceDerivs d = g_.d1(uv.u, uv.v);
    return d.p.Translated(g_.normal(uv.u, uv.v, &d) * p_.ball_radius);
  }
  bool inside(const ParamPt& uv) const {
    return transposed_ ? trim_.contains(uv.v, uv.u) : trim_.contains(uv.u, uv.v);
  }
  TrimDomain::RectClass classify(const ParamPt& a, const ParamPt& b) const {
    const double u0 = std::min(a.u, b.u), u1 = std::max(a.u, b.u);
    const double v0 = std::min(a.v, b.v), v1 = std::max(a.v, b.v);
    return transposed_ ? trim_.classify_rect(v0, v1, u0, u1) : trim_.classify_rect(u0, u1, v0, v1);
  }
  // Between t_in (inside) and t_out, the end of the inside part, by
  // bisection to 1e-4 of the chord tolerance in space.
  double boundary(const FrontPiece& pc, double t_in, double t_out) const {
    for (int it = 0; it < 60; ++it) {
      const ParamPt a = uv_at(pc, t_in), b = uv_at(pc, t_out);
      if (g_.eval(a.u, a.v).Distance(g_.eval(b.u, b.v)) <= 1e-4 * p_.chord_tolerance) break;
      const double m = 0.5 * (t_in + t_out);
      (inside(uv_at(pc, m)) ? t_in : t_out) = m;
    }
    return t_in;
  }
  // The parameter intervals of the piece inside the face: a segment whose
  // rectangle may meet the boundary is also tested at 7 interior points.
  std::vector<std::pair<double, double>> inside_runs(const FrontPiece& pc) const {
    std::vector<std::pair<double, double>> runs;
    bool in = inside(pc[0].uv);
    double start = 0.0;
    for (std::size_t k = 0; k + 1 < pc.size(); ++k) {
      using RectClass = TrimDomain::RectClass;
      RectClass state = classify(pc[k].uv, pc[k + 1].uv);
      // An end inside (or the previous run open) contradicts "outside": test it.
      if (state == RectClass::Outside && (in || inside(pc[k + 1].uv))) state = RectClass::Boundary;
      if (state == RectClass::Inside && in) continue;
      std::vector<double> ts;
      if (state == RectClass::Boundary)
        for (int q = 1; q < 8; ++q) ts.push_back(double(k) + q / 8.0);
      ts.push_back(double(k + 1));
      double tp = double(k);
      for (double t : ts) {
        const bool s = state == RectClass::Outside ? false : inside(uv_at(pc, t));
        if (in && !s) runs.emplace_back(start, boundary(pc, tp, t));
        if (!in && s) start = boundary(pc, t, tp);
        in = s;
        tp = t;
      }
    }
    if (in) runs.emplace_back(start, double(pc.size() - 1));
    return runs;
  }

  const PatchGrid& g_;
  const TrimDomain& trim_;
  bool transposed_;
  const IsoParams& p_;
  const ClearanceModel& model_;
  double clearance_;
};

struct FaceOut {
  FacePaths paths;
  std::shared_ptr<const PatchGrid> grid;
  IsoDirection dir = IsoDirection::V;
  double gap = 0.0, gap_scallop = 0.0;  // sample_coverage()
  std::optional<std::string> failed;    // why the geometry defeated it (face_failure.h)
  // Meets the scallop asked (5% for what the samples miss) by its certificate.
  bool meets(double h) const { return std::max(paths.scallop, gap_scallop) <= 1.05 * h; }
};

// Phase 1: the paths of every face in every direction tried (tasks on
// threads), each with its certificate before the clip.
std::vector<FaceOut> plan_faces(const std::vector<ScallopFace>& faces,
                                const std::vector<IsoDirection>& dirs, const StripWidth& width,
                                const IsoParams& params, const ProgressSlice& all) {
  const std::size_t nd = dirs.size();
  const double flat = stepover_for_scallop(params.ball_radius, params.scallop_height);
  std::vector<FaceOut> tried(faces.size() * nd);
  TaskProgress tracing(all.sub(0.0, 0.7), tried.size());
  for_each_index(tried.size(), params.threads, [&](std::size_t k) {
    const ScallopFace& face = faces[k / nd];
    FaceOut& o = tried[k];
    o.dir = dirs[k % nd];
    const bool transposed = o.dir == IsoDirection::U;
    o.failed = face_failure(face.index, [&] {
      o.grid = std::make_shared<const PatchGrid>(transposed ? face.grid->transposed() : *face.grid);
      o.paths = trace_paths(*o.grid, *face.trim, transposed, width, params, tracing.task(k));
      sample_coverage(*o.grid, *face.trim, transposed, *o.paths.index, params.ball_radius, flat,
                      o.paths.max_spacing, &o.gap, &o.gap_scallop);
    });
  });
  return tried;
}

// Phase 2: per face, among the directions that did not fail (a failed one
// beside another is a warning), the one that meets the scallop by its
// certificate, then the shorter one; if all failed, the first failure.
std::vector<FaceOut> choose(std::vector<FaceOut> tried, std::size_t nd, double h,
                            std::vector<std::string>* warnings) {
  std::vector<FaceOut> chosen(tried.size() / nd);
  for (std::size_t f = 0; f < chosen.size(); ++f) {
    std::size_t best = f * nd;
    for (std::size_t d = 1; d < nd; ++d) {
      const FaceOut &a = tried[f * nd + d], &b = tried[best];
      const bool ma = a.meets(h), mb = b.meets(h);
      if (a.failed) continue;
      if (b.failed || (ma && !mb) || (ma == mb && a.paths.length < b.paths.length))
        best = f * nd + d;
    }
    for (std::size_t d = 0; d < nd && !tried[best].failed; ++d)
      if (tried[f * nd + d].failed)
        warnings->push_back(*tried[f * nd + d].failed + "; direction " +
                            (tried[f * nd + d].dir == IsoDirection::U ? "U" : "V") +
                            " left out, the other used");
    chosen[f] = std::move(tried[best]);
  }
  return chosen;
}

struct FaceCut {
  std::vector<CutPiece> pieces;
  int curves = 0;
  double unreachable = 0.0, from_above = 0.0;
};

// Phase 3: a face's paths clipped, offset, cut for clearance, zig-zag; and
// its certificate measured again on the clipped paths (near a hole's wire
// that runs along the passes, the pass that would have cut there was
// clipped away, as isocurves are).
FaceCut cut_face(FaceOut* o, const ScallopFace& face, const IsoParams& params,
                 const ClearanceModel& model, const ProgressSlice& all) {
  FaceCut out;
  const bool transposed = o->dir == IsoDirection::U;
  const PieceCutter cutter(*o->grid, *face.trim, transposed, params, model);
  const double flat = stepover_for_scallop(params.ball_radius, params.scallop_height);
  PathIndex clipped(flat);
  for (std::size_t i = 0; i < o->paths.paths.size(); ++i) {
    all.check();
    std::vector<CutPiece> pieces;
    for (const FrontPiece& pc : o->paths.paths[i])
      cutter.cut(pc, &pieces, &out.curves, &out.unreachable, &out.from_above, &clipped);
    if (i % 2 == 1) {  // zig-zag
      std::reverse(pieces.begin(), pieces.end());
      for (CutPiece& pc : pieces) pc.reverse();
    }
    std::move(pieces.begin(), pieces.end(), std::back_inserter(out.pieces));
  }
  sample_coverage(*o->grid, *face.trim, transposed, clipped, params.ball_radius, 0.5 * flat,
                  o->paths.max_spacing, &o->gap, &o->gap_scallop);
  return out;
}

// Phase 4: one face's part of the result.
void add_face(const FaceOut& o, FaceCut cut, int face_index, ScallopPieces* out) {
  out->failed.push_back(o.failed);
  if (o.failed) {
    out->face_direction.push_back(IsoDirection::Auto);
    return;
  }
  const FacePaths& fp = o.paths;
  out->face_direction.push_back(o.dir);
  out->paths += static_cast<int>(fp.paths.size());
  out->curves += cut.curves;
  out->unreachable_length += cut.unreachable;
  out->unreachable_from_above += cut.from_above;
  out->max_spacing = std::max({out->max_spacing, fp.max_spacing, 2 * o.gap});
  out->guaranteed_scallop = std::max({out->guaranteed_scallop, fp.scallop, o.gap_scallop});
  out->max_width = std::max(out->max_width, fp.max_width);
  std::move(cut.pieces.begin(), cut.pieces.end(), std::back_inserter(out->pieces));
  if (fp.min_hits > 0)
    out->warnings.push_back(
        face_label(face_index) + ": the strip width asked for a spacing below " +
        "the minimum (2% of the flat stepover) at " + std::to_string(fp.min_hits) +
        " points; the minimum was used there (see guaranteed_scallop)");
  if (fp.capped)
    out->warnings.push_back(face_label(face_index) + ": constant-scallop paths stopped at " +
                            std::to_string(fp.paths.size()) +
                            " paths (the cap); the face may not be covered");
}

}  // namespace

ScallopPieces constant_scallop_pieces(const std::vector<ScallopFace>& faces,
                                      const IsoParams& params, const ClearanceModel& model,
                                      Progress* progress, const StripWidth& width_in) {
  // The job passes the chord tolerance it derived; 0 (derive) means nothing here.
  if (!(params.chord_tolerance > 0))
    throw InvalidArgument("chord_tolerance must be > 0 mm here (the job derives it; got " +
                          std::to_string(params.chord_tolerance) + ")");
  const StripWidth width =
      width_in ? width_in : ball_strip_width(params.ball_radius, params.scallop_height);
  std::vector<IsoDirection> dirs{IsoDirection::V, IsoDirection::U};
  if (params.direction != IsoDirection::Auto) dirs = {params.direction};
  const ProgressSlice all(progress);
  ScallopPieces out;
  std::vector<FaceOut> chosen = choose(plan_faces(faces, dirs, width, params, all), dirs.size(),
                                       params.scallop_height, &out.warnings);
  std::vector<FaceCut> cut(faces.size());
  for_each_index(faces.size(), params.threads, [&](std::size_t f) {
    all.check();
    if (chosen[f].failed) return;
    chosen[f].failed = face_failure(
        faces[f].index, [&] { cut[f] = cut_face(&chosen[f], faces[f], params, model, all); });
  });
  all.report(0.95);
  for (std::size_t f = 0; f < faces.size(); ++f)
    add_face(chosen[f], std::move(cut[f]), faces[f].index, &out);
  return out;
}

}  // namespace isocam
