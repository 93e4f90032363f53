#include "tracking/name_corrections.hpp"

#include <cmath>
#include <map>

namespace rostro::tracking {
namespace {

MarkerObservation* find(TrackedFrame& f, const std::string& id) {
  for (MarkerObservation& o : f.markers)
    if (o.marker == id) return &o;
  return nullptr;
}

}  // namespace

void apply_name_corrections(std::span<TrackedFrame> earlier, const TrackedFrame& now) {
  if (now.corrections.empty()) return;
  // Each corrected name's track, followed back from the last earlier frame while it stays
  // seen and moves by less than a jump between frames (LK followed one dot there).
  const double jump = [&] {
    // A tenth of the spread of the markers seen on the frame of the correction: well over a
    // frame's motion of one dot, well under the spacing of two.
    double lo_x = 1e18, hi_x = -1e18;
    for (const MarkerObservation& o : now.markers)
      if (o.valid) lo_x = std::min(lo_x, o.position.x), hi_x = std::max(hi_x, o.position.x);
    return hi_x > lo_x ? 0.1 * (hi_x - lo_x) : 1e18;
  }();
  std::map<std::string, long> track_begins;  // from -> first frame of its last track
  for (const NameCorrection& c : now.corrections) {
    long begins = now.frame;
    const MarkerObservation* after = nullptr;
    for (auto it = earlier.rbegin(); it != earlier.rend(); ++it) {
      if (it->frame < now.corrected_since) break;
      const MarkerObservation* o = find(*it, c.from);
      if (o == nullptr || !o->valid) break;
      if (after != nullptr &&
          std::hypot(o->position.x - after->position.x, o->position.y - after->position.y) > jump)
        break;
      begins = it->frame;
      after = o;
    }
    track_begins[c.from] = begins;
  }
  for (TrackedFrame& f : earlier) {
    if (f.frame < now.corrected_since) continue;
    std::map<std::string, MarkerObservation> moved;  // from's observation, by its new name
    for (const NameCorrection& c : now.corrections) {
      if (f.frame < track_begins[c.from]) continue;
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
  std::string text = "frames " + std::to_string(frame.corrected_since) + "-" +
                     std::to_string(frame.frame - 1) + " renamed:";
  for (size_t i = 0; i < frame.corrections.size(); ++i) {
    const NameCorrection& c = frame.corrections[i];
    text += (i ? ", " : " ") + c.from + (c.to.empty() ? " was no marker" : " was " + c.to);
  }
  return text;
}

void append_corrected(std::vector<TrackedFrame>& take, TrackedFrame frame) {
  apply_name_corrections(take, frame);
  take.push_back(std::move(frame));
}

std::vector<TrackedFrame> CorrectionWindow::push(TrackedFrame frame) {
  if (!frame.corrections.empty()) {
    std::vector<TrackedFrame> held(held_.begin(), held_.end());
    apply_name_corrections(held, frame);
    held_.assign(held.begin(), held.end());
  }
  held_.push_back(std::move(frame));
  std::vector<TrackedFrame> out;
  while (static_cast<long>(held_.size()) > horizon_) {
    out.push_back(std::move(held_.front()));
    held_.pop_front();
  }
  return out;
}

std::vector<TrackedFrame> CorrectionWindow::flush() {
  std::vector<TrackedFrame> out(std::make_move_iterator(held_.begin()),
                                std::make_move_iterator(held_.end()));
  held_.clear();
  return out;
}

}  // namespace rostro::tracking
