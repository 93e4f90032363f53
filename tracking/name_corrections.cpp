#include "tracking/name_corrections.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "tracking/order_statistic.hpp"

namespace rostro::tracking {
namespace {

MarkerObservation* find(TrackedFrame& f, const std::string& id) {
  for (MarkerObservation& o : f.markers)
    if (o.marker == id) return &o;
  return nullptr;
}

// The face's own motion from `a` to `b`: the median shift of the markers seen on both.
cv::Point2d face_shift(const TrackedFrame& a, const TrackedFrame& b) {
  std::vector<double> dx, dy;
  for (const MarkerObservation& oa : a.markers) {
    if (!oa.valid) continue;
    for (const MarkerObservation& ob : b.markers)
      if (ob.marker == oa.marker && ob.valid) {
        dx.push_back(ob.position.x - oa.position.x), dy.push_back(ob.position.y - oa.position.y);
        break;
      }
  }
  return {median(dx), median(dy)};
}

// Half the markers' typical spacing on `f` (the median distance to the nearest other marker
// seen): a followed dot never leaves its neighbours by that much between two frames.
double half_spacing(const TrackedFrame& f) {
  std::vector<double> nearest;
  for (const MarkerObservation& a : f.markers) {
    if (!a.valid) continue;
    double d = std::numeric_limits<double>::max();
    for (const MarkerObservation& b : f.markers)
      if (&a != &b && b.valid) d = std::min(d, cv::norm(a.position - b.position));
    if (d < std::numeric_limits<double>::max()) nearest.push_back(d);
  }
  return nearest.empty() ? std::numeric_limits<double>::max() : 0.5 * median(nearest);
}

}  // namespace

void apply_name_corrections(std::span<TrackedFrame> earlier, const TrackedFrame& now) {
  if (now.corrections.empty()) return;
  // Each corrected name's track, followed back from the last earlier frame while it stays
  // seen and moves with the face (LK followed one blob there; a name re-found on another blob
  // jumps away from its neighbours' motion).
  const double jump = half_spacing(now);
  std::map<std::string, long> track_begins;  // from -> first frame of its last track
  for (const NameCorrection& c : now.corrections) {
    long begins = now.frame;
    const TrackedFrame* after = nullptr;
    const MarkerObservation* after_o = nullptr;
    for (auto it = earlier.rbegin(); it != earlier.rend(); ++it) {
      if (it->frame < std::max(now.corrected_since, c.since)) break;
      const MarkerObservation* o = find(*it, c.from);
      if (o == nullptr || !o->valid) break;
      if (after != nullptr &&
          cv::norm(after_o->position - o->position - face_shift(*it, *after)) > jump)
        break;
      begins = it->frame;
      after = &*it, after_o = o;
    }
    track_begins[c.from] = begins;
  }
  for (TrackedFrame& f : earlier) {
    if (f.frame < now.corrected_since) continue;
    std::map<std::string, MarkerObservation> moved;  // from's observation, by its new name
    for (const NameCorrection& c : now.corrections) {
      if (f.frame < std::max(track_begins[c.from], c.since)) continue;
      MarkerObservation* o = find(f, c.from);
      if (o == nullptr || !o->valid) continue;
      if (!c.to.empty()) moved[c.to] = *o;
      o->valid = false;
      o->quality = 0;
      o->position = cv::Point2d(std::nan(""), std::nan(""));
    }
    for (auto& [to, observation] : moved)
      if (MarkerObservation* o = find(f, to)) {
        o->valid = true;
        o->position = observation.position;
        o->quality = observation.quality;
      }
  }
}

std::string describe_corrections(const TrackedFrame& frame) {
  auto range = [&](long since) {
    return "frames " + std::to_string(std::max(since, frame.corrected_since)) + "-" +
           std::to_string(frame.frame - 1);
  };
  std::string text = range(-1) + " renamed:";
  for (size_t i = 0; i < frame.corrections.size(); ++i) {
    const NameCorrection& c = frame.corrections[i];
    text += (i ? ", " : " ") + c.from + (c.to.empty() ? " was no marker" : " was " + c.to);
    if (c.since > frame.corrected_since) text += " (" + range(c.since) + ")";
  }
  return text;
}

void append_corrected(std::vector<TrackedFrame>& take, TrackedFrame frame) {
  apply_name_corrections(take, frame);
  take.push_back(std::move(frame));
}

std::vector<TrackedFrame> CorrectionWindow::push(TrackedFrame frame) {
  apply_name_corrections(held_, frame);
  held_.push_back(std::move(frame));
  const long ready = std::max(0L, static_cast<long>(held_.size()) - horizon_);
  std::vector<TrackedFrame> out(std::make_move_iterator(held_.begin()),
                                std::make_move_iterator(held_.begin() + ready));
  held_.erase(held_.begin(), held_.begin() + ready);
  return out;
}

std::vector<TrackedFrame> CorrectionWindow::flush() {
  std::vector<TrackedFrame> out = std::move(held_);
  held_.clear();
  return out;
}

}  // namespace rostro::tracking
