#pragma once
// The seed's own mapping (dissertation section 4.3, Eq. 4.16), kept as the baseline: each
// marker's displacement from its neutral position relative to the nose tip (9.3), per axis,
// image y flipped to MPEG-4 y up (image x is the face's left for an unmirrored camera),
// divided by the actor's FAPU measured on the neutral image. The head is assumed still.

#include <optional>
#include <string>
#include <vector>

#include "calib/actor_profile.hpp"
#include "facecore/fap_frame.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::mapping {

class Seed2dMapper {
 public:
  // Throws InputError when the profile has no nose-tip (9.3) marker.
  explicit Seed2dMapper(const calib::ActorProfile& profile);

  // FAPs of every valid marker; an empty mask when the nose tip is not valid this frame.
  FapFrame map(const tracking::TrackedFrame& frame) const;

 private:
  struct Marker {
    std::string id;
    cv::Point2d neutral_offset;  // neutral position minus neutral nose tip, px
    std::vector<int> faps;
  };
  calib::ActorProfile profile_;
  std::string reference_;
  std::vector<Marker> markers_;
};

}  // namespace rostro::mapping
