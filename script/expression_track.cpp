#include "script/expression_track.hpp"

#include <algorithm>
#include <cmath>

namespace rostro::script {
namespace {

double ease(double u, Ease e) {
  u = std::clamp(u, 0.0, 1.0);
  return e == Ease::Smooth ? u * u * (3.0 - 2.0 * u) : u;
}

}  // namespace

ExpressionTrack::ExpressionTrack(std::vector<ExpressionItem> items,
                                 const ExpressionLibrary& library)
    : items_(std::move(items)) {
  std::stable_sort(items_.begin(), items_.end(),
                   [](const ExpressionItem& a, const ExpressionItem& b) { return a.at < b.at; });
  double ended = -kOpenEnd;
  for (const ExpressionItem& item : items_) {
    ended = std::max(ended, item.end);
    ended_by_.push_back(ended);
    vectors_.push_back(speech::low_level_vector(library.expression(item.expression)));
    std::vector<int> moves;
    for (int id = 3; id <= kFapCount; ++id)
      if (speech::fap(vectors_.back(), id) != 0.0) moves.push_back(id);
    moves_.push_back(std::move(moves));
  }
}

double ExpressionTrack::weight(const ExpressionItem& item, double t) {
  if (t < item.at || t >= item.end) return 0.0;
  double w = 1.0;
  if (item.ramp_in > 0.0) w = std::min(w, ease((t - item.at) / item.ramp_in, item.ease));
  if (item.ramp_out > 0.0 && std::isfinite(item.end))
    w = std::min(w, ease((item.end - t) / item.ramp_out, item.ease));
  return item.intensity * w;
}

void ExpressionTrack::sample(double t, FapVector& value, FapVector& activity) const {
  value.fill(0.0);
  activity.fill(0.0);
  // Items before `first` ended before t; items from `last` on start after it.
  const auto first = std::upper_bound(ended_by_.begin(), ended_by_.end(), t) - ended_by_.begin();
  const auto last = std::upper_bound(items_.begin(), items_.end(), t,
                                     [](double x, const ExpressionItem& e) { return x < e.at; }) -
                    items_.begin();
  double total = 0.0;
  for (auto i = first; i < last; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const double w = weight(items_[u], t);
    if (w <= 0.0) continue;
    total += w;
    for (int id : moves_[u]) {
      speech::fap(value, id) += w * speech::fap(vectors_[u], id);
      speech::fap(activity, id) += w;
    }
  }
  if (total > 1.0)
    for (double& v : value) v /= total;
  for (double& a : activity) a = std::min(a, 1.0);
}

std::vector<int> ExpressionTrack::faps() const {
  std::vector<int> out;
  for (const auto& moves : moves_) out.insert(out.end(), moves.begin(), moves.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace rostro::script
