#pragma once
// A whole take mapped frame by frame in order, as `rostro capture` and `rostro eval loop` do:
// with an actor profile every frame is mapped at once; without one the first frames (the
// first second of the take from the first frame with a tracked marker, taken as the actor's
// neutral face) are held back, the actor is calibrated on them, and then they and every later
// frame are mapped. A take shorter than
// the calibration window is calibrated on what it has when it ends.

#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "calib/actor_profile.hpp"
#include "calib/camera_intrinsics.hpp"
#include "calib/neutral_motion.hpp"
#include "facecore/face_model.hpp"
#include "facecore/fap_frame.hpp"
#include "mapping/fap_mapper.hpp"
#include "tracking/layout.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::mapping {

class TakeMapper {
 public:
  // `camera` replaces the profile's intrinsics (and is what a calibration here assumes).
  // Without `profile`, the actor is calibrated from the first `calibration_frames` frames
  // (at least one) on the default head's prior (or calibrate_on()'s), for `layout`.
  TakeMapper(const tracking::MarkerLayout& layout, MapperOptions options,
             const calib::CameraIntrinsics& camera, std::optional<calib::ActorProfile> profile,
             long calibration_frames);
  ~TakeMapper();
  // Calibrate on `head`'s prior (its feature points and deformation) instead of the default
  // head's: the head a clip was rendered from, in `rostro eval loop --head`.
  void calibrate_on(std::shared_ptr<const FaceModel> head) { prior_head_ = std::move(head); }
  TakeMapper(const TakeMapper&) = delete;
  TakeMapper& operator=(const TakeMapper&) = delete;

  // The FAP frames now ready, in the order their tracked frames were pushed: none while
  // calibration frames are being collected, all of them at once when the last one arrives.
  // Throws InputError when the calibration fails (too few usable markers).
  std::vector<FapFrame> push(const tracking::TrackedFrame& frame);
  // The end of the take: calibrates on the frames held back if that has not happened yet
  // (throws InputError for a take with no frame at all) and returns the rest.
  std::vector<FapFrame> finish();

  // Frames pushed but not yet returned.
  long held_back() const { return static_cast<long>(pending_.size()); }
  // True once a profile is in use (given, or calibrated here).
  bool ready() const { return mapper_ != nullptr; }
  // Whether the actor was calibrated here from the take (rather than given), and from how
  // many frames: 0 until it happens.
  bool self_calibrated() const { return calibrated_from_ > 0; }
  long calibration_frames_used() const { return calibrated_from_; }
  // How much the face moved over those frames (calib/neutral_motion.hpp); nullopt until the
  // calibration here, or when it could not be measured.
  const std::optional<calib::NeutralMotion>& calibration_motion() const {
    return calibration_motion_;
  }
  // The profile in use; null until ready().
  const calib::ActorProfile* profile() const { return mapper_ ? &profile_ : nullptr; }
  // The head pose of the last mapped frame when the method estimates one.
  std::optional<tracking::HeadPose> last_pose() const;

 private:
  void calibrate();
  std::vector<FapFrame> drain();

  const tracking::MarkerLayout& layout_;
  MapperOptions options_;
  calib::CameraIntrinsics camera_;
  long calibration_frames_;
  calib::ActorProfile profile_;
  std::unique_ptr<FapMapper> mapper_;
  std::deque<tracking::TrackedFrame> pending_;
  long calibrated_from_ = 0;
  std::optional<calib::NeutralMotion> calibration_motion_;
  long usable_ = 0;                              // held-back frames with any valid marker
  std::shared_ptr<const FaceModel> prior_head_;  // null: the default head
};

}  // namespace rostro::mapping
