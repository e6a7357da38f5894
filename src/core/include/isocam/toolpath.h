// The Toolpath: flat arrays at the boundary (ENGINEERING.md, habit 2).
// Coordinates are tool-tip coordinates in mm (FreeCAD's convention: for a
// ball-end tool of radius r the tip is r below the ball centre).
#pragma once

#include <cstdint>
#include <vector>

namespace isocam {

enum class MoveKind : std::uint8_t {
  Rapid = 0,   // G0
  Feed = 1,    // G1 at horizontal feed (cutting and linking moves)
  Plunge = 2,  // G1 at vertical feed: the fed part of an entry, straight down (or along the normal)
  // 3 and 4 are the pocketing's arcs (isocam/pocketing.h).
  Ramp = 5,  // G1 at horizontal feed: the fed part of an entry, a ramp down along the pass
};

// Move i goes from the end of move i-1 (the machine's position before the
// path, for i == 0) to (x[i], y[i], z[i]).
struct Toolpath {
  std::vector<std::uint8_t> kind;
  std::vector<double> x, y, z;

  std::size_t size() const { return kind.size(); }
  bool empty() const { return kind.empty(); }
  void add(MoveKind k, double px, double py, double pz) {
    kind.push_back(static_cast<std::uint8_t>(k));
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
  }
  void append(const Toolpath& other);
};

// Lengths of the moves of each kind; the first move is not counted (its start
// is wherever the machine was).
struct PathLengths {
  double feed = 0.0;
  double rapid = 0.0;
  double plunge = 0.0;
  double ramp = 0.0;
  int retracts = 0;  // lifts: moves straight up, rapid or fed (a fed lift and the rapid on top of
                     // it count once)
};
PathLengths measure(const Toolpath& path);

// Time estimate (s) at constant rates (mm/min), no acceleration: rapids at
// `rapid`, feed moves and ramps at `feed`, plunges at `plunge`; the first
// move is not counted (as in measure()). `feed` is the feed moves' share
// (the cutting time; entries are not in it).
struct PathTimes {
  double total = 0.0;
  double feed = 0.0;
  double plunge = 0.0;  // plunges and ramps: the fed entries
  double rapid = 0.0;
};
PathTimes estimate_time(const Toolpath& path, double feed, double plunge, double rapid);

}  // namespace isocam
