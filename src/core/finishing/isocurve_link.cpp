// Ordering and linking of cut pieces into one path.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include "finishing/coverage.h"
#include "finishing/task_pool.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

// A feed link from the end of `a` to the start of `b` (its end if
// `b_reversed`), or an empty vector if none keeps the ball clear of the
// model. Between pieces of one face the
// link follows the offset surface along the straight parameter segment (the
// ball stays tangent to the face); otherwise (other faces, or pieces with
// no grid such as parallel-plane curves) it is a straight move.
std::vector<gp_Pnt> feed_link(const CutPiece& a, const CutPiece& b, bool b_reversed,
                              const IsoParams& params, const ClearanceModel& model,
                              double clearance) {
  std::vector<gp_Pnt> link;
  const gp_Pnt& b_start = b_reversed ? b.pts.back() : b.pts.front();
  const double b_t = b_reversed ? b.t.back() : b.t.front();
  // The middle first: a link that is not clear mostly crosses something (a
  // valley, another face) away from its ends, which were cut clear; one
  // point query refuses it before it is linearised.
  if (a.grid && a.grid == b.grid) {
    const PatchGrid& g = *a.grid;
    const double r = params.ball_radius;
    const double t0 = a.t.back(), v0 = a.level, t1 = b_t, v1 = b.level;
    auto centre = [&](double s) {
      const double t = t0 + (t1 - t0) * s, v = v0 + (v1 - v0) * s;
      const SurfaceDerivs d = g.d1(t, v);
      return d.p.Translated(g.normal(t, v, &d) * r);
    };
    if (!model.clear(centre(0.5), clearance)) return {};
    link = linearize(centre, 0.0, 1.0, params.chord_tolerance, {}, 2);
    link.front() = a.pts.back();
    link.back() = b_start;
  } else {
    link = {a.pts.back(), b_start};
    if (!model.clear(link[0].Translated(0.5 * gp_Vec(link[0], link[1])), clearance)) return {};
  }
  std::vector<char> ok(link.size(), 0);
  model.clear_polyline(link.data(), link.size(), clearance, ok.data());
  for (std::size_t k = 0; k + 1 < link.size(); ++k)
    if (!ok[k]) return {};
  return link;
}

struct Candidate {
  double distance;
  std::size_t piece;
  bool reversed;
};

double polyline_length(const std::vector<gp_Pnt>& pts) {
  double s = 0;
  for (std::size_t k = 1; k < pts.size(); ++k) s += pts[k - 1].Distance(pts[k]);
  return s;
}

// The lowest of the increasing `tries` at which `clear` holds, lowered by
// bisection to `tol` towards the try before it (or `below`, a value known
// not to hold) where there is one; nothing if it holds at none. `clear` is
// taken to grow with its argument (a higher start only shortens the move it
// checks); what is returned has been checked.
template <class Clear>
std::optional<double> lowest_clear(const std::vector<double>& tries, std::optional<double> below,
                                   double tol, Clear clear) {
  for (double hi : tries) {
    if (!clear(hi)) {
      below = hi;
      continue;
    }
    while (below && hi - *below > tol) {
      const double mid = 0.5 * (*below + hi);
      (clear(mid) ? hi : *below) = mid;
    }
    return hi;
  }
  return std::nullopt;
}

// The lift from a ball centre a to a height (the program's last lift to
// the safe height; the first part of every hop). Times in minutes.
struct Lift {
  // Where the lift starts, if not at a: the end of a fed move out of a
  // (along the normal, or back along the pass and up; AirMoves::plan()).
  std::optional<gp_Pnt> leave;
  double top = 0.0;  // centre height it rises to (of the move across, in a hop)
  // The lift from a: fed (at the vertical feed) up to this centre height,
  // from there a rapid; a's own height if the whole lift is a rapid.
  double fed_to = 0.0;
  double time = 0.0;  // estimated at the rates of the params
};

// The air moves between two ball centres a and b (or from the safe height
// when a is null): ball centres up (the lift), across, down (rapids) to the
// approach point, then the fed entry from there to b.
struct Hop : Lift {
  gp_Pnt approach;    // where the fed entry starts (the descent's end)
  bool ramp = false;  // the entry is a ramp (at the horizontal feed), not a plunge
};

class AirMoves {
 public:
  AirMoves(const IsoParams& p, const ClearanceModel& model)
      : p_(p),
        model_(model),
        safe_c_(p.safe_z + p.ball_radius),
        cut_(model.query_distance(p.ball_radius - p.chord_tolerance - p.gouge_tolerance)),
        air_(model.query_distance(p.ball_radius + p.air_clearance)),
        touch_(model.query_distance(p.ball_radius + 0.5 * std::sqrt(3.0) * p.posted_resolution)) {}

  double cutting_clearance() const { return cut_; }

  // Rapids keep r + air_clearance from the model (the move across, the
  // descent); the lift from a cutting position and the fed entry keep the
  // cutting clearance. The entry starts from one of two points, whichever
  // makes the faster hop (plan_from()): a ramp down to b along the pass
  // (`dir`, horizontal, if given) from air_clearance back and as much above
  // it, fed at the horizontal feed (three times the vertical one), where
  // that ramp is clear, and where it is not (the pass starts at a wall)
  // from twice as far ahead, over the pass's own start; or a plunge at the
  // vertical feed from air_clearance above b, or where that point is not
  // clear (a steep wall) from out along the surface normal `n` at b:
  // air_clearance, twice that (b may be a little nearer than r to the
  // wall), or twice that out and as much up (the ground beside the wall
  // may rise), the first clear. A ramp fed from no higher than twice its
  // first try is taken without planning the plunge (the plunge could be at
  // most a third of its length, rarely so).
  //
  // The lift: straight up from a, or, where part of it is fed (a pass
  // that ends beside a wall lifts along it at the vertical feed) and that
  // is faster, first fed out of a (at the vertical feed): along the
  // surface normal `a_n` there air_clearance, or back along the pass
  // (`a_dir`, the horizontal direction it ended in) twice air_clearance and
  // up as much, where that move is clear; then up.
  Hop plan(const gp_Pnt* a, const gp_Pnt& b, const gp_Vec* n, const gp_Vec* dir,
           const gp_Vec* a_n = nullptr, const gp_Vec* a_dir = nullptr) const {
    Entry e = entry(b, n, dir);
    return leave_and(a, a_n, a_dir, [&](const gp_Pnt* from) { return plan_entry(from, b, &e); });
  }

  // The lift from a at the end of the program, to the safe height (by the
  // same choice of a move out as plan()'s).
  Lift retract(const gp_Pnt& a, const gp_Vec* a_n, const gp_Vec* a_dir) const {
    return leave_and(&a, a_n, a_dir, [&](const gp_Pnt* from) {
      Lift h;
      h.top = safe_c_;
      h.fed_to = lift_fed_to(*from, safe_c_);
      h.time = (h.fed_to - from->Z()) / p_.plunge_rate + (safe_c_ - h.fed_to) / p_.rapid_rate;
      return h;
    });
  }

 private:
  // Where an entry to b may start, found once per hop (it does not depend
  // on where the lift starts): a ramp's start, if one is clear, found at
  // once; the plunge's the first time a hop needs it (a ramp fed from low
  // enough is taken without it).
  struct Entry {
    const gp_Vec* n;  // the normal at b, if given
    std::optional<gp_Pnt> ramp_from;
    std::optional<gp_Pnt> plunge_from;
  };

  // The point air_clearance straight above b.
  gp_Pnt air_above(const gp_Pnt& b) const { return gp_Pnt(b.X(), b.Y(), b.Z() + p_.air_clearance); }

  Entry entry(const gp_Pnt& b, const gp_Vec* n, const gp_Vec* dir) const {
    const double air = p_.air_clearance;
    const gp_Pnt above = air_above(b);
    Entry e{n, std::nullopt, std::nullopt};
    if (dir)
      for (const gp_Pnt& from :
           {above.Translated(*dir * -air), above.Translated(*dir * (2.0 * air))})
        if (model_.clear(from, b, cut_)) {
          e.ramp_from = from;
          break;
        }
    return e;
  }

  gp_Pnt plunge_from(const gp_Pnt& b, const gp_Vec* n) const {
    const double air = p_.air_clearance;
    const gp_Pnt above = air_above(b);
    if (n && !model_.clear(above, air_))
      for (const gp_Vec& out : {*n * air, *n * (2.0 * air), (*n + gp_Vec(0, 0, 1)) * (2.0 * air)})
        if (model_.clear(b.Translated(out), air_)) return b.Translated(out);
    return above;
  }

  // The hop from a, lifting straight up, with the faster of the entries.
  Hop plan_entry(const gp_Pnt* a, const gp_Pnt& b, Entry* e) const {
    std::optional<Hop> ramp;
    if (e->ramp_from) {
      ramp = plan_from(a, b, *e->ramp_from, true);
      if (ramp->ramp && ramp->approach.Z() - b.Z() <= 2.0 * p_.air_clearance) return *ramp;
    }
    if (!e->plunge_from) e->plunge_from = plunge_from(b, e->n);
    const Hop plunge = plan_from(a, b, *e->plunge_from, false);
    return ramp && ramp->time < plunge.time ? *ramp : plunge;
  }

  // The faster of the ways out of a, each followed by rest(from): what
  // comes after a lift starting at `from` (the hop on, a Hop, or the
  // program's last lift, a Lift; returned as rest() returns it). Straight
  // up from a, or, where part of that lift is fed and a move out is faster,
  // first fed out of a (see plan()).
  template <class Rest>
  auto leave_and(const gp_Pnt* a, const gp_Vec* a_n, const gp_Vec* a_dir, Rest rest) const
      -> decltype(rest(a)) {
    auto best = rest(a);
    const double air = p_.air_clearance;
    // A move out is fed at least air_clearance: only a longer fed lift can
    // be slower.
    if (!a || best.fed_to - a->Z() <= air) return best;
    std::vector<gp_Pnt> leaves;
    if (a_n) leaves.push_back(a->Translated(*a_n * air));
    if (a_dir) leaves.push_back(a->Translated(*a_dir * (-2.0 * air) + gp_Vec(0, 0, 2.0 * air)));
    for (const gp_Pnt& leave : leaves) {
      if (!model_.clear(*a, leave, cut_)) continue;
      auto out = rest(&leave);
      out.time += a->Distance(leave) / p_.plunge_rate;
      out.leave = leave;
      if (out.time < best.time) best = out;
    }
    return best;
  }

  // The hop whose fed entry starts at or above `first` (a ramp or a
  // plunge). The move across: the lowest of the heights max(a.z, first.z) +
  // air_clearance x 2^k found clear, else the safe height (which the caller
  // checked to be above the path; not queried).
  Hop plan_from(const gp_Pnt* a, const gp_Pnt& b, const gp_Pnt& first, bool ramp) const {
    Hop h;
    h.top = safe_c_;
    h.ramp = ramp;
    const double air = p_.air_clearance;
    const double base = a ? std::max(a->Z(), first.Z()) : first.Z();
    for (int k = 0; a && k < 12; ++k) {
      const double z = base + air * double(1 << k);
      if (z >= safe_c_) break;
      if (!model_.clear(up(*a, z), up(first, z), air_)) continue;
      // The lift from the cutting position keeps the cutting clearance;
      // where it does not (an overhang), the safe height, as FreeCAD's own
      // ops retract.
      if (model_.clear(*a, up(*a, z), cut_)) h.top = z;
      break;
    }
    // The descent: rapid to the approach point, lowest first: the lowest of
    // first + air_clearance x (2^k - 1) up whose descent is clear, then
    // lowered by bisection towards the last that is not, to 2% of
    // air_clearance (on a slope the point above b is nearer the ground than
    // its height: there the rapid stops at air_clearance / cos(slope), not
    // at the next power of two).
    h.approach = up(first, h.top);
    auto descent_clear = [&](double dz) {
      const gp_Pnt e = first.Translated(gp_Vec(0, 0, dz));
      return model_.clear(e, up(first, h.top), air_) && model_.clear(e, b, cut_);
    };
    std::vector<double> raises;
    for (int k = 0; k < 13; ++k) {
      // The last try: just under the height across (its own descent is nil).
      const double dz = std::min(air * double((1 << k) - 1), h.top - first.Z() - 0.02 * air);
      if (dz < 0 || (!raises.empty() && dz <= raises.back())) break;
      raises.push_back(dz);
    }
    if (const std::optional<double> dz =
            lowest_clear(raises, std::nullopt, 0.02 * air, descent_clear))
      h.approach = first.Translated(gp_Vec(0, 0, *dz));
    if (h.approach.Z() >= h.top) {  // fed all the way down, straight above b
      h.ramp = false;
      if (a && h.top < safe_c_ &&
          !(model_.clear(up(*a, h.top), up(b, h.top), air_) && model_.clear(up(b, h.top), b, cut_)))
        h.top = safe_c_;
      h.approach = up(b, h.top);
    }
    h.fed_to = a ? lift_fed_to(*a, h.top) : 0.0;
    const double across = a ? std::hypot(h.approach.X() - a->X(), h.approach.Y() - a->Y()) : 0.0;
    const double rapid = (a ? h.top - h.fed_to : 0.0) + across + (h.top - h.approach.Z());
    h.time = rapid / p_.rapid_rate + (a ? (h.fed_to - a->Z()) / p_.plunge_rate : 0.0) +
             h.approach.Distance(b) / (h.ramp ? p_.feed_rate : p_.plunge_rate);
    return h;
  }

  // A lift straight up from a cutting position a to centre height `top`
  // keeps the cutting clearance r - c - g (the reach from above,
  // coverage.h); where, above its first c + g, it passes nearer than
  // r + p to the model (p the posted rounding: a piece ends where the reach
  // does, beside an overhang, and the column grazes it; or it runs up a
  // wall at r, which the rounding may move into the wall), its lower part
  // is fed rather than a rapid, so that no posted rapid cuts: up to a
  // height from which the rest keeps r + p (the whole lift if none). That
  // height: the lowest of a.z + air_clearance x 2^k that does, then lowered
  // by bisection towards the last that does not, to 2% of air_clearance
  // (the column's clearance only grows as its foot rises). Returns the
  // height where the rapid starts.
  double lift_fed_to(const gp_Pnt& a, double top) const {
    const double start = a.Z() + p_.chord_tolerance + p_.gouge_tolerance;
    if (top <= start || model_.clear(up(a, start), up(a, top), touch_)) return a.Z();
    std::vector<double> heights;
    for (int k = 0; k < 12; ++k) {
      const double z = a.Z() + p_.air_clearance * double(1 << k);
      if (z >= top) break;
      heights.push_back(z);
    }
    // From `start` up the column is not clear.
    return lowest_clear(heights, start, 0.02 * p_.air_clearance,
                        [&](double z) { return model_.clear(up(a, z), up(a, top), touch_); })
        .value_or(top);
  }

  static gp_Pnt up(const gp_Pnt& p, double z) { return gp_Pnt(p.X(), p.Y(), z); }
  const IsoParams& p_;
  const ClearanceModel& model_;
  double safe_c_, cut_, air_, touch_;
};

// The horizontal direction from a to b (none if b is straight above or
// below a).
std::optional<gp_Vec> horizontal(const gp_Pnt& a, const gp_Pnt& b) {
  gp_Vec d(a, b);
  d.SetZ(0.0);
  if (d.Magnitude() < 1e-9) return std::nullopt;
  return d.Normalized();
}

// The horizontal direction a piece ends in, and the one it starts in
// (traced from its end if `reversed`).
std::optional<gp_Vec> end_direction(const CutPiece& p) {
  if (p.pts.size() < 2) return std::nullopt;
  return horizontal(p.pts[p.pts.size() - 2], p.pts.back());
}
std::optional<gp_Vec> start_direction(const CutPiece& p, bool reversed) {
  if (p.pts.size() < 2) return std::nullopt;
  return reversed ? horizontal(p.pts.back(), p.pts[p.pts.size() - 2])
                  : horizontal(p.pts[0], p.pts[1]);
}

// The surface normal at the start of a piece, and at its end (none
// without a grid, unless the pattern gave them).
gp_Vec normal_at(const CutPiece& p, double t) {
  const SurfaceDerivs d = p.grid->d1(t, p.level);
  return p.grid->normal(t, p.level, &d);
}
std::optional<gp_Vec> start_normal(const CutPiece& p) {
  return p.grid ? normal_at(p, p.t.front()) : p.front_normal;
}
std::optional<gp_Vec> end_normal(const CutPiece& p) {
  return p.grid ? normal_at(p, p.t.back()) : p.back_normal;
}

const gp_Vec* ptr(const std::optional<gp_Vec>& v) { return v ? &*v : nullptr; }

}  // namespace

Toolpath link_pieces(std::vector<CutPiece> pieces, const IsoParams& params,
                     const ClearanceModel& model) {
  Toolpath path;
  if (pieces.empty()) return path;
  const double r = params.ball_radius, safe = params.safe_z;
  const AirMoves air(params, model);
  const double clearance = air.cutting_clearance();
  const double max_link = 8.0 * r;
  auto tip = [&](MoveKind k, const gp_Pnt& p) { path.add(k, p.X(), p.Y(), p.Z() - r); };
  // Air moves from the current centre (none: the start) to the first point
  // of p by `h`.
  // The fed part of a lift: out of the pass, then up.
  auto lift = [&](const Lift& h) {
    if (h.leave) tip(MoveKind::Plunge, *h.leave);
    if (!path.empty() && h.fed_to > path.z.back() + r)
      path.add(MoveKind::Plunge, path.x.back(), path.y.back(), h.fed_to - r);
  };
  auto enter = [&](const CutPiece& p, const Hop& h) {
    const gp_Pnt& e = h.approach;
    lift(h);
    if (!path.empty() && h.top > path.z.back() + r)
      path.add(MoveKind::Rapid, path.x.back(), path.y.back(), h.top - r);
    path.add(MoveKind::Rapid, e.X(), e.Y(), h.top - r);
    if (e.Z() < h.top) tip(MoveKind::Rapid, e);
    tip(h.ramp ? MoveKind::Ramp : MoveKind::Plunge, p.pts.front());
  };
  auto cut = [&](const CutPiece& p) {
    for (std::size_t k = 1; k < p.pts.size(); ++k) tip(MoveKind::Feed, p.pts[k]);
  };

  std::vector<char> used(pieces.size(), 0);
  std::size_t cur = 0;
  used[0] = 1;
  enter(pieces[0], air.plan(nullptr, pieces[0].pts.front(), ptr(start_normal(pieces[0])),
                            ptr(start_direction(pieces[0], false))));
  cut(pieces[0]);
  std::vector<Candidate> cands;
  const std::size_t batch = params.threads > 0
                                ? std::size_t(params.threads)
                                : std::max<std::size_t>(1, std::thread::hardware_concurrency());
  for (std::size_t step = 1; step < pieces.size(); ++step) {
    const gp_Pnt end = pieces[cur].pts.back();
    cands.clear();
    for (std::size_t j = 0; j < pieces.size(); ++j) {
      if (used[j]) continue;
      cands.push_back({end.Distance(pieces[j].pts.front()), j, false});
      cands.push_back({end.Distance(pieces[j].pts.back()), j, true});
    }
    // The 8 nearest, in order (ties by piece, then end): only they are tried.
    const std::size_t tries = std::min<std::size_t>(8, cands.size());
    std::partial_sort(cands.begin(), cands.begin() + static_cast<std::ptrdiff_t>(tries),
                      cands.end(), [](const Candidate& x, const Candidate& y) {
                        if (x.distance != y.distance) return x.distance < y.distance;
                        if (x.piece != y.piece) return x.piece < y.piece;
                        return x.reversed < y.reversed;
                      });
    const Candidate nearest = cands.front();
    auto start_of = [&](const Candidate& c) -> const gp_Pnt& {
      const CutPiece& q = pieces[c.piece];
      return c.reversed ? q.pts.back() : q.pts.front();
    };
    // A feed link where it is clear and faster than the hop to the nearest
    // piece (a few queries: planned first).
    const CutPiece& q = pieces[nearest.piece];
    const std::optional<gp_Vec> n_next = nearest.reversed ? end_normal(q) : start_normal(q),
                                d_next = start_direction(q, nearest.reversed),
                                n_end = end_normal(pieces[cur]), d_end = end_direction(pieces[cur]);
    const Hop hop =
        air.plan(&end, start_of(nearest), ptr(n_next), ptr(d_next), ptr(n_end), ptr(d_end));
    // The candidates a link might be faster than the hop to, tried in
    // order, a batch of them (one per thread) at a time: the first clear
    // one in order is taken (or the hop, if it is faster), whatever the
    // number of threads.
    std::vector<std::size_t> worth;
    for (std::size_t k = 0; k < tries && cands[k].distance <= max_link; ++k)
      if (cands[k].distance / params.feed_rate < hop.time) worth.push_back(k);
    std::vector<std::vector<gp_Pnt>> tried(worth.size());
    std::vector<gp_Pnt> link;
    Candidate chosen = nearest;
    bool decided = false;
    for (std::size_t k0 = 0; k0 < worth.size() && !decided; k0 += batch) {
      const std::size_t k1 = std::min(worth.size(), k0 + batch);
      for_each_index(k1 - k0, params.threads, [&](std::size_t i) {
        const Candidate& c = cands[worth[k0 + i]];
        tried[k0 + i] =
            feed_link(pieces[cur], pieces[c.piece], c.reversed, params, model, clearance);
      });
      for (std::size_t k = k0; k < k1 && !decided; ++k) {
        if (tried[k].empty()) continue;
        decided = true;
        if (polyline_length(tried[k]) / params.feed_rate < hop.time) {
          link = std::move(tried[k]);
          chosen = cands[worth[k]];
        }
      }
    }
    CutPiece& next = pieces[chosen.piece];
    if (chosen.reversed) next.reverse();
    if (link.empty()) {
      enter(next, hop);
    } else {
      for (std::size_t k = 1; k < link.size(); ++k) tip(MoveKind::Feed, link[k]);
    }
    cut(next);
    used[chosen.piece] = 1;
    cur = chosen.piece;
  }
  const gp_Pnt last(path.x.back(), path.y.back(), path.z.back() + r);
  lift(air.retract(last, ptr(end_normal(pieces[cur])), ptr(end_direction(pieces[cur]))));
  path.add(MoveKind::Rapid, path.x.back(), path.y.back(), safe);
  return path;
}

}  // namespace isocam
