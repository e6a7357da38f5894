// The constant-scallop pattern's driver: the front of paths per face and
// direction (scallop_front.cpp), the measured certificate, the clip to the
// trimmed face, the ball centres and the clearance cuts (see
// constant_scallop.h for the contract).
#include "finishing/constant_scallop.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "finishing/face_failure.h"
#include "finishing/scallop_coverage.h"
#include "finishing/stepover.h"
#include "finishing/task_pool.h"
#include "isocam/errors.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

using Path = std::vector<FrontPiece>;

// The paths of one face in a working grid, with the measured spacing.
struct FacePaths {
  std::vector<Path> paths;
  // Of the ball centres' polylines (the paths' samples offset by r): what
  // the cut's length follows (on curved ground, not the contact's).
  double length = 0.0;
  int pieces = 0;
  // What the direction is chosen by: the centres' length and a link `link`
  // long from each piece to the next (the least: a flat stepover, at the
  // feed, as the links between neighbouring passes are).
  double cost(double link) const { return length + pieces * link; }
  double max_spacing = 0.0, scallop = 0.0, max_width = 0.0;
  // The samples' coverage after the gaps were filled (raise_coverage()).
  double gap = 0.0, gap_scallop = 0.0;
  int min_hits = 0, seeds = 0;
  // The samples the certificate is measured on (about half the flat
  // stepover apart); the face's grid and trimmed domain outlive it.
  std::shared_ptr<const FaceSampling> sampling;
  bool capped = false;
  std::shared_ptr<PathIndex> index;  // all the paths' contact polylines
  // Their parts inside the face's wires (clipped as the cut clips them):
  // what the clip to the face keeps, so that the coverage checks see the
  // ground that a clipped-away pass leaves, beside a hole's wire.
  std::shared_ptr<PathIndex> inside;
};

// The points (u, v) + k (du, dv), k = -half..half, clamped to the grid's
// parameter rectangle (a point where the last one is, once).
FrontPiece line_piece(const PatchGrid& g, double u, double v, double du, double dv, int half) {
  FrontPiece pc;
  for (int k = -half; k <= half; ++k) {
    FrontPoint x;
    x.uv = {std::clamp(u + k * du, g.umin(), g.umax()), std::clamp(v + k * dv, g.vmin(), g.vmax())};
    x.p = g.eval(x.uv.u, x.uv.v);
    if (pc.empty() || x.p.Distance(pc.back().p) > 1e-9) pc.push_back(x);
  }
  return pc;
}

// A path through (u, v) along the nearest path of `index` (across the way
// to it), from `step` before to `step` after it in space: the shortest
// that takes a spot the paths left. Empty where no path is near or the
// surface is degenerate there.
FrontPiece along_nearest(const PatchGrid& g, const PathIndex& index, double u, double v,
                         double step) {
  const SurfaceDerivs d = g.d1(u, v);
  gp_Pnt at;
  index.distance(d.p, &at);
  double du = 0.0, dv = 0.0;
  if (d.p.Distance(at) <= 1e-9 ||
      !param_direction(d, g.normal(u, v, &d).Crossed(gp_Vec(d.p, at)), &du, &dv))
    return {};
  const double speed = (d.su * du + d.sv * dv).Magnitude();
  if (!(speed > 0)) return {};
  return line_piece(g, u, v, step * du / speed, step * dv / speed, 1);
}

// Ground a gap `q` from the paths is left with a cusp over h by a ball of
// radius r (the centres up to e off); concave ground tighter than the ball
// (it cannot touch there) never is.
bool left_over(const Gap& q, double r, double h, double e) {
  return q.kappa * r > -1.0 && 2 * q.d > stepover_chord_with_error(r, h, q.kappa, e);
}

// The iso-v piece through (u, v), 4 flat stepovers long.
FrontPiece iso_v_piece(const PatchGrid& g, double u, double v, double flat) {
  const double speed = g.d1(u, v).su.Magnitude();
  return line_piece(g, u, v, speed > 0 ? 0.5 * flat / speed : 0.0, 0.0, 4);
}

// A seed piece resampled (samples at most `sample_max` apart) and both
// ways round: a front from it spreads to both sides; cut, the first alone
// is the path. Empty if it has no length.
std::vector<FrontPiece> seed_path(const PatchGrid& g, FrontPiece pc, double sample_max) {
  if (pc.size() < 2) return {};
  resample(g, &pc, sample_max);
  FrontPiece back(pc.rbegin(), pc.rend());
  for (std::size_t k = 0; k < pc.size(); ++k) pc[k].came = frame_at(g, pc, k).across;
  for (std::size_t k = 0; k < back.size(); ++k) back[k].came = frame_at(g, back, k).across;
  return {pc, back};
}

struct Tracer {
  const PatchGrid& g;
  const TrimDomain& trim;
  bool transposed;
  const StripWidth& width;
  const IsoParams& p;
  const ProgressSlice& progress;
  double flat;
  double h;  // the scallop the strips are spaced for (e included)
  double e;  // the centres' error: chord + posted rounding (stepover.h)
  WireClip clip;
  FrontSettings s;
  FacePaths out;
  std::size_t max_paths = 0, samples = 0;
  // While the gaps are filled: the parts inside the wires of the pieces
  // added since the round before's scan (added_before) and since this
  // round's began (added).
  std::unique_ptr<PathIndex> added = nullptr, added_before = nullptr;

  // A piece into both indexes: whole, and its parts inside the wires.
  void add(const FrontPiece& pc) {
    out.index->add(pc);
    clip.add_inside(pc, out.inside.get(), added.get());
  }

  // Paths from `front` until no point moves (or the cap). With `pairs`,
  // the first front is seeds both ways round (seed_path()): each pair
  // spreads to both sides, and the first of it alone is a path.
  void propagate(std::vector<FrontPiece> front, bool pairs = false) {
    for (bool first = true; !front.empty(); first = false) {
      const std::size_t stride = first && pairs ? 2 : 1;
      auto keep = [&] {
        Path path;
        for (std::size_t i = 0; i < front.size(); i += stride) path.push_back(std::move(front[i]));
        out.paths.push_back(std::move(path));
      };
      progress.check();
      if (out.paths.size() >= max_paths || samples > 20000000) {
        out.capped = true;
        keep();
        return;
      }
      // (Seeds are in the indexes already: fill_gaps() put them there.)
      if (!(first && pairs))
        for (const FrontPiece& pc : front) add(pc);
      FrontStep step = advance_front(g, &front, width, s, *out.index);
      out.min_hits += step.min_hits;
      for (std::size_t i = 0; i < front.size(); i += stride) {
        samples += front[i].size();
        ++out.pieces;
        gp_Pnt last;
        for (std::size_t k = 0; k < front[i].size(); ++k) {
          const FrontPoint& q = front[i][k];
          const gp_Pnt c = q.p.Translated(g.normal(q.uv.u, q.uv.v) * p.ball_radius);
          if (k > 0) out.length += last.Distance(c);
          last = c;
        }
      }
      // The certificate: each point with a successor against the next path.
      // Where the successor is on it (the next path passes within 2% of the
      // spacing: its polyline's chords sag off the contact curve along the
      // feed), the pair's chord is that of the arc marched, the spacing, on
      // the circle of curvature across (the model the width is solved on);
      // where it was cut out (a fold, a loop, covered ground), the next
      // path is not that pair's neighbour and the ground between is
      // certified by the face's samples (FaceSampling::coverage()).
      PathIndex next(flat);
      for (const FrontPiece& pc : step.next) next.add(pc);
      for (const FrontPiece& pc : front)
        for (const FrontPoint& q : pc) {
          // Concave ground tighter than the ball: it cannot touch there.
          if (!q.has_next || q.kappa * p.ball_radius <= -1.0) continue;
          out.max_width = std::max(out.max_width, q.spacing);
          const double c = next.distance(q.p);
          if (c > 1.02 * q.spacing + 1e-9) continue;
          const double chord = std::min(c, chord_of_arc(q.spacing, q.kappa));
          out.max_spacing = std::max(out.max_spacing, chord);
          out.scallop = raise_scallop(out.scallop, p.ball_radius, chord, q.kappa, e);
        }
      keep();
      front = std::move(step.next);
    }
  }

  // Left over h (left_over()) by paths more than the minimum spacing away.
  bool over(const Gap& q) const {
    return 2 * q.d > s.min_spacing && left_over(q, p.ball_radius, h, e);
  }

  // "Start new paths there": where the front left ground uncovered (it split
  // at a fold, turned back, or a wedge stayed between its parts), seeds on
  // the samples of the face (inside its wires) whose distance to the paths
  // leaves a cusp over h, a few rounds. Then the samples' coverage
  // (Definition 1) into out.gap and out.gap_scallop.
  // A sample's gap is kept from one round to the next and measured again
  // only where it is a cell of the index or more, or where a piece added
  // since (added_before, added) comes as near (as close counts: the nearest
  // point may change): the gaps are those to all the paths at the time, as
  // if each were measured anew.
  void fill_gaps() {
    const std::vector<ParamPt> at = out.sampling->points();
    std::vector<Gap> gaps(at.size());
    auto stale = [&](const Gap& q) {
      return q.d >= out.inside->cell() || (added_before && added_before->within(q.x, q.d)) ||
             added->within(q.x, q.d);
    };
    auto update = [&](std::size_t k, bool first) {
      if (first || stale(gaps[k])) gaps[k] = gap_at(g, *out.inside, at[k].u, at[k].v);
    };
    bool fresh = false;  // every gap is the one to all the paths
    for (int round = 0; round < 8; ++round) {
      added = std::make_unique<PathIndex>(out.inside->cell());
      std::vector<FrontPiece> front;
      for (std::size_t k = 0; k < at.size(); ++k) {
        update(k, round == 0);
        if (!over(gaps[k])) continue;
        const auto [u, v] = at[k];
        std::vector<FrontPiece> pair = seed_path(g, iso_v_piece(g, u, v, flat), s.sample_max);
        if (!pair.empty()) add(pair.front());  // the other is the same line
        for (FrontPiece& pc : pair) front.push_back(std::move(pc));
        ++out.seeds;
      }
      fresh = front.empty();
      if (fresh) break;
      progress.check();
      propagate(std::move(front), true);
      added_before = std::move(added);
    }
    if (!fresh) {  // seeds were left for a ninth round: measured as they are
      added = std::make_unique<PathIndex>(out.inside->cell());
      for (std::size_t k = 0; k < at.size(); ++k) update(k, false);
    }
    added.reset();
    added_before.reset();
    for (const Gap& q : gaps) raise_coverage(q, p.ball_radius, e, &out.gap, &out.gap_scallop);
  }
};

// The paths of a face spaced by `width`, with the centres up to e off.
FacePaths trace_paths(const PatchGrid& g, const TrimDomain& trim, bool transposed,
                      const StripWidth& width, const IsoParams& p, double e,
                      const ProgressSlice& progress) {
  const double h = p.scallop_height;
  const double flat = stepover_for_scallop(p.ball_radius, p.scallop_height);
  Tracer t{g,        trim, transposed, width, p,
           progress, flat, h,          e,     WireClip(g, trim, transposed, p.chord_tolerance),
           {},       {}};
  t.out.sampling =
      std::make_shared<const FaceSampling>(g, trim, transposed, 0.5 * flat, p.ball_radius, h, e);
  t.s.sample_max = flat;
  t.s.min_spacing = 0.02 * flat;
  t.max_paths = static_cast<std::size_t>(8.0 * g.size() / t.s.min_spacing) + 100;
  t.out.index = std::make_shared<PathIndex>(flat);
  t.out.inside = std::make_shared<PathIndex>(flat);
  t.propagate(start_front(g, flat, t.s.sample_max));
  progress.report(0.8);
  t.fill_gaps();
  return std::move(t.out);
}

class PieceCutter {
 public:
  PieceCutter(const PatchGrid& g, const TrimDomain& trim, bool transposed, const IsoParams& p,
              const ClearanceModel& model)
      : g_(g),
        trim_(trim),
        transposed_(transposed),
        clip_(g, trim, transposed, p.chord_tolerance),
        p_(p),
        model_(model),
        clearance_(model.query_distance(p.ball_radius - p.chord_tolerance - p.gouge_tolerance)) {}

  // The clear pieces of centre path over the parts of `pc` inside the face.
  // `kept` receives the contact polyline of each piece kept: what the ball
  // cuts, inside the wires and where it is clear and reached from above.
  void cut(const FrontPiece& pc, std::vector<CutPiece>* out, int* curves, double* unreachable,
           double* from_above, std::vector<FrontPiece>* kept) const {
    for (const auto& [a, b] : clip_.inside_runs(pc)) {
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
      double length = 0;
      for (CutPiece& piece :
           clear_pieces(pts, ts, f, model_, clearance_, p_.chord_tolerance, from_above)) {
        length += piece.length();
        piece.front_normal = normal(uv_at(pc, piece.t.front()));
        piece.back_normal = normal(uv_at(pc, piece.t.back()));
        kept->push_back(clip_.contact(pc, piece.t.front(), piece.t.back()));
        out->push_back(std::move(piece));
      }
      *unreachable += full - length;
    }
  }

  // The ball touching the face at (u, v) is reached from above: its column
  // keeps the clearance the cut keeps (as clear_pieces() keeps a vertex).
  // `w`, if given, receives the witness where it is not.
  bool reached(double u, double v, ClearanceModel::Witness* w = nullptr) const {
    return reached_centre(centre({u, v}), w);
  }
  bool reached_centre(const gp_Pnt& c, ClearanceModel::Witness* w = nullptr) const {
    return model_.clear_above(c, clearance_, w);
  }
  // The point of a witness found before shows the ball centre c not reached
  // (ClearanceModel::witness_blocks_above(): what reached_centre() would
  // answer, without a query).
  bool blocked_by(const ClearanceModel::Witness& w, const gp_Pnt& c) const {
    return model_.witness_blocks_above(w, c, clearance_);
  }
  // No ball centre within `radius` of the one touching (u, v) is reached
  // from above: a witness shows the model closer to its column than the
  // clearance less radius and the model's tolerance, so closer than the
  // clearance less the tolerance to the column of any such centre (a query
  // out of its budget shows nothing: false).
  bool unreached_within(double u, double v, double radius) const {
    ClearanceModel::Witness w;
    return !model_.clear_above(centre({u, v}), clearance_ - radius - model_.tolerance(), &w) &&
           w.grid != nullptr;
  }
  gp_Pnt centre(double u, double v) const { return centre({u, v}); }
  bool inside(double u, double v) const {
    return transposed_ ? trim_.contains(v, u) : trim_.contains(u, v);
  }

 private:
  gp_Pnt centre(const ParamPt& uv) const {
    const SurfaceDerivs d = g_.d1(uv.u, uv.v);
    return d.p.Translated(g_.normal(uv.u, uv.v, &d) * p_.ball_radius);
  }
  gp_Vec normal(const ParamPt& uv) const { return g_.normal(uv.u, uv.v); }

  const PatchGrid& g_;
  const TrimDomain& trim_;
  bool transposed_;
  WireClip clip_;
  const IsoParams& p_;
  const ClearanceModel& model_;
  double clearance_;
};

struct FaceOut {
  FacePaths paths;
  std::shared_ptr<const PatchGrid> grid;
  IsoDirection dir = IsoDirection::V;
  double gap = 0.0, gap_scallop = 0.0;  // FaceSampling::coverage()
  std::optional<std::string> failed;    // why the geometry defeated it (face_failure.h)
  double certificate() const { return std::max(paths.scallop, gap_scallop); }
  // Meets the scallop asked by its certificate.
  bool meets(double h) const { return certificate() <= h * (1 + 1e-9); }
};

// Phase 1: the paths of every face in every direction tried (tasks on
// threads), each with its certificate before the clip (against the paths'
// parts inside the wires).
std::vector<FaceOut> plan_faces(const std::vector<ScallopFace>& faces,
                                const std::vector<IsoDirection>& dirs, const StripWidth& width,
                                const IsoParams& params, double e, const ProgressSlice& all) {
  const std::size_t nd = dirs.size();
  std::vector<FaceOut> tried(faces.size() * nd);
  TaskProgress tracing(all.sub(0.0, 0.7), tried.size());
  for_each_index(tried.size(), params.threads, [&](std::size_t k) {
    const ScallopFace& face = faces[k / nd];
    FaceOut& o = tried[k];
    o.dir = dirs[k % nd];
    const bool transposed = o.dir == IsoDirection::U;
    o.failed = face_failure(face.index, [&] {
      o.grid = std::make_shared<const PatchGrid>(transposed ? face.grid->transposed() : *face.grid);
      o.paths = trace_paths(*o.grid, *face.trim, transposed, width, params, e, tracing.task(k));
      o.gap = o.paths.gap;
      o.gap_scallop = o.paths.gap_scallop;
    });
  });
  return tried;
}

// Phase 2: per face, among the directions that did not fail (a failed one
// beside another is a warning), the one that meets the scallop by its
// certificate, then the one of lower FacePaths::cost() (the centres'
// length and a link `flat` long per piece: the flat stepover); if all
// failed, the first failure.
std::vector<FaceOut> choose(std::vector<FaceOut> tried, std::size_t nd, double h, double flat,
                            std::vector<std::string>* warnings) {
  std::vector<FaceOut> chosen(tried.size() / nd);
  for (std::size_t f = 0; f < chosen.size(); ++f) {
    std::size_t best = f * nd;
    for (std::size_t d = 1; d < nd; ++d) {
      const FaceOut &a = tried[f * nd + d], &b = tried[best];
      const bool ma = a.meets(h), mb = b.meets(h);
      if (a.failed) continue;
      if (b.failed || (ma && !mb) || (ma == mb && a.paths.cost(flat) < b.paths.cost(flat)))
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

// The reach border (as the isocurves' border passes, reach_border.h): where
// the wires, the clearance or the reach from above cut a path, the ground
// beside the cut is finished from the one side left, up to a whole spacing
// away, and the pair certificate does not see it. So the face's samples are
// measured against the contact polylines of the pieces kept. A sample that
// the ball reaches from above and that is left with a cusp over h gets a
// short path through it, cut as the others (its parts the ball cannot take
// are not needed, so not counted as unreachable). A sample it does not
// reach stands for the reachable ground up to the reach border, which may
// pass between it and its neighbours: towards each of 8 neighbours a
// sampling step away that the ball reaches, the border is bisected and
// the last point reached treated as a sample. The cusp of every sample
// reached, after its path, enters the certificate, which is measured here
// anew; the ground beyond the reach is the unreachable length.
//
// The samples are a quarter of the flat stepover apart (twice as dense as
// the planning's): between samples the distance to the paths can exceed
// the samples' by up to half the diagonal of the sampling step, and where
// fronts met or gaps were filled (no pair certifies the ground) the
// simulation of the posted program found that excess over the certificate
// at half the stepover (Ball, r 1, h 0.05: 0.054 mm left against 0.05).
// Beside the end of a piece kept the distance peaks between the end and
// the pieces beside it, where samples miss it (a MAT piece: 0.0119 mm left
// against a certificate of 0.01): from the samples there the distance is
// climbed to its local maximum, which is then treated as a sample (climb()).
class ReachBorder {
 public:
  static constexpr double kStep = 0.25;  // the sampling step / the flat stepover
  // Half the length of a spot's path / the flat stepover (cover()).
  static constexpr double kSpotStep = 0.25;

  ReachBorder(FaceOut* o, const FaceSampling& samples, const PieceCutter& cutter,
              const IsoParams& params, double e, PathIndex* kept, FaceCut* out)
      : o_(o),
        samples_(samples),
        g_(*o->grid),
        cutter_(cutter),
        r_(params.ball_radius),
        h_(params.scallop_height),
        e_(e),
        flat_(stepover_for_scallop(r_, h_)),
        kept_(kept),
        fresh_(kept->cell()),
        out_(out),
        threads_(params.threads) {}

  // The samples in blocks: each block's gaps to the pieces kept measured on
  // the threads (read only), then the samples visited in order, a gap
  // measured again where a piece kept since comes as near (nearer()): as one
  // pass in order would, the result does not depend on the threads.
  void fill() {
    o_->gap = o_->gap_scallop = 0.0;
    const std::vector<ParamPt> at = samples_.points();
    std::vector<EndSample> ends;
    std::vector<Gap> block;
    constexpr std::size_t kBlock = 1024;
    for (std::size_t b = 0; b < at.size(); b += kBlock) {
      block.resize(std::min(kBlock, at.size() - b));
      for_each_index(block.size(), threads_, [&](std::size_t k) {
        block[k] = gap_at(g_, *kept_, at[b + k].u, at[b + k].v);
      });
      fresh_ = PathIndex(kept_->cell());
      for (std::size_t k = 0; k < block.size(); ++k) {
        const auto [u, v] = at[b + k];
        const Gap q = nearer(block[k].x, block[k].d) ? gap_at(g_, *kept_, u, v) : block[k];
        if (q.end && !over(q) && may_hide_more(q)) ends.push_back({u, v, q.at, q.x});
        visit(u, v, q);
      }
    }
    climb(ends);
  }

 private:
  // A sample whose nearest point on the pieces kept ends one.
  struct EndSample {
    double u, v;
    gp_Pnt end;
    gp_Pnt x;  // the sample's ground point
  };
  // A piece kept since the block's gaps were measured (fresh_) comes as near
  // to p as d (as close counts: the nearest point may change).
  bool nearer(const gp_Pnt& p, double d) const { return fresh_.within(p, d); }

  bool over(const Gap& q) const { return left_over(q, r_, h_, e_); }
  // Half the diagonal of a sampling step: every point of the face is about
  // this near a sample (less on convex patches, sampled finer).
  double cell_radius() const { return std::sqrt(0.5) * kStep * flat_; }
  // The ground within cell_radius() of the sample may be over h: its distance to
  // the pieces grows by at most that much.
  bool may_hide_more(Gap q) const {
    q.d += cell_radius();
    return over(q);
  }

  // A sample's gap `q`: certified if not over h, else a path through it if
  // the ball reaches it, else the reach border towards its neighbours.
  void visit(double u, double v, const Gap& q) {
    if (!over(q)) return certify(q);
    ClearanceModel::Witness w;
    if (cutter_.reached(u, v, &w)) return cover(u, v);
    border(u, v, w);
  }
  // From (u, v), which the ball does not reach, towards each of its 8
  // neighbours a sampling step away that it reaches: the reach border
  // bisected (6 halvings, to 1/64) and its last point reached treated as a
  // sample (a path there if over h). Where the model blocks the column at
  // (u, v) by more than the farthest neighbour's centre is away, none is
  // reached (PieceCutter::unreached_within()): one query instead of eight,
  // the same answer. `w`: the witness that (u, v) is not reached; a
  // neighbour whose column it blocks, or the witness of a neighbour found
  // not reached before, needs no query (PieceCutter::blocked_by()), nor a
  // point of a bisection whose column the witness of its last point not
  // reached blocks.
  void border(double u, double v, const ClearanceModel::Witness& w) {
    const SurfaceDerivs d = g_.d1(u, v);
    const double du = kStep * flat_ / std::max(d.su.Magnitude(), 1e-12);
    const double dv = kStep * flat_ / std::max(d.sv.Magnitude(), 1e-12);
    std::array<ParamPt, 8> next;
    std::array<gp_Pnt, 8> centres;
    const gp_Pnt c = cutter_.centre(u, v);
    double radius = 0.0;
    std::size_t n = 0;
    for (int a = -1; a <= 1; ++a)
      for (int b = -1; b <= 1; ++b) {
        if (a == 0 && b == 0) continue;
        next[n] = {std::clamp(u + a * du, g_.umin(), g_.umax()),
                   std::clamp(v + b * dv, g_.vmin(), g_.vmax())};
        centres[n] = cutter_.centre(next[n].u, next[n].v);
        radius = std::max(radius, c.Distance(centres[n]));
        ++n;
      }
    if (cutter_.unreached_within(u, v, radius)) return;
    std::array<ClearanceModel::Witness, 9> seen{w};  // the witnesses found so far
    std::size_t n_seen = 1;
    for (std::size_t n1 = 0; n1 < next.size(); ++n1) {
      const auto [u1, v1] = next[n1];
      if (!cutter_.inside(u1, v1) ||
          std::any_of(seen.begin(), seen.begin() + n_seen, [&](const ClearanceModel::Witness& x) {
            return cutter_.blocked_by(x, centres[n1]);
          }))
        continue;
      ClearanceModel::Witness wn;
      if (!cutter_.reached_centre(centres[n1], &wn)) {
        if (wn.grid) seen[n_seen++] = wn;
        continue;
      }
      double s0 = 0.0, s1 = 1.0;
      ClearanceModel::Witness wb = w;
      for (int k = 0; k < 6; ++k) {
        const double m = 0.5 * (s0 + s1);
        const gp_Pnt cm = cutter_.centre(u + m * (u1 - u), v + m * (v1 - v));
        (!cutter_.blocked_by(wb, cm) && cutter_.reached_centre(cm, &wb) ? s1 : s0) = m;
      }
      const double ub = u + s1 * (u1 - u), vb = v + s1 * (v1 - v);
      const Gap qb = gap_at(g_, *kept_, ub, vb);
      if (over(qb))
        cover(ub, vb);
      else
        certify(qb);
    }
  }

  // Beside the end of a piece the ground's cusp peaks where its distance
  // to the end and to the neighbouring pieces is the same, between the
  // samples. From the samples under h whose nearest point ends a piece
  // (and whose ground within cell_radius() may be over h), the distance is
  // climbed to its local maximum within cell_radius() (climb_from()); per
  // end, a sample within cell_radius() of a maximum already found is not
  // climbed again. A maximum over h that the ball reaches gets a path
  // (cover()), one under h enters the certificate; from one the ball does
  // not reach, the reach border towards its neighbours is sampled (border():
  // the climb can pass the border, and the reachable ground before it peaks
  // on it; Ball, r 1, h 0.05: 0.054 mm left on face 17 with the peak
  // dropped).
  void climb(std::vector<EndSample> ends) {
    std::stable_sort(ends.begin(), ends.end(), [](const EndSample& a, const EndSample& b) {
      const double ka[3] = {a.end.X(), a.end.Y(), a.end.Z()};
      const double kb[3] = {b.end.X(), b.end.Y(), b.end.Z()};
      return std::lexicographical_compare(ka, ka + 3, kb, kb + 3);
    });
    std::vector<gp_Pnt> peaks;  // of the current end
    for (std::size_t k = 0; k < ends.size(); ++k) {
      const EndSample& s = ends[k];
      if (k == 0 || !s.end.IsEqual(ends[k - 1].end, 0.0)) peaks.clear();
      if (std::any_of(peaks.begin(), peaks.end(),
                      [&](const gp_Pnt& p) { return p.Distance(s.x) <= cell_radius(); }))
        continue;
      double u = s.u, v = s.v;
      climb_from(&u, &v);
      peaks.push_back(g_.eval(u, v));
      const Gap q = gap_at(g_, *kept_, u, v);
      ClearanceModel::Witness w;
      if (!over(q))
        certify(q);
      else if (cutter_.reached(u, v, &w))
        cover(u, v);
      else
        border(u, v, w);
    }
  }

  // A compass search on the face from (u, v) up the distance to the pieces
  // kept: the 8 directions of the parameter plane at a step in space from
  // half of cell_radius(), halved 3 times, at most 2 moves a step, inside the
  // face and within cell_radius() of the start. Moves (u, v) to the farthest
  // point found.
  void climb_from(double* u, double* v) const {
    const SurfaceDerivs d = g_.d1(*u, *v);
    const double su = std::max(d.su.Magnitude(), 1e-12), sv = std::max(d.sv.Magnitude(), 1e-12);
    const gp_Pnt start = d.p;
    double best = kept_->distance(start);
    double step = 0.5 * cell_radius();
    for (int level = 0; level < 4; ++level, step *= 0.5)
      for (int moves = 0; moves < 2; ++moves) {
        double bu = *u, bv = *v;
        for (int a = -1; a <= 1; ++a)
          for (int b = -1; b <= 1; ++b) {
            if (a == 0 && b == 0) continue;
            const double f = a != 0 && b != 0 ? std::sqrt(0.5) : 1.0;
            const double u1 = std::clamp(*u + a * f * step / su, g_.umin(), g_.umax());
            const double v1 = std::clamp(*v + b * f * step / sv, g_.vmin(), g_.vmax());
            const gp_Pnt x = g_.eval(u1, v1);
            if (x.Distance(start) > cell_radius() || !cutter_.inside(u1, v1)) continue;
            const double d1 = kept_->distance(x);
            if (d1 > best) {
              best = d1;
              bu = u1;
              bv = v1;
            }
          }
        if (bu == *u && bv == *v) break;
        *u = bu;
        *v = bv;
      }
  }
  // A path through (u, v), reached, then its cusp certified. What the cut
  // leaves over h beside a reach border is mostly a spot at the end of a
  // piece kept, so first the shortest path that takes it: half a flat
  // stepover long, along the nearest piece kept (across the way to it).
  // If the sample is still over (the clearance took that path), the
  // longer iso-v seed.
  // Both are cut as they are, (u, v) a vertex of each (no resample: their
  // points are under a flat stepover apart already, and it drops a point
  // within an eighth of one of the last, as the sample could be beside a
  // point clamped to the grid's side): where the reach is a sliver that
  // the ends of the path miss, the cut keeps the part about the sample.
  void cover(double u, double v) {
    cut_seed(along_nearest(g_, *kept_, u, v, kSpotStep * flat_));
    Gap q = gap_at(g_, *kept_, u, v);
    if (over(q)) {
      cut_seed(iso_v_piece(g_, u, v, flat_));
      q = gap_at(g_, *kept_, u, v);
    }
    certify(q);
  }
  // Its parts the ball cannot take are not needed: not unreachable.
  void cut_seed(const FrontPiece& pc) {
    if (pc.size() < 2) return;
    double not_needed = 0.0, not_needed_from_above = 0.0;
    std::vector<FrontPiece> contact;
    cutter_.cut(pc, &out_->pieces, &out_->curves, &not_needed, &not_needed_from_above, &contact);
    for (const FrontPiece& c : contact) {
      kept_->add(c);
      fresh_.add(c);
    }
  }
  // The cusp a sample's gap `q` to the pieces kept leaves, into the
  // certificate.
  void certify(const Gap& q) { raise_coverage(q, r_, e_, &o_->gap, &o_->gap_scallop); }

  FaceOut* o_;
  const FaceSampling& samples_;
  const PatchGrid& g_;
  const PieceCutter& cutter_;
  double r_, h_, e_, flat_;
  PathIndex* kept_;
  // The pieces cover() kept since the block's gaps were measured.
  PathIndex fresh_;
  FaceCut* out_;
  int threads_;
};

// Phase 3a: one path of a face clipped, offset, cut for clearance (every
// other path's pieces run back: zig-zag), with the contact polylines of the
// pieces kept. A path's cut depends on it alone.
struct PathCut {
  FaceCut cut;
  std::vector<FrontPiece> contact;
};

PathCut cut_path(const PieceCutter& cutter, const Path& path, std::size_t i) {
  PathCut out;
  FaceCut& c = out.cut;
  for (const FrontPiece& pc : path)
    cutter.cut(pc, &c.pieces, &c.curves, &c.unreachable, &c.from_above, &out.contact);
  if (i % 2 == 1) {
    std::reverse(c.pieces.begin(), c.pieces.end());
    for (CutPiece& pc : c.pieces) pc.reverse();
  }
  return out;
}

// Phase 3b: a face's paths' cuts merged in order, and its certificate
// measured again on the pieces kept, with paths added where the cut left
// ground beside it (ReachBorder).
FaceCut finish_cut(FaceOut* o, const ScallopFace& face, const PieceCutter& cutter,
                   std::vector<PathCut> per, const IsoParams& params, double e) {
  FaceCut out;
  const double flat = stepover_for_scallop(params.ball_radius, params.scallop_height);
  PathIndex kept(flat);
  for (PathCut& pc : per) {
    for (const FrontPiece& k : pc.contact) kept.add(k);
    std::move(pc.cut.pieces.begin(), pc.cut.pieces.end(), std::back_inserter(out.pieces));
    out.curves += pc.cut.curves;
    out.unreachable += pc.cut.unreachable;
    out.from_above += pc.cut.from_above;
  }
  const FaceSampling samples(*o->grid, *face.trim, o->dir == IsoDirection::U,
                             ReachBorder::kStep * flat, params.ball_radius, params.scallop_height,
                             e);
  ReachBorder(o, samples, cutter, params, e, &kept, &out).fill();
  return out;
}

// Phase 3: every face's paths cut as one list of tasks on the threads (so a
// large face among small ones is shared out too), then each face's reach
// border, the faces on the threads. A face fails with the first of its
// paths that failed.
std::vector<FaceCut> cut_faces(std::vector<FaceOut>* chosen, const std::vector<ScallopFace>& faces,
                               const IsoParams& params, const ClearanceModel& model, double e,
                               const ProgressSlice& all) {
  std::vector<FaceOut>& c = *chosen;
  std::vector<std::optional<PieceCutter>> cutters(faces.size());
  std::vector<std::vector<PathCut>> per(faces.size());
  std::vector<std::pair<std::size_t, std::size_t>> tasks;  // (face, path)
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (c[f].failed) continue;
    cutters[f].emplace(*c[f].grid, *faces[f].trim, c[f].dir == IsoDirection::U, params, model);
    per[f].resize(c[f].paths.paths.size());
    for (std::size_t i = 0; i < per[f].size(); ++i) tasks.emplace_back(f, i);
  }
  std::vector<std::optional<std::string>> task_failed(tasks.size());
  for_each_index(tasks.size(), params.threads, [&](std::size_t k) {
    all.check();
    const auto [f, i] = tasks[k];
    task_failed[k] = face_failure(
        faces[f].index, [&] { per[f][i] = cut_path(*cutters[f], c[f].paths.paths[i], i); });
  });
  for (std::size_t k = 0; k < tasks.size(); ++k) {
    std::optional<std::string>& failed = c[tasks[k].first].failed;
    if (task_failed[k] && !failed) failed = std::move(task_failed[k]);
  }
  std::vector<FaceCut> cut(faces.size());
  for_each_index(faces.size(), params.threads, [&](std::size_t f) {
    all.check();
    if (c[f].failed) return;
    c[f].failed = face_failure(faces[f].index, [&] {
      cut[f] = finish_cut(&c[f], faces[f], *cutters[f], std::move(per[f]), params, e);
    });
  });
  return cut;
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
  // The centres' error (stepover.h): the strips are spaced for the cusp
  // the budget leaves, so the certificate, e included, stays under h.
  const double e = params.chord_tolerance + 0.5 * std::sqrt(3.0) * params.posted_resolution;
  std::vector<IsoDirection> dirs{IsoDirection::V, IsoDirection::U};
  if (params.direction != IsoDirection::Auto) dirs = {params.direction};
  const ProgressSlice all(progress);
  ScallopPieces out;
  const StripWidth width =
      width_in ? width_in : ball_strip_width(params.ball_radius, params.scallop_height, e);
  std::vector<FaceOut> chosen =
      choose(plan_faces(faces, dirs, width, params, e, all), dirs.size(), params.scallop_height,
             stepover_for_scallop(params.ball_radius, params.scallop_height), &out.warnings);
  std::vector<FaceCut> cut = cut_faces(&chosen, faces, params, model, e, all);
  all.report(0.95);
  for (std::size_t f = 0; f < faces.size(); ++f)
    add_face(chosen[f], std::move(cut[f]), faces[f].index, &out);
  return out;
}

}  // namespace isocam
