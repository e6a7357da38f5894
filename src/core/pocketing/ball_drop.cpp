// Ball-end cutter location on a sculptured pocket floor, and the path
// interval of Suh & Lee's eq. 11-18.
//
// Suh & Lee compute CC points by intersecting the floor with the ruled
// surface swept down from the profile, then CL = CC + R (n - a) (eq. 5),
// which puts the tool centre off the profile by R n_xy. Here the profile is
// the tool centre's plan path itself and the tip z is the height at which
// the ball rests on the floor, i.e. the floor's ball-end offset surface:
// the ball touches the floor and never enters it (no gouge, also where the
// floor curves more than the ball or at its edges).
#include <BRepAdaptor_Surface.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <TopLoc_Location.hxx>
#include <algorithm>
#include <cmath>

#include "isocam/errors.h"
#include "pocketing/floor_path.h"

namespace isocam::pocket {
namespace {

// Highest ball centre z over (x, y) touching triangle t; -inf if none.
// `w` gets the contact's barycentric weights, `facet` whether it is inside.
double drop_on_triangle(const gp_Pnt p[3], double x, double y, double r, gp_Pnt& contact,
                        double w[3], bool& facet) {
  double best = -1e300;
  const double r2 = r * r;
  for (int k = 0; k < 3; ++k) {  // vertices
    const double dx = x - p[k].X(), dy = y - p[k].Y(), d2 = dx * dx + dy * dy;
    if (d2 <= r2) {
      const double zc = p[k].Z() + std::sqrt(r2 - d2);
      if (zc > best) {
        best = zc;
        contact = p[k];
        w[0] = w[1] = w[2] = 0.0;
        w[k] = 1.0;
        facet = false;
      }
    }
  }
  gp_Vec n = gp_Vec(p[0], p[1]).Crossed(gp_Vec(p[0], p[2]));
  const double nn = n.Magnitude();
  if (nn > 0) {
    n /= nn;
    if (n.Z() < 0) n.Reverse();
    if (n.Z() > 1e-12) {  // facet: contact at (x, y) - R n_xy
      const double cx = x - r * n.X(), cy = y - r * n.Y();
      const double v0x = p[1].X() - p[0].X(), v0y = p[1].Y() - p[0].Y();
      const double v1x = p[2].X() - p[0].X(), v1y = p[2].Y() - p[0].Y();
      const double wx = cx - p[0].X(), wy = cy - p[0].Y();
      const double den = v0x * v1y - v1x * v0y;
      if (std::abs(den) > 0) {
        const double a = (wx * v1y - v1x * wy) / den, b = (v0x * wy - wx * v0y) / den;
        if (a >= 0 && b >= 0 && a + b <= 1) {
          const double cz = p[0].Z() - (n.X() * wx + n.Y() * wy) / n.Z();
          const double zc = cz + r * n.Z();
          if (zc > best) {
            best = zc;
            contact = gp_Pnt(cx, cy, cz);
            w[0] = 1 - a - b;
            w[1] = a;
            w[2] = b;
            facet = true;
          }
        }
      }
    }
  }
  for (int k = 0; k < 3; ++k) {  // edges: |C - A|^2 - ((C - A).d)^2 / |d|^2 = R^2
    const gp_Pnt& A = p[k];
    const gp_Vec d(A, p[(k + 1) % 3]);
    const double L2 = d.SquareMagnitude();
    if (L2 <= 0) continue;
    const gp_Vec wv(x - A.X(), y - A.Y(), -A.Z());
    const double qa = 1.0 - d.Z() * d.Z() / L2;
    if (qa < 1e-12) continue;  // vertical edge: its vertices decide
    const double wd = wv.Dot(d);
    const double qb = 2.0 * (wv.Z() - wd * d.Z() / L2);
    const double qc = wv.SquareMagnitude() - wd * wd / L2 - r2;
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) continue;
    const double zc = (-qb + std::sqrt(disc)) / (2 * qa);
    const double t = (wd + zc * d.Z()) / L2;
    if (t < 0 || t > 1 || zc <= best) continue;
    best = zc;
    contact = A.Translated(t * d);
    w[k] = 1 - t;
    w[(k + 1) % 3] = t;
    w[(k + 2) % 3] = 0.0;
    facet = false;
  }
  return best;
}

}  // namespace

BallDrop::BallDrop(const std::vector<TopoDS_Face>& faces, double radius, double mesh_tol)
    : faces_(faces), r_(radius), mesh_tol_(mesh_tol) {
  for (const TopoDS_Face& f : faces) surf_.emplace_back(f);
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    BRepMesh_IncrementalMesh mesher(faces[f], mesh_tol, false, 0.2, false);
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(faces[f], loc);
    if (tri.IsNull()) throw GeometryError("sculptured floor: the face could not be meshed");
    const gp_Trsf tr = loc.Transformation();
    for (int i = 1; i <= tri->NbTriangles(); ++i) {
      int a, b, c;
      tri->Triangle(i).Get(a, b, c);
      Tri t{{tri->Node(a).Transformed(tr), tri->Node(b).Transformed(tr),
             tri->Node(c).Transformed(tr)},
            {},
            static_cast<int>(f)};
      if (tri->HasUVNodes()) {
        t.uv[0] = tri->UVNode(a);
        t.uv[1] = tri->UVNode(b);
        t.uv[2] = tri->UVNode(c);
      }
      for (const gp_Pnt& q : t.p) {
        x0 = std::min(x0, q.X());
        y0 = std::min(y0, q.Y());
        x1 = std::max(x1, q.X());
        y1 = std::max(y1, q.Y());
      }
      tris_.push_back(t);
    }
  }
  if (tris_.empty()) throw GeometryError("sculptured floor: no triangles");
  cell_ = std::max(r_, std::max(x1 - x0, y1 - y0) / 400.0);
  gx0_ = x0 - r_;
  gy0_ = y0 - r_;
  nx_ = static_cast<long>(std::ceil((x1 - x0 + 2 * r_) / cell_)) + 1;
  ny_ = static_cast<long>(std::ceil((y1 - y0 + 2 * r_) / cell_)) + 1;
  grid_.assign(static_cast<std::size_t>(nx_ * ny_), {});
  for (std::size_t k = 0; k < tris_.size(); ++k) {
    double tx0 = 1e300, ty0 = 1e300, tx1 = -1e300, ty1 = -1e300;
    for (const gp_Pnt& q : tris_[k].p) {
      tx0 = std::min(tx0, q.X());
      ty0 = std::min(ty0, q.Y());
      tx1 = std::max(tx1, q.X());
      ty1 = std::max(ty1, q.Y());
    }
    const long i0 = std::max(0L, static_cast<long>((tx0 - r_ - gx0_) / cell_));
    const long i1 = std::min(nx_ - 1, static_cast<long>((tx1 + r_ - gx0_) / cell_));
    const long j0 = std::max(0L, static_cast<long>((ty0 - r_ - gy0_) / cell_));
    const long j1 = std::min(ny_ - 1, static_cast<long>((ty1 + r_ - gy0_) / cell_));
    for (long j = j0; j <= j1; ++j)
      for (long i = i0; i <= i1; ++i)
        grid_[static_cast<std::size_t>(j * nx_ + i)].push_back(static_cast<int>(k));
  }
}

BallDrop::Contact BallDrop::drop(double x, double y) const {
  Contact c;
  const auto i = static_cast<long>(std::floor((x - gx0_) / cell_));
  const auto j = static_cast<long>(std::floor((y - gy0_) / cell_));
  if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return c;
  double best = -1e300;
  bool facet = false;
  double bw[3] = {0, 0, 0};
  int best_tri = -1;
  for (int k : grid_[static_cast<std::size_t>(j * nx_ + i)]) {
    gp_Pnt cp;
    double w[3] = {0, 0, 0};
    bool f = false;
    const double zc = drop_on_triangle(tris_[static_cast<std::size_t>(k)].p, x, y, r_, cp, w, f);
    if (zc > best) {
      best = zc;
      c.cc = cp;
      facet = f;
      std::copy(w, w + 3, bw);
      best_tri = k;
    }
  }
  if (best_tri < 0) return c;
  const Tri& t = tris_[static_cast<std::size_t>(best_tri)];
  c.hit = true;
  c.face = t.face;
  c.tip_z = best - r_;
  c.u = bw[0] * t.uv[0].X() + bw[1] * t.uv[1].X() + bw[2] * t.uv[2].X();
  c.v = bw[0] * t.uv[0].Y() + bw[1] * t.uv[1].Y() + bw[2] * t.uv[2].Y();
  if (facet) refine(x, y, c);
  return c;
}

// Newton on F(u, v) = S_xy + R N_xy - (x, y) = 0 (numeric Jacobian): the
// exact contact of a ball centred above (x, y) on the face's surface.
void BallDrop::refine(double x, double y, Contact& c) const {
  const BRepAdaptor_Surface& s = surf_[static_cast<std::size_t>(c.face)];
  auto centre = [&](double u, double v, gp_Pnt& S, gp_Vec& n) {
    gp_Vec Su, Sv;
    s.D1(u, v, S, Su, Sv);
    n = Su.Crossed(Sv);
    const double m = n.Magnitude();
    if (m < 1e-300) return false;
    n /= m;
    if (n.Z() < 0) n.Reverse();
    return true;
  };
  double u = c.u, v = c.v;
  const double hu = 1e-7 * std::max(1.0, s.LastUParameter() - s.FirstUParameter());
  const double hv = 1e-7 * std::max(1.0, s.LastVParameter() - s.FirstVParameter());
  gp_Pnt S;
  gp_Vec n;
  for (int it = 0; it < 12; ++it) {
    if (!centre(u, v, S, n)) return;
    const double fx = S.X() + r_ * n.X() - x, fy = S.Y() + r_ * n.Y() - y;
    if (std::hypot(fx, fy) < 1e-9) {
      const double z = S.Z() + r_ * n.Z() - r_;
      // Keep it only where it is the mesh's contact made exact.
      if (std::abs(z - c.tip_z) <= 4.0 * mesh_tol_ && u >= s.FirstUParameter() &&
          u <= s.LastUParameter() && v >= s.FirstVParameter() && v <= s.LastVParameter()) {
        c.tip_z = z;
        c.cc = S;
        c.u = u;
        c.v = v;
      }
      return;
    }
    gp_Pnt S1, S2;
    gp_Vec n1, n2;
    if (!centre(u + hu, v, S1, n1) || !centre(u, v + hv, S2, n2)) return;
    const double j11 = (S1.X() + r_ * n1.X() - x - fx) / hu,
                 j21 = (S1.Y() + r_ * n1.Y() - y - fy) / hu;
    const double j12 = (S2.X() + r_ * n2.X() - x - fx) / hv,
                 j22 = (S2.Y() + r_ * n2.Y() - y - fy) / hv;
    const double det = j11 * j22 - j12 * j21;
    if (std::abs(det) < 1e-300) return;
    u -= (j22 * fx - j12 * fy) / det;
    v -= (j11 * fy - j21 * fx) / det;
  }
}

double path_interval(const BallDrop& floor, const BallDrop::Contact& c, P2 across, double h) {
  const double R = floor.radius();
  const double flat = 2.0 * std::sqrt(2.0 * R * h - h * h);
  if (!c.hit || c.face < 0) return flat;
  const BRepAdaptor_Surface& s = floor.surface(c.face);
  const double u = c.u, v = c.v;
  gp_Pnt P;
  gp_Vec Su, Sv, Suu, Svv, Suv;
  s.D2(u, v, P, Su, Sv, Suu, Svv, Suv);
  gp_Vec n = Su.Crossed(Sv);
  if (n.Magnitude() < 1e-300) return flat;
  n.Normalize();
  if (n.Z() < 0) n.Reverse();
  // Eq. 11: the surface direction whose plan projection is across the loop
  // (perpendicular to the loop's tangent T).
  const gp_Vec T(-across.y, across.x, 0.0);
  const double ud = Sv.Dot(T), vd = -Su.Dot(T);
  const gp_Vec rd = ud * Su + vd * Sv;  // eq. 12
  const double g =
      ud * ud * Su.Dot(Su) + 2 * ud * vd * Su.Dot(Sv) + vd * vd * Sv.Dot(Sv);  // eq. 15
  if (g <= 1e-300 || rd.Magnitude() <= 1e-300) return flat;
  const double dn =
      ud * ud * n.Dot(Suu) + 2 * ud * vd * n.Dot(Suv) + vd * vd * n.Dot(Svv);  // eq. 14
  const double kappa = -dn / g;  // eq. 13; > 0 where the floor is convex (bulges up)
  // Eq. 16-17: distance between ball centres leaving scallop h, from the
  // circle through the contact points with radius rho = 1 / |kappa|.
  double chord = flat;
  if (std::abs(kappa) > 1e-9) {
    const double rho = 1.0 / std::abs(kappa);
    if (kappa > 0) {
      const double cs =
          ((rho + R) * (rho + R) + (rho + h) * (rho + h) - R * R) / (2 * (rho + R) * (rho + h));
      chord = 2 * (rho + R) * std::sin(std::acos(std::clamp(cs, -1.0, 1.0)));
    } else if (rho > R + h) {
      const double cs =
          ((rho - R) * (rho - R) + (rho - h) * (rho - h) - R * R) / (2 * (rho - R) * (rho - h));
      chord = 2 * (rho - R) * std::sin(std::acos(std::clamp(cs, -1.0, 1.0)));
    }
  }
  // Eq. 18: its plan projection.
  const gp_Vec B(across.x, across.y, 0.0);
  return chord * std::abs(B.Dot(rd.Normalized()));
}

}  // namespace isocam::pocket
