#include "tracking/identify.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/calib3d.hpp>

#include "facecore/error.hpp"
#include "tracking/affine2d.hpp"
#include "tracking/tracks_csv.hpp"

namespace rostro::tracking {
namespace {

cv::Matx23d similarity_from_clouds(const std::vector<cv::Point2d>& from,
                                   const std::vector<cv::Point2d>& to) {
  auto centre_and_spread = [](const std::vector<cv::Point2d>& pts) {
    cv::Point2d c(0, 0);
    for (const auto& p : pts) c += p;
    c *= 1.0 / static_cast<double>(pts.size());
    double s = 0;
    for (const auto& p : pts) s += (p - c).dot(p - c);
    return std::pair{c, std::sqrt(s / static_cast<double>(pts.size()))};
  };
  auto [cf, sf] = centre_and_spread(from);
  auto [ct, st] = centre_and_spread(to);
  const double k = sf > 0 ? st / sf : 1;
  return {k, 0, ct.x - k * cf.x, 0, k, ct.y - k * cf.y};
}

constexpr double kNoPair = 1e12;

// The column given to each row that minimises the total cost (rows <= columns): the
// Hungarian method with potentials, O(rows^2 x columns). -1 for no row (never, when every row
// has a finite column).
std::vector<int> min_cost_assignment(const std::vector<std::vector<double>>& cost) {
  const size_t n = cost.size();
  if (n == 0) return {};
  const size_t m = cost[0].size();
  std::vector<double> u(n + 1, 0), v(m + 1, 0);
  std::vector<size_t> p(m + 1, 0), way(m + 1, 0);  // p[j]: row (1-based) holding column j
  for (size_t i = 1; i <= n; ++i) {
    p[0] = i;
    size_t j0 = 0;
    std::vector<double> minv(m + 1, std::numeric_limits<double>::infinity());
    std::vector<bool> used(m + 1, false);
    do {
      used[j0] = true;
      const size_t i0 = p[j0];
      double delta = std::numeric_limits<double>::infinity();
      size_t j1 = 0;
      for (size_t j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = cost[i0 - 1][j - 1] - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (size_t j = 0; j <= m; ++j) {
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const size_t j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_column(n, -1);
  for (size_t j = 1; j <= m; ++j)
    if (p[j] != 0) row_column[p[j] - 1] = static_cast<int>(j - 1);
  return row_column;
}

}  // namespace

cv::Point2d Identification::project(cv::Point2d frontal_mm) const {
  return apply(layout_to_image, frontal_mm);
}

Identification identify_markers(const MarkerLayout& layout, const std::vector<Dot>& dots,
                                const std::vector<TagDetection>& tags, double gate) {
  Identification id;

  // Tags identify themselves; their corners give the first layout -> image mapping.
  std::vector<cv::Point2d> from, to;
  for (const MarkerSpec& m : layout.markers) {
    if (!m.is_tag()) continue;
    for (const TagDetection& t : tags) {
      if (t.family != m.family || t.id != m.tag_id) continue;
      id.tags[m.id] = t;
      auto corners = m.tag_corners_frontal();
      for (int k = 0; k < 4; ++k) from.push_back(corners[k]), to.push_back(t.corners[k]);
      break;
    }
  }
  std::vector<const MarkerSpec*> layout_dots;
  std::vector<cv::Point2d> layout_points;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) layout_dots.push_back(&m), layout_points.push_back(m.frontal());

  if (layout_dots.empty() && from.empty()) return id;

  // Each layout dot may take a detection within `gate` of its nearest neighbour's distance.
  std::vector<double> spacing(layout_dots.size(), std::numeric_limits<double>::max());
  for (size_t i = 0; i < layout_points.size(); ++i)
    for (size_t j = 0; j < layout_points.size(); ++j)
      if (i != j) spacing[i] = std::min(spacing[i], cv::norm(layout_points[i] - layout_points[j]));
  const double closest = spacing.empty() ? 1.0 : *std::min_element(spacing.begin(), spacing.end());

  struct Attempt {
    cv::Matx23d mapping;
    std::vector<int> match;
    int matched = 0;
    double residual = 0;
  };
  // Match by proximity, refit an affine from the matches (and tag corners), a few rounds.
  auto settle = [&](cv::Matx23d mapping) {
    Attempt at;
    at.mapping = mapping;
    at.match.assign(layout_dots.size(), -1);
    for (int round = 0; round < 5; ++round) {
      const double scale = std::sqrt(
          std::abs(at.mapping(0, 0) * at.mapping(1, 1) - at.mapping(0, 1) * at.mapping(1, 0)));
      struct Pair {
        double distance;
        size_t layout;
        size_t dot;
      };
      std::vector<Pair> pairs;
      for (size_t i = 0; i < layout_dots.size(); ++i) {
        const cv::Point2d p = apply(at.mapping, layout_points[i]);
        const double limit = gate * spacing[i] * scale;
        for (size_t k = 0; k < dots.size(); ++k) {
          const double d = cv::norm(dots[k].center - p);
          if (d < limit) pairs.push_back({d, i, k});
        }
      }
      std::sort(pairs.begin(), pairs.end(),
                [](const Pair& x, const Pair& y) { return x.distance < y.distance; });
      std::fill(at.match.begin(), at.match.end(), -1);
      std::vector<bool> taken(dots.size(), false);
      at.matched = 0;
      at.residual = 0;
      for (const Pair& p : pairs) {
        if (at.match[p.layout] >= 0 || taken[p.dot]) continue;
        at.match[p.layout] = static_cast<int>(p.dot);
        taken[p.dot] = true;
        ++at.matched;
        at.residual += p.distance / (spacing[p.layout] * scale);
      }
      // An affine absorbs the face's own proportions and a slight turn.
      std::vector<cv::Point2d> f = from, t = to;
      for (size_t i = 0; i < at.match.size(); ++i)
        if (at.match[i] >= 0) f.push_back(layout_points[i]), t.push_back(dots[at.match[i]].center);
      if (f.size() < 4) break;
      cv::Mat a = cv::estimateAffine2D(f, t, cv::noArray(), cv::RANSAC,
                                       std::max(2.0, 0.3 * closest * scale));
      if (a.empty()) break;
      at.mapping = cv::Matx23d(a);
    }
    return at;
  };

  // Starting guesses: the tags' similarity (when there are tags) and the dot cloud's centre
  // and spread at a range of head rolls. The tags sit on the forehead, so a nod or a turn
  // mispredicts the lower face by a whole dot spacing from them alone; the settled attempt
  // matching the most dots, most closely, wins (tag corners stay in every refit).
  Attempt best;
  best.matched = -1;
  auto consider = [&](const cv::Matx23d& start) {
    Attempt at = settle(start);
    if (at.matched > best.matched || (at.matched == best.matched && at.residual < best.residual))
      best = at;
  };
  if (!from.empty()) {
    cv::Mat s = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::LMEDS);
    if (!s.empty()) consider(cv::Matx23d(s));
  }
  if (!dots.empty() && !layout_points.empty()) {
    std::vector<cv::Point2d> seen;
    for (const Dot& d : dots) seen.push_back(d.center);
    const cv::Matx23d upright = similarity_from_clouds(layout_points, seen);
    cv::Point2d centre(0, 0);
    for (const auto& p : seen) centre += p;
    centre *= 1.0 / static_cast<double>(seen.size());
    for (int degrees = -40; degrees <= 40; degrees += 4) {
      const double a = degrees * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
      const cv::Matx33d turn(c, -s, centre.x - c * centre.x + s * centre.y, s, c,
                             centre.y - s * centre.x - c * centre.y, 0, 0, 1);
      const cv::Matx33d base(upright(0, 0), upright(0, 1), upright(0, 2), upright(1, 0),
                             upright(1, 1), upright(1, 2), 0, 0, 1);
      const cv::Matx33d m = turn * base;
      consider(cv::Matx23d(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2)));
    }
  }
  if (best.matched < 0) return id;

  // A real face is not the layout's frontal plane: where it curves away (the cheekbones, the
  // chin under a nod) a dot can lie most of a spacing from where the fit puts it, nearer a
  // neighbour's place than its own. Matching one pair at a time, nearest first, then hands
  // the neighbour's detection to the wrong dot (the chin takes the chin boss's dot and the
  // chin boss is left without). The final matching is the assignment of detections to
  // layout dots with the least total squared distance, up to 0.8 of each dot's spacing, a
  // dot left unmatched costing as much as one at that limit: two dots both shifted the same
  // way then each keep their own detection.
  {
    const cv::Matx23d& m = best.mapping;
    const double scale = std::sqrt(std::abs(m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0)));
    const size_t n = layout_dots.size(), k_count = dots.size();
    std::vector<double> limit(n);
    std::vector<std::vector<double>> cost(n, std::vector<double>(k_count + n, kNoPair));
    for (size_t i = 0; i < n; ++i) {
      const cv::Point2d p = apply(m, layout_points[i]);
      limit[i] = 0.8 * spacing[i] * scale;
      for (size_t k = 0; k < k_count; ++k) {
        const double d = cv::norm(dots[k].center - p);
        if (d < limit[i]) cost[i][k] = d * d;
      }
      cost[i][k_count + i] = limit[i] * limit[i];  // left unmatched
    }
    const std::vector<int> assigned = min_cost_assignment(cost);
    for (size_t i = 0; i < n; ++i)
      best.match[i] = assigned[i] >= 0 && assigned[i] < static_cast<int>(k_count) &&
                              cost[i][static_cast<size_t>(assigned[i])] < kNoPair
                          ? assigned[i]
                          : -1;
  }
  id.layout_to_image = best.mapping;
  id.mapped = true;
  for (size_t i = 0; i < best.match.size(); ++i)
    if (best.match[i] >= 0) id.dots[layout_dots[i]->id] = dots[best.match[i]];
  return id;
}

std::map<std::string, cv::Point2d> read_start_positions(const std::filesystem::path& path,
                                                        const MarkerLayout& layout) {
  TracksReader reader(path);
  TrackedFrame first;
  if (!reader.next(first))
    throw InputError(where(path.string(), 0, "no rows: no starting positions"));
  std::map<std::string, cv::Point2d> out;
  for (const MarkerObservation& m : first.markers) {
    if (!layout.find(m.marker))
      throw InputError(where(path.string(), 0, "marker '" + m.marker + "' is not in the layout"));
    if (m.valid) out[m.marker] = m.position;
  }
  if (out.empty())
    throw InputError(where(path.string(), 0,
                           "no valid starting position in frame " + std::to_string(first.frame)));
  return out;
}

}  // namespace rostro::tracking
