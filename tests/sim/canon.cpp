// The program as LinuxCNC's interpreter reads it: its canonical calls.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "gcode_sim.h"

namespace gsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

double dist(const Vec3& a, const Vec3& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                   (a.z - b.z) * (a.z - b.z));
}

[[noreturn]] void fail(int line, const std::string& what) {
  throw std::runtime_error("canonical line " + std::to_string(line) + ": " + what);
}

// The numbers between the parentheses of `call(` in `text`; commas or blanks
// separate them (USE_TOOL_LENGTH_OFFSET prints both).
std::vector<double> arguments(const std::string& text, std::size_t open, int line) {
  const std::size_t close = text.rfind(')');
  if (close == std::string::npos || close < open) fail(line, "no closing parenthesis");
  std::string inner = text.substr(open + 1, close - open - 1);
  for (char& c : inner)
    if (c == ',') c = ' ';
  std::istringstream in(inner);
  std::vector<double> values;
  std::string word;
  while (in >> word) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(word, &used));
      if (used != word.size()) fail(line, "not a number: " + word);
    } catch (const std::logic_error&) {
      fail(line, "not a number: " + word);
    }
  }
  return values;
}

enum class Plane { XY, XZ, YZ };

// (first, second, axis) of a plane as ARC_FEED orders them: XY -> (x, y, z),
// XZ -> (z, x, y), YZ -> (y, z, x).
Vec3 to_plane(Plane p, const Vec3& v) {
  switch (p) {
    case Plane::XY:
      return {v.x, v.y, v.z};
    case Plane::XZ:
      return {v.z, v.x, v.y};
    case Plane::YZ:
      return {v.y, v.z, v.x};
  }
  return v;
}
Vec3 from_plane(Plane p, const Vec3& f) {
  switch (p) {
    case Plane::XY:
      return {f.x, f.y, f.z};
    case Plane::XZ:
      return {f.y, f.z, f.x};
    case Plane::YZ:
      return {f.z, f.x, f.y};
  }
  return f;
}

bool nonzero(const std::vector<double>& v, std::size_t from, std::size_t to) {
  for (std::size_t i = from; i < to && i < v.size(); ++i)
    if (std::fabs(v[i]) > 1e-12) return true;
  return false;
}

struct Parser {
  Program prog;
  Vec3 pos;
  Plane plane = Plane::XY;
  double feed = 0.0;
  int line = 0;
  bool after_rapid = false;

  void straight(const std::vector<double>& a, bool rapid) {
    if (a.size() < 3) fail(line, "a straight move needs x, y, z");
    if (nonzero(a, 3, a.size())) fail(line, "rotary or extra axes are not supported");
    Move m;
    m.kind = rapid ? MoveKind::Rapid : MoveKind::Feed;
    m.from = pos;
    m.to = {a[0], a[1], a[2]};
    m.length = dist(m.from, m.to);
    m.feed_rate = rapid ? 0.0 : feed;
    // A plunge: the entry feed straight down after a rapid.
    m.plunge = !rapid && after_rapid && std::fabs(m.to.x - m.from.x) < 1e-9 &&
               std::fabs(m.to.y - m.from.y) < 1e-9 && m.to.z < m.from.z;
    after_rapid = rapid;
    const int index = static_cast<int>(prog.moves.size());
    if (rapid) {
      ++prog.rapids;
      prog.rapid_length += m.length;
    } else {
      if (!(feed > 0)) fail(line, "a feed move with no feed rate");
      ++prog.feeds;
      prog.feed_length += m.length;
      if (m.plunge) prog.plunge_length += m.length;
      prog.feed_time_min += m.length / feed;
    }
    prog.segments.push_back({m.from, m.to, index, rapid});
    prog.moves.push_back(m);
    pos = m.to;
  }

  // ARC_FEED(first_end, second_end, first_axis, second_axis, rotation,
  //          axis_end_point, a, b, c[, u, v, w]): centre (first_axis,
  // second_axis); rotation > 0 counterclockwise seen from the plane's
  // positive normal, |rotation| = 1 less than one full turn, each more adds
  // one; a helix moves the axis linearly with the angle.
  void arc(const std::vector<double>& a) {
    if (a.size() < 6) fail(line, "ARC_FEED needs at least 6 numbers");
    if (nonzero(a, 6, a.size())) fail(line, "rotary or extra axes are not supported");
    if (!(feed > 0)) fail(line, "an arc with no feed rate");
    const int turns = static_cast<int>(std::lround(a[4]));
    if (turns == 0 || std::fabs(a[4] - turns) > 1e-9) fail(line, "bad arc rotation");
    const Vec3 s = to_plane(plane, pos);
    const Vec3 e{a[0], a[1], a[5]};
    const double cx = a[2], cy = a[3];
    const double r0 = std::hypot(s.x - cx, s.y - cy), r1 = std::hypot(e.x - cx, e.y - cy);
    if (!(r0 > 1e-9) || !(r1 > 1e-9)) fail(line, "arc of zero radius");
    const double t0 = std::atan2(s.y - cy, s.x - cx), t1 = std::atan2(e.y - cy, e.x - cx);
    double sweep;
    if (turns > 0) {
      sweep = t1 - t0;
      while (sweep <= 1e-12) sweep += 2 * kPi;
      sweep += 2 * kPi * (turns - 1);
    } else {
      sweep = t1 - t0;
      while (sweep >= -1e-12) sweep -= 2 * kPi;
      sweep -= 2 * kPi * (-turns - 1);
    }
    const double rmax = std::max(r0, r1);
    // sagitta of a piece of angle t on radius R: R (1 - cos(t/2)).
    const double piece =
        prog.arc_sag >= rmax ? kPi / 2 : std::min(kPi / 8, 2 * std::acos(1 - prog.arc_sag / rmax));
    const int n = std::max(1, static_cast<int>(std::ceil(std::fabs(sweep) / piece)));
    Move m;
    m.kind = MoveKind::Arc;
    m.from = pos;
    m.to = from_plane(plane, e);
    m.feed_rate = feed;
    const int index = static_cast<int>(prog.moves.size());
    Vec3 prev = pos;
    double length = 0.0;
    for (int i = 1; i <= n; ++i) {
      const double f = double(i) / n;
      const double t = t0 + sweep * f, rr = r0 + (r1 - r0) * f;
      const Vec3 q = i == n ? m.to
                            : from_plane(plane, {cx + rr * std::cos(t), cy + rr * std::sin(t),
                                                 s.z + (e.z - s.z) * f});
      prog.segments.push_back({prev, q, index, false});
      length += dist(prev, q);
      prev = q;
    }
    // The exact length of the (helical) arc when its radius is constant.
    const double mean_r = 0.5 * (r0 + r1);
    m.length = std::max(length, std::hypot(mean_r * sweep, e.z - s.z));
    after_rapid = false;
    ++prog.arcs;
    prog.arc_length += m.length;
    prog.feed_time_min += m.length / feed;
    prog.moves.push_back(m);
    pos = m.to;
  }

  void take(const std::string& text) {
    auto call = [&](const char* name) -> std::size_t {
      const std::size_t at = text.find(name);
      if (at == std::string::npos) return std::string::npos;
      const std::size_t open = at + std::string(name).size();
      return open < text.size() && text[open] == '(' ? open : std::string::npos;
    };
    std::size_t open;
    if ((open = call("STRAIGHT_TRAVERSE")) != std::string::npos) {
      straight(arguments(text, open, line), true);
    } else if ((open = call("STRAIGHT_FEED")) != std::string::npos) {
      straight(arguments(text, open, line), false);
    } else if ((open = call("ARC_FEED")) != std::string::npos) {
      arc(arguments(text, open, line));
    } else if ((open = call("SET_FEED_RATE")) != std::string::npos) {
      const std::vector<double> a = arguments(text, open, line);
      if (a.size() != 1) fail(line, "SET_FEED_RATE needs one number");
      feed = a[0];
    } else if ((open = call("SELECT_PLANE")) != std::string::npos) {
      if (text.find("CANON_PLANE_XY", open) != std::string::npos)
        plane = Plane::XY;
      else if (text.find("CANON_PLANE_XZ", open) != std::string::npos)
        plane = Plane::XZ;
      else if (text.find("CANON_PLANE_YZ", open) != std::string::npos)
        plane = Plane::YZ;
      else
        fail(line, "plane not supported: " + text);
    } else if ((open = call("USE_LENGTH_UNITS")) != std::string::npos) {
      if (text.find("CANON_UNITS_MM", open) == std::string::npos)
        fail(line, "only millimetre programs are supported");
    } else if ((open = call("SET_G5X_OFFSET")) != std::string::npos) {
      if (nonzero(arguments(text, open, line), 1, 99)) fail(line, "work offsets are not supported");
    } else if ((open = call("SET_G92_OFFSET")) != std::string::npos) {
      if (nonzero(arguments(text, open, line), 0, 99)) fail(line, "G92 offsets are not supported");
    } else if ((open = call("SET_XY_ROTATION")) != std::string::npos) {
      if (nonzero(arguments(text, open, line), 0, 99)) fail(line, "XY rotation is not supported");
    } else if ((open = call("SET_FEED_MODE")) != std::string::npos) {
      const std::vector<double> a = arguments(text, open, line);
      if (a.size() == 2 && a[1] != 0) fail(line, "only units-per-minute feed is supported");
    } else if (call("NURBS_FEED") != std::string::npos ||
               call("STRAIGHT_PROBE") != std::string::npos ||
               call("RIGID_TAP") != std::string::npos) {
      fail(line, "move not supported: " + text);
    }
  }
};

}  // namespace

Program parse_canon(std::istream& in, double arc_sag, const Vec3* start) {
  if (!(arc_sag > 0)) throw std::runtime_error("arc sagitta must be > 0");
  Parser p;
  p.prog.arc_sag = arc_sag;
  std::string text;
  bool known = start != nullptr;
  if (known) p.pos = *start;
  while (std::getline(in, text)) {
    ++p.line;
    const std::size_t before = p.prog.segments.size();
    p.take(text);
    if (!known && p.prog.moves.size() == 1) {
      // Where the machine is before the first move is unknown (rs274 says
      // the origin): the first move is swept only at its end point.
      known = true;
      for (std::size_t i = before; i < p.prog.segments.size(); ++i)
        p.prog.segments[i].a = p.prog.segments[i].b = p.prog.moves[0].to;
    }
  }
  return std::move(p.prog);
}

std::string run_rs274(const std::string& rs274, const std::string& gcode_file,
                      const std::string& tool_table) {
  auto quote = [](const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  if (!std::ifstream(gcode_file)) throw std::runtime_error("cannot open G-code file " + gcode_file);
  if (!tool_table.empty() && !std::ifstream(tool_table))
    throw std::runtime_error("cannot open tool table " + tool_table);
  // rs274 writes the canonical calls to stdout and its errors to stderr.
  const char* tmpdir = std::getenv("TMPDIR");
  std::string err_path =
      std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/isocam_gcode_sim.XXXXXX";
  std::vector<char> err_name(err_path.begin(), err_path.end());
  err_name.push_back('\0');
  const int fd = mkstemp(err_name.data());
  if (fd < 0) throw std::runtime_error("cannot make a temporary file for rs274's messages");
  close(fd);
  std::string cmd = quote(rs274);
  if (!tool_table.empty()) cmd += " -t " + quote(tool_table);
  cmd += " -g " + quote(gcode_file) + " </dev/null 2>" + quote(err_name.data());
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + rs274);
  std::string out;
  char buf[65536];
  std::size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, got);
  const int status = pclose(pipe);
  std::string messages;
  {
    std::ifstream err(err_name.data());
    for (std::string text; std::getline(err, text);)
      if (text != "executing" && !text.empty()) messages += text + "\n";
  }
  std::remove(err_name.data());
  if (status != 0 || !messages.empty()) {
    throw std::runtime_error("rs274 failed on " + gcode_file + " (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "):\n" +
                             (messages.size() > 2000 ? messages.substr(0, 2000) : messages));
  }
  return out;
}

}  // namespace gsim
