// The constant-scallop front: strip widths, marches across the feed on the
// surface, and the next path from the current one with its folds and loops
// cut out (Y.S. Lee 1998, sections 3-5; what the paper leaves open is
// handled here as stated in scallop_front.h).
#include "finishing/scallop_front.h"

#include <algorithm>
#include <cmath>

#include "finishing/stepover.h"

namespace isocam {
namespace {

// cos of the largest turn of the front's direction from one path to the next.
constexpr double kTurnBack = 0.25;
// A new point this close to the paths so far, relative to its spacing, is
// where they cut already.
constexpr double kCovered = 0.7;

ParamPt clamp_to(const PatchGrid& g, ParamPt q) {
  q.u = std::clamp(q.u, g.umin(), g.umax());
  q.v = std::clamp(q.v, g.vmin(), g.vmax());
  return q;
}

double span_width(const std::vector<double>& br, double t) {
  const auto it = std::upper_bound(br.begin(), br.end(), t);
  const std::size_t i =
      std::clamp<std::size_t>(static_cast<std::size_t>(it - br.begin()), 1, br.size() - 1);
  return br[i] - br[i - 1];
}

// Where the curvatures at uv are taken: the exact derivatives there
// (PatchGrid::d2; at a knot, those of the span it opens) and the unit
// normal, with uv kept 1e-4 of its span inside the grid's rectangle: a side
// can be a pole, where the parameters' directions degenerate and the
// curvature's solve for them cancels to nothing (Ball's sphere, face 10:
// 59.6 against its 0.0837 1e-10 of the way from the pole, exact to 5
// digits from 1e-4 to 1e-6). The normal is the point's own: the pole's,
// with the derivatives 1e-4 away, read 0.059 there. `d`, `n`: at uv.
struct CurvatureSite {
  SurfaceDerivs2 d;
  gp_Vec n;
};
CurvatureSite curvature_site(const PatchGrid& g, const ParamPt& uv, const SurfaceDerivs2& d,
                             const gp_Vec& n) {
  const double hu = 1e-4 * span_width(g.ubreaks(), uv.u), hv = 1e-4 * span_width(g.vbreaks(), uv.v);
  const double u = std::clamp(uv.u, g.umin() + hu, g.umax() - hu);
  const double v = std::clamp(uv.v, g.vmin() + hv, g.vmax() - hv);
  if (u == uv.u && v == uv.v) return {d, n};
  const SurfaceDerivs2 in = g.d2(u, v);
  return {in, g.normal(u, v, &in)};
}

// Normal curvatures along the tangent directions `t1` and `t2` (unit) at
// `c` (curvature_site()), convex > 0 (geometry/curvature.h's convention).
void normal_curvatures(const CurvatureSite& c, const gp_Vec& t1, const gp_Vec& t2, double* k1,
                       double* k2) {
  const SurfaceDerivs2& d = c.d;
  const gp_Vec& n = c.n;
  auto kappa = [&](const gp_Vec& t) {
    double a, b;
    if (!param_direction(d, t, &a, &b)) return 0.0;
    const gp_Vec tt = d.su * a + d.sv * b;
    const double len2 = tt.SquareMagnitude();
    if (!(len2 > 0)) return 0.0;
    return -(d.suu * (a * a) + d.suv * (2 * a * b) + d.svv * (b * b)).Dot(n) / len2;
  };
  *k1 = kappa(t1);
  *k2 = kappa(t2);
}

// The unit tangential part of `v` at normal n, or a null vector.
gp_Vec tangential(const gp_Vec& v, const gp_Vec& n) {
  gp_Vec t = v - n * v.Dot(n);
  const double m = t.Magnitude();
  return m > 1e-300 ? t / m : gp_Vec(0, 0, 0);
}

// A march on the surface from `uv` along the tangent direction `dir`, each
// step solved for (du, dv) by param_direction() at its midpoint and the
// direction carried on as the chord of the last step (a discrete geodesic).
// Where a step leaves the grid's rectangle it is projected onto it: kept
// (sliding along the boundary) if that keeps 70% of its length, else the
// march ends there. Points with their arc length s.
struct MarchPt {
  ParamPt uv;
  gp_Pnt p;
  double s = 0.0;
  bool pole = false;  // the march stopped at a degenerate point (a boundary)
};
std::vector<MarchPt> march(const PatchGrid& g, const ParamPt& uv0, const gp_Pnt& p0, gp_Vec dir,
                           double length, double step, bool slide = true) {
  std::vector<MarchPt> out{{uv0, p0, 0.0}};
  ParamPt cur = uv0;
  for (int it = 0; it < 64 && out.back().s < length * (1 - 1e-12); ++it) {
    const double hstep = std::min(step, length - out.back().s);
    double a, b;
    const SurfaceDerivs d = g.d1(cur.u, cur.v);
    if (!param_direction(d, tangential(dir, g.normal(cur.u, cur.v, &d)), &a, &b)) {
      out.back().pole = true;
      break;
    }
    const ParamPt mid = clamp_to(g, {cur.u + 0.5 * hstep * a, cur.v + 0.5 * hstep * b});
    const SurfaceDerivs dm = g.d1(mid.u, mid.v);
    if (!param_direction(dm, tangential(dir, g.normal(mid.u, mid.v, &dm)), &a, &b)) break;
    const ParamPt raw{cur.u + hstep * a, cur.v + hstep * b};
    const ParamPt nxt = clamp_to(g, raw);
    const gp_Pnt pn = g.eval(nxt.u, nxt.v);
    const double ds = out.back().p.Distance(pn);
    const bool clamped = nxt.u != raw.u || nxt.v != raw.v;
    if (clamped && (!slide || ds < 0.7 * hstep)) {
      if (ds > 1e-12) out.push_back({nxt, pn, out.back().s + ds});
      break;
    }
    if (!(ds > 1e-15)) break;
    dir = gp_Vec(out.back().p, pn) / ds;
    out.push_back({nxt, pn, out.back().s + ds});
    cur = nxt;
  }
  return out;
}

// The point at arc length s of a march (linear in the parameters between
// its points, then on the surface).
MarchPt at_length(const PatchGrid& g, const std::vector<MarchPt>& m, double s) {
  if (s >= m.back().s) return m.back();
  std::size_t i = 1;
  while (i + 1 < m.size() && m[i].s < s) ++i;
  const double f = (s - m[i - 1].s) / std::max(m[i].s - m[i - 1].s, 1e-300);
  const ParamPt uv{m[i - 1].uv.u + f * (m[i].uv.u - m[i - 1].uv.u),
                   m[i - 1].uv.v + f * (m[i].uv.v - m[i - 1].uv.v)};
  return {uv, g.eval(uv.u, uv.v), s};
}

// The successor of point k of a piece: the spacing D = min(w(p), w(mid),
// w(q)) (see constant_scallop.h for why the minimum), found by a fixed
// point on one march. `q` gets the new point; false if the point is on the
// boundary already (no successor).
bool successor(const PatchGrid& g, FrontPiece* piece, std::size_t k, const StripWidth& width,
               const FrontSettings& s, FrontPoint* q, bool* min_hit) {
  FrontPoint& p = (*piece)[k];
  const StripFrame f = frame_at(g, *piece, k);
  if (f.feed.SquareMagnitude() < 0.5 || f.across.Dot(p.came) < kTurnBack) return false;
  const double wp = std::clamp(width(f), s.min_spacing, s.max_spacing);
  const std::vector<MarchPt> m = march(g, p.uv, p.p, f.across, wp, 0.34 * wp);
  // W: the width allowed; D: the spacing, no more than the march went (it
  // stops on the boundary).
  double W = wp, D = std::min(wp, m.back().s), kappa = f.kappa_across;
  for (int it = 0; it < 8; ++it) {
    const MarchPt mq = at_length(g, m, D), mm = at_length(g, m, 0.5 * D);
    const StripFrame fq = make_frame(g, mq.uv, f.feed), fm = make_frame(g, mm.uv, f.feed);
    kappa = std::max({f.kappa_across, fq.kappa_across, fm.kappa_across});
    W = std::min({W, width(fq), width(fm)});
    if (W >= D * (1 - 1e-4)) break;
    D = W;
  }
  D = std::min(D, W);  // never wider than a width seen
  *min_hit = W < s.min_spacing;
  D = std::max(D, std::min(s.min_spacing, m.back().s));
  const MarchPt mq = at_length(g, m, D);
  p.spacing = std::min(D, m.back().s);
  p.kappa = kappa;
  p.has_next = m.back().s > 1e-3 * s.min_spacing;
  if (!p.has_next) return false;
  q->uv = mq.uv;
  q->p = mq.p;
  const gp_Vec moved(p.p, mq.p);
  q->came = moved.Magnitude() > 1e-300 ? moved / moved.Magnitude() : p.came;
  return true;
}

// Cuts out a fold: a new point whose step from the last one kept runs
// backwards along the source point's feed is inside a swallowtail.
void cut_folds(const std::vector<gp_Vec>& feeds, FrontPiece* piece) {
  FrontPiece kept;
  for (std::size_t k = 0; k < piece->size(); ++k) {
    if (!kept.empty() && gp_Vec(kept.back().p, (*piece)[k].p).Dot(feeds[k]) <= 0) continue;
    kept.push_back((*piece)[k]);
  }
  *piece = std::move(kept);
}

// Where the parameter segments a0-a1 and b0-b1 cross: the fraction along a.
bool crossing(const ParamPt& a0, const ParamPt& a1, const ParamPt& b0, const ParamPt& b1,
              double* ta) {
  const double rx = a1.u - a0.u, ry = a1.v - a0.v, sx = b1.u - b0.u, sy = b1.v - b0.v;
  const double den = rx * sy - ry * sx;
  if (std::abs(den) < 1e-300) return false;
  const double qx = b0.u - a0.u, qy = b0.v - a0.v;
  const double t = (qx * sy - qy * sx) / den, u = (qx * ry - qy * rx) / den;
  if (t < 0 || t > 1 || u < 0 || u > 1) return false;
  *ta = t;
  return true;
}

// Cuts out the loops of a piece: where segment i crosses a later segment
// j, the points between go and the crossing joins the two.
void cut_loops(const PatchGrid& g, FrontPiece* piece) {
  FrontPiece& pc = *piece;
  for (std::size_t i = 0; i + 2 < pc.size(); ++i) {
    const double ulo = std::min(pc[i].uv.u, pc[i + 1].uv.u),
                 uhi = std::max(pc[i].uv.u, pc[i + 1].uv.u);
    const double vlo = std::min(pc[i].uv.v, pc[i + 1].uv.v),
                 vhi = std::max(pc[i].uv.v, pc[i + 1].uv.v);
    for (std::size_t j = pc.size() - 2; j > i + 1; --j) {
      const ParamPt &b0 = pc[j].uv, &b1 = pc[j + 1].uv;
      if (std::max(b0.u, b1.u) < ulo || std::min(b0.u, b1.u) > uhi || std::max(b0.v, b1.v) < vlo ||
          std::min(b0.v, b1.v) > vhi)
        continue;
      double t;
      if (!crossing(pc[i].uv, pc[i + 1].uv, b0, b1, &t)) continue;
      FrontPoint x;
      x.uv = {pc[i].uv.u + t * (pc[i + 1].uv.u - pc[i].uv.u),
              pc[i].uv.v + t * (pc[i + 1].uv.v - pc[i].uv.v)};
      x.p = g.eval(x.uv.u, x.uv.v);
      x.came = pc[i].came;
      pc.erase(pc.begin() + static_cast<std::ptrdiff_t>(i + 1),
               pc.begin() + static_cast<std::ptrdiff_t>(j + 1));
      pc.insert(pc.begin() + static_cast<std::ptrdiff_t>(i + 1), x);
      break;
    }
  }
}

bool on_boundary(const PatchGrid& g, const ParamPt& q) {
  const double eu = 1e-9 * (g.umax() - g.umin()), ev = 1e-9 * (g.vmax() - g.vmin());
  return q.u <= g.umin() + eu || q.u >= g.umax() - eu || q.v <= g.vmin() + ev ||
         q.v >= g.vmax() - ev;
}

// A piece whose end stopped short of the rectangle's boundary (the face
// widens faster than the front, or a split left it there) is extended
// along the surface in the direction of its end segment up to the
// boundary, if that is within `reach`; so every path runs from boundary to
// boundary and no wedge is left between a side and the path ends.
void extend_ends(const PatchGrid& g, FrontPiece* piece, double reach, double step) {
  for (int end = 0; end < 2 && piece->size() >= 2; ++end) {
    if (end == 1) std::reverse(piece->begin(), piece->end());
    const FrontPoint &a = (*piece)[1], &b = (*piece)[0];
    if (!on_boundary(g, b.uv)) {
      const gp_Vec dir(a.p, b.p);
      if (dir.Magnitude() > 1e-300) {
        const std::vector<MarchPt> m =
            march(g, b.uv, b.p, dir / dir.Magnitude(), reach, step, false);
        if (on_boundary(g, m.back().uv) || m.back().pole) {
          FrontPiece ext;
          for (std::size_t k = m.size() - 1; k >= 1; --k) {
            FrontPoint x;
            x.uv = m[k].uv;
            x.p = m[k].p;
            x.came = b.came;
            ext.push_back(x);
          }
          piece->insert(piece->begin(), ext.begin(), ext.end());
        }
      }
    }
    if (end == 1) std::reverse(piece->begin(), piece->end());
  }
}

std::int64_t cell_key(long i, long j, long k) {
  return (static_cast<std::int64_t>(i & 0x1FFFFF) << 42) |
         (static_cast<std::int64_t>(j & 0x1FFFFF) << 21) | static_cast<std::int64_t>(k & 0x1FFFFF);
}

}  // namespace

bool param_direction(const SurfaceDerivs& d, const gp_Vec& dir, double* a, double* b) {
  const double E = d.su.Dot(d.su), F = d.su.Dot(d.sv), G = d.sv.Dot(d.sv);
  const double det = E * G - F * F;
  if (!(det > 1e-14 * std::max(E * G, 1e-300))) return false;
  const double ru = dir.Dot(d.su), rv = dir.Dot(d.sv);
  *a = (G * ru - F * rv) / det;
  *b = (E * rv - F * ru) / det;
  return std::isfinite(*a) && std::isfinite(*b);
}

StripFrame make_frame(const PatchGrid& g, const ParamPt& uv, const gp_Vec& feed_guess) {
  StripFrame f;
  f.uv = uv;
  const SurfaceDerivs2 d = g.d2(uv.u, uv.v);
  f.p = d.p;
  f.normal = g.normal(uv.u, uv.v, &d);
  f.feed = tangential(feed_guess, f.normal);
  f.across = f.normal.Crossed(f.feed);
  if (f.feed.SquareMagnitude() > 0.5)
    normal_curvatures(curvature_site(g, uv, d, f.normal), f.across, f.feed, &f.kappa_across,
                      &f.kappa_feed);
  return f;
}

void PathIndex::add(const FrontPiece& pc) {
  for (std::size_t k = 1; k < pc.size(); ++k) {
    const gp_Pnt &a = pc[k - 1].p, &b = pc[k].p;
    segs_.emplace_back(a, b);
    ends_.push_back(static_cast<std::uint8_t>((k == 1 ? 1 : 0) | (k + 1 == pc.size() ? 2 : 0)));
    const long i0 = idx(std::min(a.X(), b.X())), i1 = idx(std::max(a.X(), b.X()));
    const long j0 = idx(std::min(a.Y(), b.Y())), j1 = idx(std::max(a.Y(), b.Y()));
    const long k0 = idx(std::min(a.Z(), b.Z())), k1 = idx(std::max(a.Z(), b.Z()));
    for (long i = i0; i <= i1; ++i)
      for (long j = j0; j <= j1; ++j)
        for (long q = k0; q <= k1; ++q) grid_[cell_key(i, j, q)].push_back(segs_.size() - 1);
  }
}

double PathIndex::distance(const gp_Pnt& p, gp_Pnt* at, double enough, bool* end) const {
  // Squared distances throughout; a cell is opened only if its box (grown by
  // a rounding margin, the cells being floor(x / cell)) is nearer than the
  // best segment so far, and the second ring only visits its shell. Each of
  // these skips a segment only where the full scan would have rejected it.
  const double far = 2 * cell_;
  double best2 = far * far;
  const std::pair<gp_Pnt, gp_Pnt>* nearest = nullptr;
  double nearest_t = 0.0;
  const long i = idx(p.X()), j = idx(p.Y()), q = idx(p.Z());
  const double enough2 = enough * enough;
  const double c[3] = {p.X(), p.Y(), p.Z()};
  const long home[3] = {i, j, q};
  auto gap2 = [&](const long cell[3]) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double lo = double(cell[k]) * cell_, hi = lo + cell_;
      const double margin = 1e-9 * (std::abs(lo) + cell_);
      const double d = std::max({lo - margin - c[k], c[k] - hi - margin, 0.0});
      d2 += d * d;
    }
    return d2;
  };
  for (long ring = 1; ring <= 2 && best2 > double(ring - 1) * cell_ * double(ring - 1) * cell_;
       ++ring)
    for (long a = i - ring; a <= i + ring; ++a)
      for (long b = j - ring; b <= j + ring; ++b)
        for (long d = q - ring; d <= q + ring; ++d) {
          const long cell[3] = {a, b, d};
          if (ring == 2 && std::abs(a - home[0]) <= 1 && std::abs(b - home[1]) <= 1 &&
              std::abs(d - home[2]) <= 1)
            continue;  // the first ring's
          if (gap2(cell) >= best2) continue;
          const auto it = grid_.find(cell_key(a, b, d));
          if (it == grid_.end()) continue;
          for (std::size_t sgi : it->second) {
            double t;
            const double d2 = to_segment2(p, segs_[sgi].first, segs_[sgi].second, &t);
            if (d2 >= best2) continue;
            best2 = d2;
            nearest = &segs_[sgi];
            nearest_t = t;
            if (best2 <= enough2 && !at && !end) return std::sqrt(best2);
          }
        }
  if (end) {
    const std::uint8_t f =
        nearest ? ends_[static_cast<std::size_t>(nearest - segs_.data())] : std::uint8_t{0};
    *end = ((f & 1) && nearest_t <= 0.0) || ((f & 2) && nearest_t >= 1.0);
  }
  if (at) {
    *at = p;
    if (nearest) {
      const gp_Pnt &a0 = nearest->first, &b0 = nearest->second;
      *at = a0.Translated(gp_Vec(a0, b0) * nearest_t);
    }
  }
  return nearest ? std::sqrt(best2) : far;
}

bool PathIndex::within(const gp_Pnt& p, double d) const {
  if (segs_.empty()) return false;
  const double c[3] = {p.X(), p.Y(), p.Z()};
  long lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const double margin = 1e-9 * (std::abs(c[k]) + cell_);  // as distance()'s
    lo[k] = idx(c[k] - d - margin);
    hi[k] = idx(c[k] + d + margin);
  }
  for (long a = lo[0]; a <= hi[0]; ++a)
    for (long b = lo[1]; b <= hi[1]; ++b)
      for (long q = lo[2]; q <= hi[2]; ++q) {
        const auto it = grid_.find(cell_key(a, b, q));
        if (it == grid_.end()) continue;
        for (std::size_t s : it->second)
          if (to_segment2(p, segs_[s].first, segs_[s].second) <= d * d) return true;
      }
  return false;
}

long PathIndex::idx(double x) const { return static_cast<long>(std::floor(x / cell_)); }

double to_segment2(const gp_Pnt& p, const gp_Pnt& a, const gp_Pnt& b, double* t) {
  const gp_Vec ab(a, b), ap(a, p);
  const double l2 = ab.SquareMagnitude();
  const double s = l2 > 0 ? std::clamp(ap.Dot(ab) / l2, 0.0, 1.0) : 0.0;
  if (t) *t = s;
  return p.SquareDistance(a.Translated(ab * s));
}

StripWidth ball_strip_width(double r, double h, double e) {
  const double cap = 2.0 * stepover_arc_with_error(r, h, 0.0, e);
  return [r, h, e, cap](const StripFrame& f) {
    return std::min(cap, stepover_arc_with_error(r, h, f.kappa_across, e));
  };
}

double normal_curvature(const PatchGrid& g, const ParamPt& uv, const gp_Vec& dir) {
  const SurfaceDerivs2 d = g.d2(uv.u, uv.v);
  const gp_Vec n = g.normal(uv.u, uv.v, &d);
  const gp_Vec t = tangential(dir, n);
  if (t.SquareMagnitude() < 0.5) return 0.0;
  double k1, k2;
  normal_curvatures(curvature_site(g, uv, d, n), t, t, &k1, &k2);
  return k1;
}

StripFrame frame_at(const PatchGrid& g, const FrontPiece& piece, std::size_t k) {
  const std::size_t a = k > 0 ? k - 1 : k, b = k + 1 < piece.size() ? k + 1 : k;
  return make_frame(g, piece[k].uv, gp_Vec(piece[a].p, piece[b].p));
}

void resample(const PatchGrid& g, FrontPiece* piece, double step) {
  if (piece->size() < 2) return;
  FrontPiece out{piece->front()};
  for (std::size_t k = 1; k < piece->size(); ++k) {
    const FrontPoint &a = (*piece)[k - 1], &b = (*piece)[k];
    const int m = static_cast<int>(std::ceil(a.p.Distance(b.p) / step - 1e-9));
    for (int q = 1; q < std::min(m, 1000); ++q) {
      FrontPoint x;
      const double f = double(q) / m;
      x.uv = {a.uv.u + f * (b.uv.u - a.uv.u), a.uv.v + f * (b.uv.v - a.uv.v)};
      x.p = g.eval(x.uv.u, x.uv.v);
      const gp_Vec c = a.came * (1 - f) + b.came * f;
      x.came = c.Magnitude() > 1e-300 ? c / c.Magnitude() : a.came;
      if (x.p.Distance(out.back().p) >= step / 8) out.push_back(x);
    }
    if (b.p.Distance(out.back().p) >= step / 8 || k + 1 == piece->size()) {
      if (k + 1 == piece->size() && out.size() > 1 && b.p.Distance(out.back().p) < step / 8)
        out.back() = b;
      else
        out.push_back(b);
    }
  }
  *piece = std::move(out);
}

std::vector<FrontPiece> start_front(const PatchGrid& g, double w0, double sample_max) {
  const double umid = 0.5 * (g.umin() + g.umax());
  double v = g.vmin();
  auto iso = [&](double vv) {
    FrontPiece pc;
    for (int k = 0; k <= 64; ++k) {
      FrontPoint x;
      x.uv = {g.umin() + (g.umax() - g.umin()) * k / 64.0, vv};
      x.p = g.eval(x.uv.u, x.uv.v);
      pc.push_back(x);
    }
    return pc;
  };
  FrontPiece pc = iso(v);
  double len = 0;
  for (std::size_t k = 1; k < pc.size(); ++k) len += pc[k - 1].p.Distance(pc[k].p);
  if (len < 1e-6 * g.size()) {
    // A boundary collapsed to a pole: the iso-v w0/4 away from it.
    const gp_Pnt pole = g.eval(umid, g.vmin());
    double lo = g.vmin(), hi = g.vmax();
    for (int it = 0; it < 60; ++it) {
      const double m = 0.5 * (lo + hi);
      (g.eval(umid, m).Distance(pole) < 0.25 * w0 ? lo : hi) = m;
    }
    v = hi;
    pc = iso(v);
  }
  resample(g, &pc, sample_max);
  // The march goes to the left of the feed (N x T): run the start path so
  // that this is into the face (towards larger v).
  const std::size_t mid = pc.size() / 2;
  const StripFrame f = frame_at(g, pc, mid);
  if (f.across.Dot(g.d1(pc[mid].uv.u, pc[mid].uv.v).sv) < 0) std::reverse(pc.begin(), pc.end());
  for (std::size_t k = 0; k < pc.size(); ++k) pc[k].came = frame_at(g, pc, k).across;
  return {pc};
}

FrontStep advance_front(const PatchGrid& g, std::vector<FrontPiece>* front, const StripWidth& width,
                        const FrontSettings& s, const PathIndex& done) {
  FrontStep out;
  for (FrontPiece& piece : *front) {
    FrontPiece cur;
    std::vector<gp_Vec> feeds;
    std::vector<std::size_t> from;  // the points of `piece` that cur's came from
    auto flush = [&]() {
      cut_folds(feeds, &cur);
      cut_loops(g, &cur);
      extend_ends(g, &cur, 4.0 * s.sample_max, 0.5 * s.sample_max);
      resample(g, &cur, s.sample_max);
      double len = 0;
      for (std::size_t k = 1; k < cur.size(); ++k) len += cur[k - 1].p.Distance(cur[k].p);
      if (cur.size() == 1) {
        // A path of one point (a corner the front reaches): a short piece
        // along the feed, so that the point is cut.
        const FrontPoint c = cur[0];
        for (int side = 0; side < 2; ++side) {
          const gp_Vec dir = side ? -feeds[0] : feeds[0];
          const MarchPt e =
              march(g, c.uv, c.p, dir, s.sample_max / 8, s.sample_max / 8, false).back();
          FrontPoint x = c;
          x.uv = e.uv;
          x.p = e.p;
          if (side)
            cur.push_back(x);
          else
            cur.insert(cur.begin(), x);
        }
        len = cur.front().p.Distance(cur.back().p);
      }
      if (cur.size() >= 2 && len > 1e-9 * g.size()) {
        out.next.push_back(std::move(cur));
      } else {
        // Nothing left to cut (the successors met in a pole): their sources
        // have no next path to be measured against (the face's sampled
        // coverage, constant_scallop.cpp, covers the ground beyond them).
        for (std::size_t i : from) piece[i].has_next = false;
      }
      cur.clear();
      feeds.clear();
      from.clear();
    };
    for (std::size_t k = 0; k < piece.size(); ++k) {
      FrontPoint q;
      bool hit = false;
      const bool moved = successor(g, &piece, k, width, s, &q, &hit);
      out.min_hits += hit ? 1 : 0;
      if (!moved) {
        flush();
        continue;
      }
      if (done.distance(q.p, nullptr, kCovered * piece[k].spacing) < kCovered * piece[k].spacing) {
        // Covered already: left out, its neighbours joined across it (a
        // chord through covered ground), unless they end up far apart.
        piece[k].has_next = false;
        continue;
      }
      if (!cur.empty() && cur.back().p.Distance(q.p) > 3 * s.sample_max) flush();
      cur.push_back(q);
      feeds.push_back(frame_at(g, piece, k).feed);
      from.push_back(k);
    }
    flush();
  }
  return out;
}

}  // namespace isocam
