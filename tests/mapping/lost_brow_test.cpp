// An outer brow dot lost for a while (the brow's end turning away under a head turn) leaves its
// FAP seen only through the mid-brow dot, which the brow's outer FAP moves by 3 % of its own
// dot's motion (the default head generated at 20,000 vertices). That is less than the FAP's
// pull toward its previous value, so the fit held it where it was while both brows came down:
// raise_l_o_eyebrow 26.8 % of its range in that head's closed loop with turns at 1280x720. A
// marker that moves a FAP less than SolverOptions::min_reading_share of its own dot's motion
// does not read it, so the FAP is left to the hierarchy's mirror of its measured twin.
#include <gtest/gtest.h>

#include <cmath>

#include "mapping/fap_solver.hpp"
#include "mapping/hierarchy.hpp"
#include "mapping/marker_model.hpp"
#include "tests/support/hidden_dot_fit.hpp"
#include "tests/support/model_projection.hpp"
#include "tests/support/synthetic_face.hpp"

namespace rostro::mapping {
namespace {

constexpr int kRaiseLeftOuter = 35, kRaiseRightOuter = 36;

class LostBrow : public ::testing::Test {
 protected:
  void SetUp() override {
    profile = test::exact_profile(actor, neutral);
    profile.marker_motion["brow_l_out"] = {{kRaiseLeftOuter, {0, 1, 0}}};
    profile.marker_motion["brow_r_out"] = {{kRaiseRightOuter, {0, 1, 0}}};
    profile.marker_motion["brow_l_mid"] = {{kRaiseLeftOuter, {0, 0.03, 0}}};
    profile.marker_motion["brow_r_mid"] = {{kRaiseRightOuter, {0, 0.03, 0}}};
    model = build_marker_model(profile);
  }

  // Both outer brows raised by `raise` ENS, the left outer dot hidden from frame 10 on.
  tracking::TrackedFrame frame_of(double raise, long index) const {
    tracking::TrackedFrame f;
    f.frame = index;
    for (const ModelMarker& m : model.markers) {
      const cv::Point2d px = test::project_model_marker(
          m, {{kRaiseLeftOuter, raise}, {kRaiseRightOuter, raise}}, neutral, actor.camera);
      const bool hidden = m.marker == "brow_l_out" && index >= 10;
      f.markers.push_back({m.marker, m.feature_point, px, !hidden, 1.0});
    }
    return f;
  }

  // Largest error of the left outer brow's FAP, after the hierarchy, over the frames its dot is
  // hidden: the brows rise to 136 ENS over the first 10 frames, then come down to 0 by frame 25.
  double worst_hidden_error(const SolverOptions& options) {
    FapSolver solver(profile, options);
    auto raise = [](int i) { return 136 * (i < 10 ? i / 9.0 : std::max(0.0, (25 - i) / 15.0)); };
    return test::worst_hidden_error(
        solver, profile.fapu, 30, 10, kRaiseLeftOuter, kRaiseRightOuter,
        [&](int i) { return frame_of(raise(i), i); },
        [&](int i) {
          return std::map<int, double>{{kRaiseLeftOuter, raise(i)}, {kRaiseRightOuter, raise(i)}};
        });
  }

  test::SyntheticActor actor = test::make_actor();
  tracking::HeadPose neutral = test::head_pose(0, 0, 0);
  calib::ActorProfile profile;
  MarkerModel model;
};

// Read through the mid-brow dot the hidden FAP lags the brows' fall by 29 ENS; mirrored from
// its twin it is exact.
TEST_F(LostBrow, TheHiddenBrowFollowsItsTwinNotItsLastValue) {
  EXPECT_LT(worst_hidden_error({}), 3.0);
  SolverOptions every_marker;
  every_marker.min_reading_share = 0;
  EXPECT_GT(worst_hidden_error(every_marker), 20.0);
}

}  // namespace
}  // namespace rostro::mapping
