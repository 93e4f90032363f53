#include "tracking/identify.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/calib3d.hpp>

#include "facecore/error.hpp"
#include "facecore/option_check.hpp"
#include "tracking/affine2d.hpp"
#include "tracking/lower_lip_search.hpp"
#include "tracking/order_statistic.hpp"
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
// The final naming (below): how far from its predicted place a detection may be given to a
// dot (share of its spacing: farther in the first round, from the base alone, than once the
// named neighbours' offsets are in; kReachLimit for a lone free detection after the rounds),
// in how many rounds, and how much the base's own place weighs
// against the named neighbours' offsets (one a typical spacing away: 0.61).
constexpr double kFirstNameLimit = 0.8;
constexpr double kNameLimit = 0.5;
constexpr double kReachLimit = 0.9;
constexpr int kNameRounds = 3;
// The face model's offsets from its affine are averaged with this much weight on none.
constexpr double kFaceShrink = 0.5;
constexpr double kOwnWeight = 0.2;

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

void IdentificationOptions::validate() const {
  OptionCheck("IdentificationOptions")
      .positive("gate", gate)
      .at_least("size_factor", size_factor, 1)
      .not_negative("ink_weight", ink_weight)
      .not_negative("unnamed_rival", unnamed_rival)
      .not_negative("sure_within", sure_within)
      .at_least("shape_factor", shape_factor, 1)
      .within("alone_share", alone_share, 0, 1)
      .within("min_explained", min_explained, 0, 1)
      .positive("max_residual", max_residual)
      .within("min_margin", min_margin, 0, 1)
      .not_negative("min_tags", min_tags)
      .positive("max_tag_error", max_tag_error)
      .at_least("max_elongation", max_elongation, 1);
}

std::string describe(const IdentificationConfidence& c) {
  std::string out = fmt::format("{}/{} dots, residual {:.2f}, margin {:.2f}", c.matched, c.dots,
                                c.residual, c.margin);
  if (c.tags > 0)
    out += fmt::format(", tags {}/{} read, {} agree", c.tags_seen, c.tags, c.tags_agreeing);
  if (c.face_model) out += ", face landmarks";
  return out;
}

Identification identify_markers(const MarkerLayout& layout, const std::vector<Dot>& detected,
                                const std::vector<TagDetection>& tags,
                                const IdentificationOptions& options,
                                const std::map<std::string, cv::Point2d>& expected) {
  Identification id;
  // One dot may be found twice (two peaks of one blob, a pixel apart): the stronger stays, or
  // the two would look like rivals for one name.
  std::vector<Dot> dots;
  for (const Dot& d : detected)
    if (std::none_of(dots.begin(), dots.end(), [&](const Dot& kept) {
          return cv::norm(kept.center - d.center) < 0.5 * std::max(kept.diameter, d.diameter);
        }))
      dots.push_back(d);
  const double gate = options.gate;

  // Tags identify themselves; their corners give the first layout -> image mapping.
  std::vector<cv::Point2d> from, to;
  struct SeenTag {
    std::array<cv::Point2d, 4> frontal, image;
  };
  std::vector<SeenTag> seen_tags;
  for (const MarkerSpec& m : layout.markers) {
    if (!m.is_tag()) continue;
    ++id.confidence.tags;
    for (const TagDetection& t : tags) {
      if (t.family != m.family || t.id != m.tag_id) continue;
      id.tags[m.id] = t;
      auto corners = m.tag_corners_frontal();
      SeenTag seen;
      for (int k = 0; k < 4; ++k) {
        from.push_back(corners[k]), to.push_back(t.corners[k]);
        seen.frontal[k] = corners[k], seen.image[k] = t.corners[k];
      }
      seen_tags.push_back(seen);
      break;
    }
  }
  id.confidence.tags_seen = static_cast<int>(seen_tags.size());
  std::vector<const MarkerSpec*> layout_dots;
  std::vector<cv::Point2d> layout_points;
  for (const MarkerSpec& m : layout.markers)
    if (!m.is_tag()) layout_dots.push_back(&m), layout_points.push_back(m.frontal());
  id.confidence.dots = static_cast<int>(layout_dots.size());
  // Whether dots i and j speak for each other's places (IdentificationOptions::lower_lip_apart).
  std::vector<bool> on_lower_lip;
  for (const MarkerSpec* m : layout_dots)
    on_lower_lip.push_back(options.lower_lip_apart && internal::at_lower_lip(m->feature_point));
  auto neighbours = [&](size_t i, size_t j) { return on_lower_lip[i] == on_lower_lip[j]; };

  auto judge = [&] {
    IdentificationConfidence& c = id.confidence;
    const int tags_needed = std::min(options.min_tags, c.tags);
    const double explained = c.dots > 0 ? static_cast<double>(c.matched) / c.dots : 1.0;
    if (!id.mapped)
      c.doubt = "nothing could be placed";
    else if (c.tags_seen < tags_needed)
      c.doubt = fmt::format("{} of {} tags read", c.tags_seen, c.tags);
    else if (c.tags_agreeing < c.tags_seen)
      c.doubt = fmt::format("{} of {} tags read disagree with the dots",
                            c.tags_seen - c.tags_agreeing, c.tags_seen);
    else if (explained < options.min_explained)
      c.doubt = fmt::format("{} of {} dots found where the layout puts them", c.matched, c.dots);
    else if (c.residual > options.max_residual)
      c.doubt =
          fmt::format("the dots lie {:.2f} spacings from the layout's arrangement", c.residual);
    else if (c.elongation > options.max_elongation)
      c.doubt = fmt::format("the dots are smeared ({:.1f} times as long as wide): motion blur",
                            c.elongation);
    else if (c.margin < options.min_margin)
      c.doubt = fmt::format("another assignment explains the dots nearly as well (margin {:.2f})",
                            c.margin);
    c.confident = c.doubt.empty();
  };

  if (layout_dots.empty() && from.empty()) {
    judge();
    return id;
  }

  // Each layout dot may take a detection within `gate` of its nearest neighbour's distance.
  std::vector<double> spacing(layout_dots.size(), std::numeric_limits<double>::max());
  for (size_t i = 0; i < layout_points.size(); ++i)
    for (size_t j = 0; j < layout_points.size(); ++j)
      if (i != j) spacing[i] = std::min(spacing[i], cv::norm(layout_points[i] - layout_points[j]));
  const double closest = spacing.empty() ? 1.0 : *std::min_element(spacing.begin(), spacing.end());
  // The layout's typical spacing: how far a neighbour's offset speaks for a dot.
  const double closest_typical = order_statistic(spacing, 0.5, 1.0);

  auto scale_of = [](const cv::Matx23d& m) {
    return std::sqrt(std::abs(m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0)));
  };
  // Detections of the dots' common size and shape, judged against the medians of `match`'s
  // (all while nothing is matched).
  auto dot_like = [&](const std::vector<int>& match) {
    std::vector<double> d, e;
    for (int k : match)
      if (k >= 0)
        d.push_back(dots[static_cast<size_t>(k)].diameter),
            e.push_back(dots[static_cast<size_t>(k)].elongation);
    std::vector<bool> ok(dots.size(), true);
    if (d.size() < 3) return ok;
    const double median = order_statistic(d, 0.5, 0), elongation = order_statistic(e, 0.5, 1);
    for (size_t k = 0; k < dots.size(); ++k)
      ok[k] = dots[k].diameter <= median * options.size_factor &&
              dots[k].diameter >= median / options.size_factor &&
              (dots[k].elongation <= elongation * options.shape_factor ||
               dots[k].share <= options.alone_share);
    return ok;
  };
  // How many of the tags read lie where `mapping` puts them (their centres: a side tag on a
  // curved headband turns away, and its corners with it, while its centre stays near the
  // frontal arrangement's place).
  auto tags_agreeing = [&](const cv::Matx23d& mapping) {
    int agreeing = 0;
    for (const SeenTag& t : seen_tags) {
      const double side = cv::norm(t.image[0] - t.image[1]);
      cv::Point2d predicted(0, 0), seen(0, 0);
      for (int k = 0; k < 4; ++k) predicted += apply(mapping, t.frontal[k]), seen += t.image[k];
      agreeing += cv::norm(predicted - seen) / 4 <= options.max_tag_error * side;
    }
    return agreeing;
  };

  struct Attempt {
    cv::Matx23d mapping;
    std::vector<int> match;
    int matched = 0;
    double score = 0;  // matched dots, each weighed down by its distance: 1 at its place
  };
  // A face model marks each dot's feature point, and the dot is worn `beside` it (above the
  // brow hair, beside the eye's corners, above and below the lids, docs/markers.md): its place
  // is the model's point moved by that offset, turned and scaled as `mapping` lays the layout
  // on the image. A dot larger than the layout's is worn with the same clearance from the
  // feature, so its centre lies farther out by the difference in radius (the matched
  // detections' median diameter against the layout's).
  auto worn_places = [&](const cv::Matx23d& mapping, const std::vector<int>& match) {
    std::map<std::string, cv::Point2d> worn = expected;
    if (!options.dots_beside_points) return worn;
    const double px_per_mm = scale_of(mapping);
    std::vector<double> diameters;
    for (int k : match)
      if (k >= 0) diameters.push_back(dots[static_cast<size_t>(k)].diameter);
    const double measured_mm = px_per_mm > 0 ? order_statistic(diameters, 0.5, 0) / px_per_mm : 0;
    const double larger_mm = std::max(0.0, (measured_mm - layout.dot_diameter_mm) / 2);
    for (const MarkerSpec* dot : layout_dots) {
      auto it = worn.find(dot->id);
      if (it == worn.end() || !dot->beside_mm) continue;
      // beside_mm: x toward the face's left, y up; the layout's frontal axes: y down.
      cv::Point2d b(dot->beside_mm->x, -dot->beside_mm->y);
      const double length = cv::norm(b);
      if (length <= 0) continue;
      b *= (length + larger_mm) / length;
      it->second += cv::Point2d(mapping(0, 0) * b.x + mapping(0, 1) * b.y,
                                mapping(1, 0) * b.x + mapping(1, 1) * b.y);
    }
    return worn;
  };

  // Match by proximity, refit an affine from the matches (and tag corners), a few rounds.
  auto settle = [&](cv::Matx23d mapping) {
    Attempt at;
    at.mapping = mapping;
    at.match.assign(layout_dots.size(), -1);
    for (int round = 0; round < 5; ++round) {
      const double scale = scale_of(at.mapping);
      const std::vector<bool> usable = dot_like(at.match);
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
          if (d < limit && usable[k]) pairs.push_back({d, i, k});
        }
      }
      std::sort(pairs.begin(), pairs.end(),
                [](const Pair& x, const Pair& y) { return x.distance < y.distance; });
      std::fill(at.match.begin(), at.match.end(), -1);
      std::vector<bool> taken(dots.size(), false);
      at.matched = 0;
      at.score = 0;
      for (const Pair& p : pairs) {
        if (at.match[p.layout] >= 0 || taken[p.dot]) continue;
        at.match[p.layout] = static_cast<int>(p.dot);
        taken[p.dot] = true;
        ++at.matched;
        const double r = p.distance / (gate * spacing[p.layout] * scale);
        at.score += 1 - r * r;
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
  // mispredicts the lower face by a whole dot spacing from them alone; each guess is settled,
  // and those the tags read disagree with are dropped (a shifted arrangement can match as many
  // blobs on a real face). The best-scoring settled attempt wins; the best one that names the
  // dots otherwise is its rival, and the margin between the two is part of the confidence.
  std::vector<Attempt> attempts;
  auto consider = [&](const cv::Matx23d& start) {
    Attempt at = settle(start);
    if (!seen_tags.empty() && 2 * tags_agreeing(at.mapping) < static_cast<int>(seen_tags.size()))
      return;
    attempts.push_back(std::move(at));
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
  if (attempts.empty()) {
    judge();
    return id;
  }
  const auto best_it =
      std::max_element(attempts.begin(), attempts.end(),
                       [](const Attempt& x, const Attempt& y) { return x.score < y.score; });
  Attempt best = *best_it;
  // Two attempts name the dots alike when most of the dots either matches get the same
  // detection from both.
  auto alike = [&](const Attempt& x) {
    int same = 0, either = 0;
    for (size_t i = 0; i < best.match.size(); ++i) {
      if (best.match[i] < 0 && x.match[i] < 0) continue;
      ++either;
      same += best.match[i] == x.match[i];
    }
    return either == 0 || same >= 0.8 * either;
  };
  double rival = 0;
  for (const Attempt& at : attempts)
    if (!alike(at)) rival = std::max(rival, at.score);
  id.confidence.margin = best.score > 0 ? std::clamp(1 - rival / best.score, 0.0, 1.0) : 0;

  // A real face is not the layout's frontal plane, nor its average proportions: where it
  // curves away (the cheekbones, the chin under a nod) or smiles (the mouth wide, the lower lip
  // low), a dot lies a good part of a spacing from where the affine puts it, nearer a
  // neighbour's place than its own, and blobs that are no dots (a beard, a lip corner) lie
  // nearer still. So each dot gets a base place: where a model of this face puts it (dlib's
  // landmarks, face_prior.hpp) when there is one the tags agree with, else the affine's. Its
  // predicted place is the base plus its named neighbours' offsets from theirs (a face's own
  // shape moves neighbours together); the naming is the assignment of detections to dots with
  // the least total squared distance from the predictions, up to kFirstNameLimit of each dot's
  // spacing (kNameLimit in the later rounds), a dot left unnamed costing as much as one at that
  // limit (two dots shifted the same way each keep their own detection), repeated as the
  // predictions improve.
  {
    const cv::Matx23d& m = best.mapping;
    const double scale = scale_of(m);
    const size_t n = layout_dots.size(), k_count = dots.size();
    const std::vector<bool> usable = dot_like(best.match);
    std::vector<cv::Point2d> base(n);
    for (size_t i = 0; i < n; ++i) base[i] = apply(m, layout_points[i]);
    // A model of the face, where the tags agree with it, places the dots it knows better than
    // the affine, and the rest by the layout mapped onto those.
    {
      const std::map<std::string, cv::Point2d> worn = worn_places(m, best.match);
      std::vector<cv::Point2d> f, t;
      for (size_t i = 0; i < n; ++i)
        if (auto it = worn.find(layout_dots[i]->id); it != worn.end())
          f.push_back(layout_points[i]), t.push_back(it->second);
      cv::Mat a;
      if (f.size() >= 6)
        a = cv::estimateAffine2D(f, t, cv::noArray(), cv::RANSAC, 0.3 * closest_typical * scale);
      if (!a.empty() && 2 * tags_agreeing(cv::Matx23d(a)) >= static_cast<int>(seen_tags.size())) {
        // The face's shape, not its points: the layout mapped by the affine through the
        // model's places (where the dots are worn), plus their offsets from it smoothed over
        // neighbours (a landmark still sits a little off: at the visible eye corner, on the
        // brow hair), shrunk toward none where the model places no dot near.
        const cv::Matx23d face(a);
        std::vector<cv::Point2d> offset(n);
        std::vector<bool> known(n, false);
        for (size_t i = 0; i < n; ++i)
          if (auto it = worn.find(layout_dots[i]->id); it != worn.end())
            offset[i] = it->second - apply(face, layout_points[i]), known[i] = true;
        for (size_t i = 0; i < n; ++i) {
          cv::Point2d sum(0, 0);
          double weight = kFaceShrink;
          for (size_t j = 0; j < n; ++j) {
            if (!known[j] || !neighbours(i, j)) continue;
            const double d = cv::norm(layout_points[i] - layout_points[j]) / closest_typical;
            const double w = std::exp(-0.5 * d * d);
            sum += w * offset[j], weight += w;
          }
          base[i] = apply(face, layout_points[i]) + sum * (1 / weight);
        }
        id.confidence.face_model = true;
      }
    }
    std::vector<double> limit(n);
    std::vector<int> named(n, -1);
    // Each dot's place: its base plus its named neighbours' offsets from theirs (itself left
    // out), weighed by their nearness in the layout.
    auto predict = [&](size_t i) {
      cv::Point2d offset(0, 0);
      double weight = kOwnWeight;  // the base's own say where no named neighbour is near
      for (size_t j = 0; j < n; ++j) {
        if (j == i || named[j] < 0 || !neighbours(i, j)) continue;
        const double d = cv::norm(layout_points[i] - layout_points[j]) / closest_typical;
        const double w = std::exp(-0.5 * d * d);
        offset += w * (dots[static_cast<size_t>(named[j])].center - base[j]);
        weight += w;
      }
      return base[i] + offset * (1 / weight);
    };
    std::vector<cv::Point2d> predicted = base;
    // How much fainter than the named dots each detection is (IdentificationOptions::ink_weight).
    std::vector<double> faintness(k_count, 0.0);
    {
      std::vector<double> contrasts;
      for (int k : best.match)
        if (k >= 0) contrasts.push_back(dots[static_cast<size_t>(k)].contrast);
      const double typical = order_statistic(contrasts, 0.5, 0);
      for (size_t k = 0; k < k_count; ++k)
        if (typical > 0 && dots[k].contrast > 0 && dots[k].contrast < typical)
          faintness[k] = std::pow(std::log(typical / dots[k].contrast), 2);
    }
    for (int round = 0; round < kNameRounds; ++round) {
      const double reach = round == 0 ? kFirstNameLimit : kNameLimit;
      for (size_t i = 0; i < n; ++i) limit[i] = reach * spacing[i] * scale;
      std::vector<std::vector<double>> cost(n, std::vector<double>(k_count + n, kNoPair));
      for (size_t i = 0; i < n; ++i) {
        const double unit = spacing[i] * scale;
        for (size_t k = 0; k < k_count; ++k) {
          const double d = cv::norm(dots[k].center - predicted[i]);
          if (d < limit[i] && usable[k])
            cost[i][k] = d * d + options.ink_weight * unit * unit * faintness[k];
        }
        cost[i][k_count + i] = limit[i] * limit[i];  // left unnamed
      }
      const std::vector<int> assigned = min_cost_assignment(cost);
      for (size_t i = 0; i < n; ++i)
        named[i] = assigned[i] >= 0 && assigned[i] < static_cast<int>(k_count) &&
                           cost[i][static_cast<size_t>(assigned[i])] < kNoPair
                       ? assigned[i]
                       : -1;
      for (size_t i = 0; i < n; ++i) predicted[i] = predict(i);
    }
    // A dot still unnamed (where the face curves away from the layout's plane most: the
    // cheekbones) takes the one free detection within kReachLimit of its predicted place, when
    // there is exactly one.
    {
      std::vector<bool> taken(k_count, false);
      for (int k : named)
        if (k >= 0) taken[static_cast<size_t>(k)] = true;
      for (size_t i = 0; i < n; ++i) {
        if (named[i] >= 0) continue;
        int only = -1, count = 0;
        for (size_t k = 0; k < k_count; ++k)
          if (!taken[k] && usable[k] &&
              cv::norm(dots[k].center - predicted[i]) < kReachLimit * spacing[i] * scale)
            only = static_cast<int>(k), ++count;
        if (count == 1) named[i] = only, taken[static_cast<size_t>(only)] = true;
      }
    }
    // A name in doubt left out (IdentificationOptions::unnamed_rival).
    {
      std::vector<size_t> in_doubt;
      for (size_t i = 0; i < n; ++i) {
        if (named[i] < 0) continue;
        const cv::Point2d at = dots[static_cast<size_t>(named[i])].center;
        const double own = cv::norm(at - predicted[i]);
        if (own < options.sure_within * spacing[i] * scale) continue;
        for (size_t j = 0; j < n; ++j)
          if (named[j] < 0 && cv::norm(at - predicted[j]) < options.unnamed_rival * own) {
            in_doubt.push_back(i);
            break;
          }
      }
      for (size_t i : in_doubt) named[i] = -1;
    }
    for (size_t i = 0; i < n; ++i) id.places[layout_dots[i]->id] = predicted[i];
    best.match = named;
    // Residual: each named dot's distance from where its neighbours put it (in its spacings),
    // the median over the named dots: a few dots where the face curves away from the plane
    // the most do not make a naming doubtful. Margin: how much farther the next detection
    // lies from there, in half spacings (1 at half a spacing or more), the lowest quartile: a
    // quarter of the names in doubt make the naming doubtful.
    std::vector<double> distances;
    int matched = 0;
    std::vector<double> gaps;
    for (size_t i = 0; i < n; ++i) {
      if (named[i] < 0) continue;
      ++matched;
      const double unit = spacing[i] * scale;
      const double own = cv::norm(dots[static_cast<size_t>(named[i])].center - predicted[i]);
      double other = 1e18;
      for (size_t k = 0; k < k_count; ++k)
        if (static_cast<int>(k) != named[i] && usable[k])
          other = std::min(other, cv::norm(dots[k].center - predicted[i]));
      distances.push_back(own / unit);
      gaps.push_back(std::clamp((other - own) / (0.5 * unit), 0.0, 1.0));
    }
    id.confidence.matched = matched;
    std::vector<double> elongations;
    for (size_t i = 0; i < n; ++i)
      if (named[i] >= 0) elongations.push_back(dots[static_cast<size_t>(named[i])].elongation);
    id.confidence.elongation = order_statistic(elongations, 0.5, 1);
    id.confidence.residual = order_statistic(distances, 0.5, 0);
    if (!gaps.empty()) {
      // Without tags read, a shifted arrangement is the rival to beat as well.
      const double local = order_statistic(gaps, 0.25, 0);
      id.confidence.margin = seen_tags.empty() ? std::min(local, id.confidence.margin) : local;
    }
  }
  id.layout_to_image = best.mapping;
  id.mapped = true;
  id.confidence.tags_agreeing = tags_agreeing(best.mapping);
  for (size_t i = 0; i < best.match.size(); ++i)
    if (best.match[i] >= 0) id.dots[layout_dots[i]->id] = dots[best.match[i]];
  judge();
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
