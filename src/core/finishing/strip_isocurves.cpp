// Adaptive isocurves spaced by a strip width (finishing/strip_isocurves.h).
#include "finishing/strip_isocurves.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace isocam {
namespace {

using Range = std::pair<std::size_t, std::size_t>;  // samples a..b, both included

// The u samples: each u-span in 8 parts, then intervals longer than `step`
// in space at any of 17 levels of v cut into equal parts, until none is.
std::vector<double> sample_us(const PatchGrid& g, double step) {
  const std::vector<double>& br = g.ubreaks();
  std::vector<double> us;
  for (std::size_t i = 0; i + 1 < br.size(); ++i)
    for (int k = 0; k < 8; ++k) us.push_back(br[i] + (br[i + 1] - br[i]) * k / 8.0);
  us.push_back(br.back());
  constexpr int kLevels = 17;
  const double tiny = 1e-12 * (g.umax() - g.umin());
  for (int pass = 0; pass < 30; ++pass) {
    std::vector<double> out{us.front()};
    bool split = false;
    for (std::size_t i = 1; i < us.size(); ++i) {
      const double a = us[i - 1], b = us[i];
      double d = 0.0;
      for (int l = 0; l < kLevels; ++l) {
        const double v = g.vmin() + (g.vmax() - g.vmin()) * l / (kLevels - 1);
        d = std::max(d, g.eval(a, v).Distance(g.eval(b, v)));
      }
      if (d > step && b - a > tiny && us.size() < 1000000) {
        const int m = std::min(1000, static_cast<int>(std::ceil(d / step)));
        for (int q = 1; q < m; ++q) out.push_back(a + (b - a) * q / m);
        split = true;
      }
      out.push_back(b);
    }
    us = std::move(out);
    if (!split) break;
  }
  return us;
}

class Builder {
 public:
  Builder(const PatchGrid& g, const StripWidth& width, const IsoStripSettings& s,
          const std::function<void(double)>& progress)
      : g_(g), width_(width), s_(s), progress_(progress), us_(sample_us(g, s.sample_max)) {}

  IsoStripPaths build() {
    const Range all{0, us_.size() - 1};
    levels_[g_.vmin()].push_back(all);
    levels_[g_.vmax()].push_back(all);
    points_ = 2 * us_.size();
    split(g_.vmin(), g_.vmax(), {all});
    progress_(1.0);
    return collect();
  }

 private:
  struct Level {
    std::vector<gp_Pnt> p;
    std::vector<double> w;  // < 0: not computed yet
    std::vector<char> has_p;
  };

  Level& level(double v) {
    auto it = cache_.find(v);
    if (it == cache_.end()) {
      Level l;
      l.p.resize(us_.size());
      l.w.assign(us_.size(), -1.0);
      l.has_p.assign(us_.size(), 0);
      it = cache_.emplace(v, std::move(l)).first;
    }
    return it->second;
  }
  const gp_Pnt& point(double v, std::size_t i) {
    Level& l = level(v);
    if (!l.has_p[i]) {
      l.p[i] = g_.eval(us_[i], v);
      l.has_p[i] = 1;
    }
    return l.p[i];
  }
  // The strip width at (u_i, v) with the feed along the isocurve; no limit
  // where that direction is degenerate (a pole).
  double width_at(double v, std::size_t i) {
    Level& l = level(v);
    if (l.w[i] < 0) {
      const StripFrame f = make_frame(g_, {us_[i], v}, g_.d1(us_[i], v).su);
      l.w[i] = f.feed.SquareMagnitude() > 0.5 ? width_(f) : std::numeric_limits<double>::max();
    }
    return l.w[i];
  }
  bool pair_ok(double va, double vb, std::size_t i) {
    const double d = point(va, i).Distance(point(vb, i));
    return d <= width_at(va, i) && d <= width_at(vb, i) && d <= width_at(0.5 * (va + vb), i);
  }

  // Algorithm 1 between the curves va < vb over `ranges` of samples
  // (depth first, the lower pair first: va never decreases).
  void split(double va, double vb, const std::vector<Range>& ranges) {
    progress_((va - g_.vmin()) / (g_.vmax() - g_.vmin()));
    std::vector<Range> bad;
    for (const Range& r : ranges) {
      for (std::size_t i = r.first; i <= r.second; ++i) {
        if (pair_ok(va, vb, i)) continue;
        std::size_t j = i;
        while (j < r.second && !pair_ok(va, vb, j + 1)) ++j;
        const Range grown{i > r.first ? i - 1 : i, j < r.second ? j + 1 : j};
        if (!bad.empty() && grown.first <= bad.back().second)
          bad.back().second = std::max(bad.back().second, grown.second);
        else
          bad.push_back(grown);
        i = j;
      }
    }
    if (bad.empty()) return;
    if (vb - va < s_.min_dv * (g_.vmax() - g_.vmin())) {
      ++min_hits_;
      return;
    }
    std::size_t added = 0;
    for (const Range& r : bad) added += r.second - r.first + 1;
    if (points_ + added > s_.max_points) {
      capped_ = true;
      return;
    }
    points_ += added;
    const double vm = 0.5 * (va + vb);
    std::vector<Range>& at = levels_[vm];
    at.insert(at.end(), bad.begin(), bad.end());
    split(va, vm, bad);
    split(vm, vb, bad);
  }

  IsoStripPaths collect() {
    IsoStripPaths out;
    out.min_hits = min_hits_;
    out.capped = capped_;
    // The next curve above each sample, from the top level down.
    const double none = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> above(us_.size(), none);
    std::vector<std::vector<std::vector<double>>> next_v;
    for (auto it = levels_.rbegin(); it != levels_.rend(); ++it) {
      const double v = it->first;
      std::vector<Range> ranges = it->second;
      std::sort(ranges.begin(), ranges.end());
      std::vector<FrontPiece> path;
      std::vector<std::vector<ParamPt>> next;
      for (const Range& r : ranges) {
        FrontPiece piece;
        std::vector<ParamPt> partner;
        for (std::size_t i = r.first; i <= r.second; ++i) {
          FrontPoint x;
          x.uv = {us_[i], v};
          x.p = point(v, i);
          x.has_next = !std::isnan(above[i]);
          x.spacing = width_at(v, i);
          piece.push_back(x);
          partner.push_back({us_[i], x.has_next ? above[i] : v});
        }
        path.push_back(std::move(piece));
        next.push_back(std::move(partner));
      }
      for (const Range& r : ranges)
        for (std::size_t i = r.first; i <= r.second; ++i) above[i] = v;
      out.paths.push_back(std::move(path));
      out.next.push_back(std::move(next));
    }
    std::reverse(out.paths.begin(), out.paths.end());
    std::reverse(out.next.begin(), out.next.end());
    return out;
  }

  const PatchGrid& g_;
  const StripWidth& width_;
  const IsoStripSettings& s_;
  const std::function<void(double)>& progress_;
  std::vector<double> us_;
  std::map<double, Level> cache_;
  std::map<double, std::vector<Range>> levels_;
  std::size_t points_ = 0;
  int min_hits_ = 0;
  bool capped_ = false;
};

}  // namespace

IsoStripPaths strip_isocurves(const PatchGrid& g, const StripWidth& width,
                              const IsoStripSettings& s,
                              const std::function<void(double)>& progress) {
  return Builder(g, width, s, progress).build();
}

}  // namespace isocam
