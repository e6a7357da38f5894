#include "isocam/toolpath.h"

#include <cmath>

namespace isocam {

void Toolpath::append(const Toolpath& other) {
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
      default:
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
