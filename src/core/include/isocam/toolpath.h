// The Toolpath: flat arrays at the boundary (ENGINEERING.md, habit 2), the
// one path type of every operation (finishing, 5-axis, pocketing).
// Coordinates are tool-tip coordinates in mm (FreeCAD's convention: for a
// ball-end tool of radius r the tip is r below the ball centre).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace isocam {

// The values are the module's RAPID ... RAMP (src/python/path_arrays.cpp)
// and those of the uint8 `kind` arrays the operations return; they do not
// change.
enum class MoveKind : std::uint8_t {
  Rapid = 0,  // G0
  Feed = 1,   // G1 at horizontal feed (cutting and linking moves)
  // G1 at vertical feed: the fed part of an entry, straight down (or along
  // the normal), or of a lift (straight up, or first out of the pass beside
  // a wall: along the normal, or back along it and up)
  Plunge = 2,
  ArcCW = 3,   // G2 at horizontal feed, clockwise in the XY plane about (cx, cy)
  ArcCCW = 4,  // G3, counter-clockwise
  Ramp = 5,    // G1 at horizontal feed: the fed part of an entry, a ramp down along the pass
};

inline bool is_arc(std::uint8_t kind) {
  return kind == static_cast<std::uint8_t>(MoveKind::ArcCW) ||
         kind == static_cast<std::uint8_t>(MoveKind::ArcCCW);
}

// Move i goes from the end of move i-1 (the machine's position before the
// path, for i == 0) to (x[i], y[i], z[i]); an arc (ArcCW, ArcCCW) turns
// about (cx[i], cy[i]) in the XY plane, less than a full turn unless its end
// is its start (then one full turn); its z goes linearly from start to end.
//
// The arc centres cost nothing to a path without arcs: cx and cy stay empty
// until the first arc is added (add_arc, or append of a path that has
// arcs); from then on they hold one value per move, NaN for the moves that
// are not arcs (the earlier ones included). So either cx.size() == cy.size()
// == 0 (has_arcs() false) or == size(). Arcs are added with add_arc only.
struct Toolpath {
  std::vector<std::uint8_t> kind;
  std::vector<double> x, y, z;
  std::vector<double> cx, cy;  // arc centres, see above

  std::size_t size() const { return kind.size(); }
  bool empty() const { return kind.empty(); }
  bool has_arcs() const { return !cx.empty(); }
  // A straight move (Rapid, Feed, Plunge, Ramp).
  void add(MoveKind k, double px, double py, double pz) {
    kind.push_back(static_cast<std::uint8_t>(k));
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
    if (has_arcs()) {
      cx.push_back(kNoCentre);
      cy.push_back(kNoCentre);
    }
  }
  // An arc to (px, py, pz) about (ccx, ccy): G3 if ccw, else G2.
  void add_arc(bool ccw, double px, double py, double pz, double ccx, double ccy);
  void append(const Toolpath& other);

  static constexpr double kNoCentre = std::numeric_limits<double>::quiet_NaN();
};

// Lengths of the moves of each kind; the first move is not counted (its start
// is wherever the machine was). Arcs are measured along the arc (the helix
// if z changes), not along the chord.
struct PathLengths {
  double feed = 0.0;  // Feed moves and arcs
  double rapid = 0.0;
  double plunge = 0.0;
  double ramp = 0.0;
  int retracts = 0;  // lifts: moves straight up, rapid or fed (a fed lift and the rapid on top of
                     // it count once)
  int arcs = 0;      // ArcCW and ArcCCW moves
  int cutting_moves = 0;  // Feed moves and arcs
};
PathLengths measure(const Toolpath& path);

// The lengths every operation reports, into its metrics (IsoMetrics,
// FiveAxisMetrics, PocketMetrics): cutting = feed moves and arcs, plunge =
// plunges and ramps (the fed entries).
template <class Metrics>
void report_lengths(const PathLengths& len, Metrics& m) {
  m.cutting_length = len.feed;
  m.rapid_length = len.rapid;
  m.plunge_length = len.plunge + len.ramp;
  m.retracts = len.retracts;
}

// Time estimate (s) at constant rates (mm/min), no acceleration: rapids at
// `rapid`, feed moves, arcs and ramps at `feed`, plunges at `plunge`; the
// first move is not counted (as in measure()). `feed` is the feed moves' and
// arcs' share (the cutting time; entries are not in it).
struct PathTimes {
  double total = 0.0;
  double feed = 0.0;
  double plunge = 0.0;  // plunges and ramps: the fed entries
  double rapid = 0.0;
};
PathTimes estimate_time(const Toolpath& path, double feed, double plunge, double rapid);

}  // namespace isocam
