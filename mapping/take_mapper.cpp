#include "mapping/take_mapper.hpp"

#include <algorithm>

#include "calib/actor_calibration.hpp"
#include "calib/actor_prior.hpp"
#include "facecore/error.hpp"

namespace rostro::mapping {

TakeMapper::TakeMapper(const tracking::MarkerLayout& layout, MapperOptions options,
                       const calib::CameraIntrinsics& camera,
                       std::optional<calib::ActorProfile> profile, long calibration_frames)
    : layout_(layout),
      options_(std::move(options)),
      camera_(camera),
      calibration_frames_(std::max(1L, calibration_frames)) {
  if (profile) {
    profile_ = std::move(*profile);
    profile_.camera = camera_;
    mapper_ = make_fap_mapper(profile_, options_);
  }
}

TakeMapper::~TakeMapper() = default;

std::vector<FapFrame> TakeMapper::push(const tracking::TrackedFrame& frame) {
  if (mapper_) return {mapper_->map(frame)};
  pending_.push_back(frame);
  // Frames before the face is found (a late start, a bare face not yet detected) wait with
  // the others but do not count toward the neutral window: it starts with the face.
  if (std::any_of(frame.markers.begin(), frame.markers.end(),
                  [](const tracking::MarkerObservation& m) { return m.valid; }))
    ++usable_;
  if (usable_ < calibration_frames_) return {};
  calibrate();
  return drain();
}

std::vector<FapFrame> TakeMapper::finish() {
  if (!mapper_) calibrate();
  return drain();
}

std::optional<tracking::HeadPose> TakeMapper::last_pose() const {
  return mapper_ ? mapper_->last_pose() : std::nullopt;
}

void TakeMapper::calibrate() {
  // The prior is only needed here; the options point into it, so it lives as long as they do.
  const calib::ActorPrior prior =
      prior_head_ ? calib::actor_prior(prior_head_) : calib::load_actor_prior();
  std::vector<tracking::TrackedFrame> neutral;
  for (const tracking::TrackedFrame& f : pending_)
    if (std::any_of(f.markers.begin(), f.markers.end(),
                    [](const tracking::MarkerObservation& m) { return m.valid; }))
      neutral.push_back(f);
  if (neutral.empty() && !pending_.empty())
    throw InputError("actor calibration: none of the " + std::to_string(pending_.size()) +
                     " frames has a tracked marker or landmark");
  profile_ = calib::calibrate_actor(neutral, camera_,
                                    calib::actor_calibration_options(layout_, prior, "actor"));
  calibrated_from_ = static_cast<long>(neutral.size());
  calibration_motion_ = calib::measure_neutral_motion(neutral);
  mapper_ = make_fap_mapper(profile_, options_);
}

std::vector<FapFrame> TakeMapper::drain() {
  std::vector<FapFrame> out;
  out.reserve(pending_.size());
  for (const tracking::TrackedFrame& f : pending_) out.push_back(mapper_->map(f));
  pending_.clear();
  return out;
}

}  // namespace rostro::mapping
