// A guard in front of BRepTools::Read (issue 15). OpenCASCADE's reader
// trusts the counts in the text: a header announcing 10^9 surfaces or a
// B-spline with 10^9 poles makes it allocate and loop for that many before
// it notices the text has ended, and it accepts NaN, 1e308 and negative
// weights, which later computations turn into hangs or garbage. This pass
// walks the geometry sections of the format (OpenCASCADE's BRepTools_ShapeSet,
// GeomTools_*Set: Locations, Curve2ds, Curves, Polygon3D,
// PolygonOnTriangulations, Surfaces, Triangulations, TShapes) token by
// token without allocating anything of the announced size, and throws
// InvalidArgument("brep: ... at byte N") where the text cannot be what it
// says. It checks:
//   - every count is an integer no larger than the tokens left can hold;
//   - every section and entry is complete (a truncated text is caught at
//     the entry where it ends);
//   - every real of the geometry is finite and at most kMaxMagnitude in
//     absolute value; no token anywhere is NaN or infinite;
//   - rational weights are positive and within kMaxWeightRatio of each
//     other in one curve or surface; degrees are at most 25 (OpenCASCADE's
//     limit).
// The shapes section (TShapes) is only bounded by its count: its entries
// refer to the geometry by index, which OpenCASCADE checks itself.
#include "brep_guard.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "isocam/errors.h"

namespace isocam::detail {
namespace {

constexpr double kMaxMagnitude = 1e100;  // Precision::Infinite() is 2e100: above it is not geometry
constexpr double kMaxWeightRatio = 1e12;
constexpr long kMaxDegree = 25;

struct Token {
  std::size_t offset, length;
};

class Guard {
 public:
  explicit Guard(const std::string& text) : text_(text) { tokenize(); }

  void run() {
    for (std::size_t i = 0; i < tokens_.size(); ++i) reject_non_finite_word(i);
    while (pos_ < tokens_.size()) {
      const std::string w = word(pos_);
      ++pos_;
      if (w == "Locations")
        section(w, [this] { location(); });
      else if (w == "Curve2ds")
        section(w, [this] { curve(2); });
      else if (w == "Curves")
        section(w, [this] { curve(3); });
      else if (w == "Polygon3D")
        section(w, [this] { polygon3d(); });
      else if (w == "PolygonOnTriangulations")
        section(w, [this] { polygon_on_triangulation(); });
      else if (w == "Surfaces")
        section(w, [this] { surface(); });
      else if (w == "Triangulations")
        section(w, [this] { triangulation(); });
      else if (w == "TShapes") {
        // Each shape takes several tokens (type, flags, sub-shape list end).
        const long n = count(w, 3);
        (void)n;
        return;
      }
    }
  }

 private:
  void tokenize() {
    std::size_t i = 0;
    const std::size_t n = text_.size();
    while (i < n) {
      while (i < n && std::isspace(static_cast<unsigned char>(text_[i]))) ++i;
      if (i >= n) break;
      const std::size_t s = i;
      while (i < n && !std::isspace(static_cast<unsigned char>(text_[i]))) ++i;
      tokens_.push_back({s, i - s});
    }
  }

  std::string word(std::size_t i) const {
    return text_.substr(tokens_[i].offset, tokens_[i].length);
  }
  std::size_t offset_of(std::size_t i) const {
    return i < tokens_.size() ? tokens_[i].offset : text_.size();
  }
  [[noreturn]] void fail(std::size_t token, const std::string& what) const {
    throw InvalidArgument("brep: " + what + " at byte " + std::to_string(offset_of(token)));
  }
  std::size_t left() const { return tokens_.size() - pos_; }

  void reject_non_finite_word(std::size_t i) const {
    std::string w = word(i);
    std::transform(w.begin(), w.end(), w.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::size_t k = w.find_first_not_of("+-");
    if (k != std::string::npos && (w.compare(k, 3, "nan") == 0 || w.compare(k, 3, "inf") == 0))
      fail(i, "a number is not finite ('" + word(i) + "')");
  }

  // The next token as a non-negative integer.
  long integer(const char* what) {
    if (pos_ >= tokens_.size()) fail(pos_, std::string("the text ends where ") + what + " is due");
    const std::string w = word(pos_);
    if (w.empty() || w.size() > 12 ||
        !std::all_of(w.begin(), w.end(), [](unsigned char c) { return std::isdigit(c); }))
      fail(pos_, std::string(what) + " '" + w + "' is not a non-negative integer");
    ++pos_;
    return std::stol(w);
  }

  double real(const char* what) {
    if (pos_ >= tokens_.size()) fail(pos_, std::string("the text ends where ") + what + " is due");
    const std::string w = word(pos_);
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end != '\0')
      fail(pos_, std::string(what) + " '" + w + "' is not a number");
    if (!std::isfinite(v) || std::abs(v) > kMaxMagnitude)
      fail(pos_, std::string(what) + " " + w + " is out of range (|x| <= 1e100)");
    ++pos_;
    return v;
  }

  void reals(long n, const char* what) {
    for (long k = 0; k < n; ++k) real(what);
  }

  // A count of items each taking at least `tokens_each` tokens.
  long count(const std::string& what, long tokens_each) {
    const std::size_t at = pos_;
    const long n = integer(what.c_str());
    if (static_cast<double>(n) * static_cast<double>(tokens_each) > static_cast<double>(left()))
      fail(at, what + " count " + std::to_string(n) + " exceeds what the rest of the text holds (" +
                   std::to_string(left()) + " tokens)");
    return n;
  }

  template <class F>
  void section(const std::string& name, F entry) {
    const long n = count(name, 1);
    for (long k = 0; k < n; ++k) entry();
  }

  void weights_ok(const std::vector<double>& w, std::size_t at) const {
    if (w.empty()) return;
    double lo = 1e300, hi = 0.0;
    for (double x : w) {
      if (!(x > 0.0)) fail(at, "a rational weight is not positive (" + std::to_string(x) + ")");
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    if (hi / lo > kMaxWeightRatio)
      fail(at, "rational weights span more than 1e12 (" + std::to_string(lo) + " to " +
                   std::to_string(hi) + ")");
  }

  long degree() {
    const std::size_t at = pos_;
    const long d = integer("a degree");
    if (d < 1 || d > kMaxDegree)
      fail(at, "degree " + std::to_string(d) + " is out of range (1 to 25)");
    return d;
  }

  long flag(const char* what) {
    const std::size_t at = pos_;
    const long f = integer(what);
    if (f > 1) fail(at, std::string(what) + " must be 0 or 1");
    return f;
  }

  // dim reals a pole, plus a weight when rational.
  void poles(long n, int dim, bool rational) {
    const std::size_t at = pos_;
    std::vector<double> w;
    for (long k = 0; k < n; ++k) {
      reals(dim, "a pole coordinate");
      if (rational) w.push_back(real("a weight"));
    }
    weights_ok(w, at);
  }

  void knots(long n) {
    for (long k = 0; k < n; ++k) {
      real("a knot");
      const std::size_t at = pos_;
      const long m = integer("a knot multiplicity");
      if (m < 1 || m > kMaxDegree + 1) fail(at, "knot multiplicity out of range");
    }
  }

  void location() {
    const std::size_t at = pos_;
    const long kind = integer("a location type");
    if (kind == 1) {
      reals(12, "a matrix entry");
    } else if (kind == 2) {
      // Pairs (location index, power) ending with 0.
      while (true) {
        const long l = integer("a location index");
        if (l == 0) break;
        if (pos_ >= tokens_.size()) fail(pos_, "the text ends in a location");
        ++pos_;  // the power, a signed integer
      }
    } else {
      fail(at, "unknown location type " + std::to_string(kind));
    }
  }

  void curve(int dim) {
    const std::size_t at = pos_;
    const long kind = integer("a curve type");
    const long frame = dim == 3 ? 12 : 6;  // P, N, X, Y (3D) or P, X, Y (2D)
    switch (kind) {
      case 1:
        reals(2 * dim, "a line coordinate");
        break;
      case 2:
        reals(frame + 1, "a circle coordinate");
        break;
      case 3:
        reals(frame + 2, "an ellipse coordinate");
        break;
      case 4:
        reals(frame + 1, "a parabola coordinate");
        break;
      case 5:
        reals(frame + 2, "a hyperbola coordinate");
        break;
      case 6: {
        const bool rational = flag("a rational flag");
        const long d = degree();
        poles(d + 1, dim, rational);
        break;
      }
      case 7: {
        const bool rational = flag("a rational flag");
        flag("a periodic flag");
        degree();
        const long np = count("B-spline pole", dim);
        const long nk = count("B-spline knot", 2);
        poles(np, dim, rational);
        knots(nk);
        break;
      }
      case 8:
        reals(2, "a trim parameter");
        curve(dim);
        break;
      case 9:
        real("an offset");
        if (dim == 3) reals(3, "an offset direction");
        curve(dim);
        break;
      default:
        fail(at, "unknown curve type " + std::to_string(kind));
    }
  }

  void surface() {
    const std::size_t at = pos_;
    const long kind = integer("a surface type");
    switch (kind) {
      case 1:
        reals(12, "a plane coordinate");
        break;
      case 2:
        reals(13, "a cylinder coordinate");
        break;
      case 3:
        reals(14, "a cone coordinate");
        break;
      case 4:
        reals(13, "a sphere coordinate");
        break;
      case 5:
        reals(14, "a torus coordinate");
        break;
      case 6:
        reals(3, "an extrusion direction");
        curve(3);
        break;
      case 7:
        reals(6, "a revolution axis");
        curve(3);
        break;
      case 8: {
        const bool ur = flag("a rational flag");
        const bool vr = flag("a rational flag");
        const long du = degree(), dv = degree();
        poles((du + 1) * (dv + 1), 3, ur || vr);
        break;
      }
      case 9: {
        const bool ur = flag("a rational flag");
        const bool vr = flag("a rational flag");
        flag("a periodic flag");
        flag("a periodic flag");
        degree();
        degree();
        const std::size_t pat = pos_;
        const long nu = integer("a pole count"), nv = integer("a pole count");
        if (static_cast<double>(nu) * static_cast<double>(nv) * 3.0 > static_cast<double>(left()))
          fail(pat, "B-spline surface of " + std::to_string(nu) + " x " + std::to_string(nv) +
                        " poles exceeds what the rest of the text holds");
        const long nku = count("B-spline knot", 2), nkv = count("B-spline knot", 2);
        poles(nu * nv, 3, ur || vr);
        knots(nku);
        knots(nkv);
        break;
      }
      case 10:
        reals(4, "a trim parameter");
        surface();
        break;
      case 11:
        real("an offset");
        surface();
        break;
      default:
        fail(at, "unknown surface type " + std::to_string(kind));
    }
  }

  void polygon3d() {
    const long n = count("polygon node", 3);
    const bool params = flag("a parameters flag");
    real("a deflection");
    reals(3 * n, "a node coordinate");
    if (params) reals(n, "a node parameter");
  }

  void polygon_on_triangulation() {
    const long n = count("polygon node", 1);
    for (long k = 0; k < n; ++k) integer("a node index");
    if (pos_ < tokens_.size() && word(pos_) == "p") ++pos_;
    real("a deflection");
    const bool params = flag("a parameters flag");
    if (params) reals(n, "a node parameter");
  }

  void triangulation() {
    const long nodes = count("triangulation node", 3);
    const long tris = count("triangle", 3);
    const bool uv = flag("a UV flag");
    // Version 3 adds a normals flag before the deflection: an integer 0/1
    // where version 1 has the deflection, a real.
    bool normals = false;
    if (version_ >= 3) normals = flag("a normals flag");
    real("a deflection");
    reals(3 * nodes, "a node coordinate");
    if (uv) reals(2 * nodes, "a UV coordinate");
    for (long k = 0; k < 3 * tris; ++k) integer("a triangle node index");
    if (normals) reals(3 * nodes, "a normal coordinate");
  }

 public:
  void find_version() {
    const std::size_t k = text_.find("CASCADE Topology V");
    if (k != std::string::npos && k + 18 < text_.size() &&
        std::isdigit(static_cast<unsigned char>(text_[k + 18])))
      version_ = text_[k + 18] - '0';
  }

 private:
  const std::string& text_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  int version_ = 1;
};

}  // namespace

void check_brep_text(const std::string& text) {
  Guard g(text);
  g.find_version();
  g.run();
}

}  // namespace isocam::detail
