#include "tracking/lower_lip_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "facecore/option_check.hpp"
#include "tracking/affine2d.hpp"

namespace rostro::tracking {

void LowerLipOptions::validate() const {
  OptionCheck("LowerLipOptions")
      .not_negative("up", up)
      .not_negative("down", down)
      .not_negative("sideways", sideways)
      .positive("shape", shape);
}

namespace internal {
namespace {

// A lower-lip dot is taken only when at most half as far from its own expected place as from
// where a lost neighbour is expected: between the two it is ambiguous, and a dot left lost is
// better than one named wrongly (Xface fear at 1280x720: the chin boss's dot 7.6 px from the
// curled-under lower lip's middle place and 8.3 px from the lost chin boss's).
constexpr double kClearlyNearer = 2.0;

}  // namespace

bool at_lower_lip(const FeaturePointId& fp) {
  return fp.group == 8 && (fp.index == 2 || fp.index == 7 || fp.index == 8);
}

bool at_upper_lip_or_corner(const FeaturePointId& fp) {
  return fp.group == 8 && fp.index >= 1 && fp.index <= 6 && !at_lower_lip(fp);
}

std::optional<cv::Matx23d> mouth_frame(const std::vector<cv::Point2d>& from,
                                       const std::vector<cv::Point2d>& to) {
  if (from.size() < 2) return std::nullopt;
  // Least squares over all of them: a robust fit to three of five points took the upper lip's
  // three alone, squeezed in a smile (a scale 0.1 low: the lower lip placed a third of a
  // spacing inward at the sides).
  const double n = static_cast<double>(from.size());
  cv::Point2d mean_from(0, 0), mean_to(0, 0);
  for (size_t k = 0; k < from.size(); ++k) mean_from += from[k] / n, mean_to += to[k] / n;
  double a = 0, b = 0, norm = 0;  // to - mean = (a -b; b a)(from - mean)
  for (size_t k = 0; k < from.size(); ++k) {
    const cv::Point2d f = from[k] - mean_from, t = to[k] - mean_to;
    a += f.x * t.x + f.y * t.y, b += f.x * t.y - f.y * t.x, norm += f.dot(f);
  }
  if (!(norm > 0)) return std::nullopt;
  a /= norm, b /= norm;
  return cv::Matx23d(a, -b, mean_to.x - (a * mean_from.x - b * mean_from.y),  //
                     b, a, mean_to.y - (b * mean_from.x + a * mean_from.y));
}

std::optional<std::vector<LowerLipFound>> find_lower_lip(const LowerLipScene& scene,
                                                         const LowerLipSearch& search) {
  const std::vector<LowerLipDot>& members = scene.lower_lip;
  bool any_lost = false;
  for (const LowerLipDot& k : members) any_lost |= !k.followed && k.predicted;
  if (members.size() < 2 || !any_lost) return std::nullopt;
  const std::optional<cv::Matx23d> frame = mouth_frame(scene.upper_start, scene.upper_now);
  if (!frame) return std::nullopt;
  const cv::Matx23d& m = *frame;
  const double scale = scale_of(m);
  const double det = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
  if (!(scale > 0) || std::abs(det) < 1e-12) return std::nullopt;
  // Offsets from a dot's place in the mouth's frame, in start pixels along the start image's
  // axes (the face upright: +y is down the face).
  auto to_start = [&](cv::Point2d d) {
    return cv::Point2d((m(1, 1) * d.x - m(0, 1) * d.y) / det,
                       (-m(1, 0) * d.x + m(0, 0) * d.y) / det);
  };
  double unit = std::numeric_limits<double>::max();
  for (const LowerLipDot& k : members) unit = std::min(unit, k.spacing);
  const LowerLipOptions& o = search.options;
  const double side = o.sideways * unit, up = o.up * unit, down = o.down * unit,
               tolerance = o.shape * unit;

  struct Candidate {
    size_t member;  // index into `members`
    Dot dot;
    cv::Point2d offset;
  };
  std::vector<Candidate> candidates;
  std::vector<cv::Point2d> offsets(members.size());
  for (size_t k = 0; k < members.size(); ++k) {
    const LowerLipDot& member = members[k];
    const cv::Point2d place = apply(m, member.start);
    if (member.followed) {
      offsets[k] = to_start(member.now - place);
      continue;
    }
    if (!member.predicted) continue;
    // The region the lower lip may be in, a strip down the mouth's frame, is searched in
    // windows a spacing wide: the contrast is measured against the level at a window's rim,
    // which for a window as large as the strip takes in the open mouth and, under a head turn,
    // the backdrop beside the chin (the dots' contrast came out at a quarter).
    std::vector<Dot> found;
    for (double along = -up + side; along < down + side; along += side) {
      const cv::Point2d middle = place + apply_linear(m, {0, std::min(along, down)});
      const double radius = side * std::sqrt(2.0) * scale;
      for (const Dot& d : search.dots_near(member.marker, middle, radius)) {
        bool again = false;
        for (const Dot& f : found) again |= cv::norm(f.center - d.center) < 0.25 * unit * scale;
        if (!again) found.push_back(d);
      }
    }
    for (const Dot& d : found) {
      const cv::Point2d u = to_start(d.center - place);
      if (std::abs(u.x) > side || u.y < -up || u.y > down || !search.passes(member.marker, d))
        continue;
      bool taken = false;  // a followed marker's own dot
      for (size_t j = 0; j < scene.followed.size() && !taken; ++j) {
        const FollowedDot& other = scene.followed[j];
        taken = other.marker != member.marker &&
                cv::norm(other.now - d.center) < 0.5 * other.spacing * scale;
      }
      if (!taken) candidates.push_back({k, d, u});
    }
  }

  // Each followed dot's offset and each candidate's is a guess at the shared shift.
  std::vector<cv::Point2d> shifts;
  for (size_t k = 0; k < members.size(); ++k)
    if (members[k].followed) shifts.push_back(offsets[k]);
  for (const Candidate& c : candidates) shifts.push_back(c.offset);
  // A found dot not clearly nearer its place, as the other members (followed or found) put it,
  // than where a lost neighbour is expected may be that one's (kClearlyNearer; the single-dot
  // search judges alike, MarkerTracker's belongs_to).
  auto nearer_a_neighbour = [&](const Candidate& c, const std::vector<cv::Point2d>& others) {
    if (others.empty() || scene.expected.empty()) return false;
    cv::Point2d shift(0, 0);
    for (const cv::Point2d& guess : others) shift += guess / static_cast<double>(others.size());
    const cv::Point2d own_place = apply(m, members[c.member].start) + apply_linear(m, shift);
    const double own = cv::norm(c.dot.center - own_place);
    for (const FollowedDot& other : scene.expected)
      if (cv::norm(c.dot.center - other.now) < kClearlyNearer * own) return true;
    return false;
  };
  int best_count = 0;
  double best_residual = 0;
  std::vector<const Candidate*> best;
  for (const cv::Point2d& shift : shifts) {
    std::vector<cv::Point2d> agreeing;  // the followed members' offsets near this shift
    std::vector<const Candidate*> picks;
    double residual = 0;  // over the agreeing members and the kept picks
    for (size_t k = 0; k < members.size(); ++k) {
      if (members[k].followed) {
        const double r = cv::norm(offsets[k] - shift);
        if (r <= tolerance) agreeing.push_back(offsets[k]), residual += r;
        continue;
      }
      const Candidate* pick = nullptr;
      double nearest = tolerance;
      for (const Candidate& c : candidates)
        if (c.member == k && cv::norm(c.offset - shift) <= nearest)
          pick = &c, nearest = cv::norm(c.offset - shift);
      if (pick) picks.push_back(pick);
    }
    std::vector<const Candidate*> kept;
    for (const Candidate* p : picks) {
      std::vector<cv::Point2d> others = agreeing;
      for (const Candidate* q : picks)
        if (q != p) others.push_back(q->offset);
      if (!nearer_a_neighbour(*p, others))
        kept.push_back(p), residual += cv::norm(p->offset - shift);
    }
    const int count = static_cast<int>(agreeing.size() + kept.size());
    if (kept.empty() || count < 2) continue;
    bool apart = true;  // two members on one dot: not the lower lip
    for (size_t a = 0; a < kept.size(); ++a)
      for (size_t b = a + 1; b < kept.size(); ++b)
        apart &= cv::norm(kept[a]->dot.center - kept[b]->dot.center) >= 0.5 * unit * scale;
    if (apart && (count > best_count || (count == best_count && residual < best_residual)))
      best_count = count, best_residual = residual, best = kept;
  }
  std::vector<LowerLipFound> out;
  for (const Candidate* c : best) out.push_back({members[c->member].marker, c->dot});
  return out;
}

}  // namespace internal
}  // namespace rostro::tracking
