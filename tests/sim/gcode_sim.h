// An independent G-code simulator for ball-end finishing (issue 10, habit 15).
//
// It shares nothing with the IsoCAM core: it reads the posted program as the
// canonical moves of LinuxCNC's interpreter (rs274 -g), sweeps a ball of
// radius r along them and measures, on points sampled densely on the design
// surface (inside each face's wires), how far the swept ball stays from it:
//
//   d(p) = min over all swept centre segments of |p - c| - r
//
// d > 0 is material left above the design, d < 0 an overcut. Only OpenCASCADE
// is used, for reading the B-rep and evaluating its faces.
#pragma once

#include <TopoDS_Shape.hxx>
#include <array>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace gsim {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// -- the program ------------------------------------------------------------

enum class MoveKind { Rapid, Feed, Arc };

struct Move {
  MoveKind kind = MoveKind::Feed;
  Vec3 from, to;           // tool tip, program coordinates (mm)
  double length = 0.0;     // along the move (mm)
  double feed_rate = 0.0;  // mm/min in force (feeds and arcs)
  bool plunge = false;     // an entry: a feed straight down right after a rapid
};

// A straight piece of the tool-tip path; arcs are split into pieces whose
// sagitta is below Program::arc_sag.
struct Segment {
  Vec3 a, b;
  int move = 0;  // index into Program::moves
  bool rapid = false;
};

struct Program {
  std::vector<Move> moves;
  std::vector<Segment> segments;
  double arc_sag = 0.0;
  int rapids = 0, feeds = 0, arcs = 0;
  double rapid_length = 0.0, feed_length = 0.0, plunge_length = 0.0, arc_length = 0.0;
  double feed_time_min = 0.0;  // sum of length / feed rate over feeds and arcs
};

// Parses the canonical calls printed by `rs274 -g` (STRAIGHT_TRAVERSE,
// STRAIGHT_FEED, ARC_FEED with the plane of SELECT_PLANE, SET_FEED_RATE).
// The machine starts at `start`; without it the start is unknown (rs274
// assumes the origin) and the first move is swept at its end point only. Throws
// std::runtime_error naming the line on anything it cannot take: inch units,
// work offsets or a rotation, inverse-time feed, a malformed call.
Program parse_canon(std::istream& in, double arc_sag, const Vec3* start = nullptr);

// Runs `rs274 [-t tool_table] -g gcode_file` and returns its standard output.
// Throws std::runtime_error when it cannot run or reports an error.
std::string run_rs274(const std::string& rs274, const std::string& gcode_file,
                      const std::string& tool_table);

// -- the design surface -------------------------------------------------------

struct Sample {
  Vec3 p;
  std::array<float, 3> n{};  // unit normal away from the material (0 if undefined)
  float area = 0.0f;         // the part of the face's area this point stands for (mm^2)
  int face = 0;              // 1-based, FreeCAD's FaceN
  bool picked = false;
  bool open = false;  // its face bounds no solid of the shape: either side may be cut
};

// The faces of `shape` as FreeCAD numbers them (FaceN = N-th entry of
// TopExp::MapShapes(shape, TopAbs_FACE)).
std::vector<TopoDS_Shape> faces_of(const TopoDS_Shape& shape);

// Points on every face, no farther than about `spacing` apart (mm) in 3D,
// kept where the face's wires classify them inside (or on).
std::vector<Sample> sample_faces(const TopoDS_Shape& shape, const std::vector<int>& picked,
                                 double spacing, int threads);

// -- the measurement ------------------------------------------------------------

struct Options {
  double ball_radius = 3.0;
  double rapid_rate = 5000.0;  // mm/min, for the machine time estimate (no acceleration)
  double max_residual = 0.5;   // d is measured up to this; above it counts as "not covered"
  double reach_margin = 0.0;   // reachable: a ball of r + margin touching p is clear
  double reach_tol = 1e-4;     // ... i.e. no model point closer than r + margin - tol
  // ... and so is that ball lifted straight up (a 3-axis tool comes from
  // above): no model point that close to the vertical ray up from its centre.
  // A point of an open face is reachable if it is so from either side.
  bool from_above = true;
  double scallop = -1.0;  // if > 0: coverage = reachable fraction with d <= scallop
  double cell = 0.5;      // fine cell of the sample grid (mm)
  int threads = 2;
};

struct Extreme {
  double value = 0.0;  // mm, >= 0
  Vec3 at;
  int face = 0;  // 0: none
  int move = -1;
};

struct Result {
  std::size_t samples = 0, picked_samples = 0, reachable_samples = 0, uncovered_samples = 0;
  std::size_t overcut_samples = 0;  // samples with d < -1e-4
  double picked_area = 0.0, reachable_area = 0.0, covered_area = 0.0;
  // rapid_overcut: the deepest cut of a rapid where it comes nearer to the
  // design than every feed move does (without an order in time, the ball at
  // a retract's start is the feed's own cut there).
  Extreme left, overcut, rapid_overcut;
  std::vector<double> residual;  // per sample (capped at max_residual)
  std::vector<unsigned char> reachable;
};

Result measure(const std::vector<Sample>& samples, const Program& program, const Options& o);

// A residual map of the picked faces seen from +z: per x-y cell of `step`,
// the deepest overcut if there is one, else the most material left on a
// reachable point; cells with only unreachable points are written as nan.
// Lines "x y value" after a header line.
void write_map(std::ostream& out, const std::vector<Sample>& samples, const Result& r, double step);

void write_json(std::ostream& out, const std::vector<Sample>& samples, const Program& program,
                const Options& o, const Result& r, double spacing, const std::vector<int>& picked,
                int face_count);

}  // namespace gsim
