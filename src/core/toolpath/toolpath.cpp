#include "isocam/toolpath.h"

#include <cmath>

namespace isocam {

namespace {

constexpr double kTwoPi = 2.0 * 3.14159265358979323846;

double wrap_2pi(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

// Length of arc move i (i >= 1): radius times the sweep in its direction (a
// full turn when it ends where it starts), with the z change as a helix.
double arc_length(const Toolpath& path, std::size_t i) {
  const double ax = path.x[i - 1] - path.cx[i], ay = path.y[i - 1] - path.cy[i];
  const double bx = path.x[i] - path.cx[i], by = path.y[i] - path.cy[i];
  const double a = std::atan2(ay, ax), b = std::atan2(by, bx);
  double sweep = path.kind[i] == static_cast<std::uint8_t>(MoveKind::ArcCCW) ? wrap_2pi(b - a)
                                                                             : wrap_2pi(a - b);
  if (sweep == 0.0) sweep = kTwoPi;
  // hypot(s, 0) is exactly |s|: a flat arc's length is radius x sweep.
  return std::hypot(std::hypot(ax, ay) * sweep, path.z[i] - path.z[i - 1]);
}

}  // namespace

void Toolpath::add_arc(bool ccw, double px, double py, double pz, double ccx, double ccy) {
  if (!has_arcs()) {
    cx.assign(size(), kNoCentre);
    cy.assign(size(), kNoCentre);
  }
  kind.push_back(static_cast<std::uint8_t>(ccw ? MoveKind::ArcCCW : MoveKind::ArcCW));
  x.push_back(px);
  y.push_back(py);
  z.push_back(pz);
  cx.push_back(ccx);
  cy.push_back(ccy);
}

void Toolpath::append(const Toolpath& other) {
  if (other.has_arcs() && !has_arcs()) {
    cx.assign(size(), kNoCentre);
    cy.assign(size(), kNoCentre);
  }
  if (has_arcs()) {
    if (other.has_arcs()) {
      cx.insert(cx.end(), other.cx.begin(), other.cx.end());
      cy.insert(cy.end(), other.cy.begin(), other.cy.end());
    } else {
      cx.insert(cx.end(), other.size(), kNoCentre);
      cy.insert(cy.end(), other.size(), kNoCentre);
    }
  }
  kind.insert(kind.end(), other.kind.begin(), other.kind.end());
  x.insert(x.end(), other.x.begin(), other.x.end());
  y.insert(y.end(), other.y.begin(), other.y.end());
  z.insert(z.end(), other.z.begin(), other.z.end());
}

PathLengths measure(const Toolpath& path) {
  PathLengths m;
  bool fed_lift = false;  // the move before was a vertical feed up
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double dx = path.x[i] - path.x[i - 1], dy = path.y[i] - path.y[i - 1];
    const double dz = path.z[i] - path.z[i - 1];
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool up = dz > 0 && std::abs(dx) + std::abs(dy) < 1e-12;
    const bool was_fed_lift = fed_lift;
    fed_lift = false;
    switch (static_cast<MoveKind>(path.kind[i])) {
      case MoveKind::Feed:
        m.feed += len;
        ++m.cutting_moves;
        break;
      case MoveKind::ArcCW:
      case MoveKind::ArcCCW:
        m.feed += arc_length(path, i);
        ++m.cutting_moves;
        ++m.arcs;
        break;
      case MoveKind::Plunge:
        m.plunge += len;
        // A lift fed (near an overhang) counts as the retract; the rapid
        // that may follow it up is the same retract.
        if (up) {
          if (!was_fed_lift) ++m.retracts;
          fed_lift = true;
        }
        break;
      case MoveKind::Ramp:
        m.ramp += len;
        break;
      case MoveKind::Rapid:
        m.rapid += len;
        if (up && !was_fed_lift) ++m.retracts;
        break;
    }
  }
  return m;
}

PathTimes estimate_time(const Toolpath& path, double feed, double plunge, double rapid) {
  const PathLengths len = measure(path);
  PathTimes t;
  t.feed = 60.0 * len.feed / feed;
  t.plunge = 60.0 * len.plunge / plunge + 60.0 * len.ramp / feed;
  t.rapid = 60.0 * len.rapid / rapid;
  t.total = t.feed + t.plunge + t.rapid;
  return t;
}

}  // namespace isocam
