#include "speech/dtw.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rostro::speech {
namespace {

// Below this many cells the whole matrix is searched.
constexpr long kFullSearchCells = 250000;

// Columns [lo, hi] of b that row i of a may match.
struct Band {
  std::vector<int> lo, hi;
};

// Symmetric DTW (a diagonal step counts its distance twice, so every path's total weight
// is a.frames + b.frames) restricted to `band`.
WarpPath search(const Features& a, const Features& b, const Band& band, double penalty) {
  const int n = a.frames;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> offset(n + 1, 0);
  for (int i = 0; i < n; ++i) offset[i + 1] = offset[i] + (band.hi[i] - band.lo[i] + 1);
  std::vector<double> cost(offset[n], kInf);
  std::vector<unsigned char> move(offset[n], 0);  // 0 diagonal, 1 from i-1, 2 from j-1
  auto at = [&](int i, int j) -> double {
    if (i < 0 || j < band.lo[i] || j > band.hi[i]) return kInf;
    return cost[offset[i] + (j - band.lo[i])];
  };
  for (int i = 0; i < n; ++i)
    for (int j = band.lo[i]; j <= band.hi[i]; ++j) {
      const double d = frame_distance(a, i, b, j);
      const std::size_t k = offset[i] + (j - band.lo[i]);
      if (i == 0 && j == 0) {
        cost[k] = 2 * d;
        continue;
      }
      const double diagonal = at(i - 1, j - 1) + 2 * d;
      const double down = at(i - 1, j) + d + penalty;
      const double across = j > band.lo[i] ? cost[k - 1] + d + penalty : kInf;
      if (diagonal <= down && diagonal <= across) {
        cost[k] = diagonal;
      } else if (down <= across) {
        cost[k] = down;
        move[k] = 1;
      } else {
        cost[k] = across;
        move[k] = 2;
      }
    }
  WarpPath path;
  int i = n - 1, j = b.frames - 1;
  path.mean_cost = at(i, j) / (a.frames + b.frames);
  if (!std::isfinite(path.mean_cost)) throw std::logic_error("dtw: band has no path");
  while (true) {
    path.steps.emplace_back(i, j);
    if (i == 0 && j == 0) break;
    const unsigned char m = move[offset[i] + (j - band.lo[i])];
    if (m == 0) {
      --i;
      --j;
    } else if (m == 1) {
      --i;
    } else {
      --j;
    }
  }
  std::reverse(path.steps.begin(), path.steps.end());
  return path;
}

Features halve(const Features& f) {
  Features h;
  h.dims = f.dims;
  h.hop_s = 2 * f.hop_s;
  h.frames = (f.frames + 1) / 2;
  h.values.assign(static_cast<std::size_t>(h.frames) * h.dims, 0.0f);
  for (int i = 0; i < h.frames; ++i) {
    const int a = 2 * i, b = std::min(2 * i + 1, f.frames - 1);
    for (int d = 0; d < f.dims; ++d) h.row(i)[d] = 0.5f * (f.row(a)[d] + f.row(b)[d]);
  }
  return h;
}

// The cells of `coarse` at double resolution, widened by `radius` each way.
Band project(const WarpPath& coarse, int n, int m, int radius) {
  Band band;
  band.lo.assign(n, m);
  band.hi.assign(n, -1);
  for (const auto& [ci, cj] : coarse.steps)
    for (int i = 2 * ci; i <= std::min(n - 1, 2 * ci + 1); ++i) {
      band.lo[i] = std::min(band.lo[i], 2 * cj);
      band.hi[i] = std::max(band.hi[i], std::min(m - 1, 2 * cj + 1));
    }
  Band wide = band;
  for (int i = 0; i < n; ++i)
    for (int k = std::max(0, i - radius); k <= std::min(n - 1, i + radius); ++k) {
      wide.lo[i] = std::min(wide.lo[i], band.lo[k]);
      wide.hi[i] = std::max(wide.hi[i], band.hi[k]);
    }
  for (int i = 0; i < n; ++i) {
    wide.lo[i] = std::max(0, wide.lo[i] - radius);
    wide.hi[i] = std::min(m - 1, wide.hi[i] + radius);
  }
  wide.lo[0] = 0;
  wide.hi[n - 1] = m - 1;
  return wide;
}

}  // namespace

float frame_distance(const Features& a, int i, const Features& b, int j) {
  const float* x = a.row(i);
  const float* y = b.row(j);
  float sum = 0.0f;
  for (int d = 0; d < a.dims; ++d) sum += (x[d] - y[d]) * (x[d] - y[d]);
  return std::sqrt(sum);
}

WarpPath warp(const Features& a, const Features& b, const WarpOptions& options) {
  if (a.frames < 1 || b.frames < 1 || a.dims != b.dims)
    throw std::invalid_argument("dtw: empty sequences or different feature sizes");
  if (static_cast<long>(a.frames) * b.frames <= kFullSearchCells || a.frames < 4 || b.frames < 4) {
    Band all;
    all.lo.assign(a.frames, 0);
    all.hi.assign(a.frames, b.frames - 1);
    return search(a, b, all, options.step_penalty);
  }
  const WarpPath coarse = warp(halve(a), halve(b), options);
  return search(a, b, project(coarse, a.frames, b.frames, options.radius), options.step_penalty);
}

}  // namespace rostro::speech
