// The marker model: steps along fap_axis() without motion data, the prior head's coupled
// motion when the profile carries it, and the hierarchy's derived FAPs folded in.
#include "mapping/marker_model.hpp"

#include <gtest/gtest.h>

#include "facecore/fap_table.hpp"

namespace rostro::mapping {
namespace {

calib::ActorProfile lip_profile() {
  calib::ActorProfile p;
  p.fapu.mns0 = 30;
  p.fapu.mw0 = 50;
  p.fapu.es0 = 64;
  p.fapu.ens0 = 40;
  p.fapu.irisd0 = 12;
  auto add = [&](const std::string& id, FeaturePointId fp, Eigen::Vector3d x) {
    calib::NeutralMarker m;
    m.marker = id;
    m.feature_point = fp;
    m.position = x;
    p.markers.push_back(m);
  };
  add("chin", {2, 1}, {0, -70, 70});
  add("lip_bot", {8, 2}, {0, -40, 90});
  return p;
}

const FapStep* step_of(const MarkerModel& m, const std::string& marker, int fap) {
  for (const ModelMarker& mm : m.markers)
    if (mm.marker == marker)
      for (const FapStep& s : mm.faps)
        if (s.fap == fap) return &s;
  return nullptr;
}

TEST(MarkerModel, WithoutMotionEachFapMovesOnlyItsOwnPointAlongItsAxis) {
  const MarkerModel m = build_marker_model(lip_profile());
  const double mns = 30.0 / 1024.0;
  ASSERT_NE(step_of(m, "chin", 3), nullptr);
  EXPECT_NEAR(step_of(m, "chin", 3)->step.y(), -mns, 1e-12);  // open_jaw: down
  ASSERT_NE(step_of(m, "lip_bot", 52), nullptr);
  EXPECT_NEAR(step_of(m, "lip_bot", 52)->step.y(), mns, 1e-12);  // raise_b_midlip_o: up
  EXPECT_EQ(step_of(m, "lip_bot", 3), nullptr);                  // the jaw does not reach the lip
}

TEST(MarkerModel, ProfileMotionCouplesTheJawToTheLowerLip) {
  calib::ActorProfile p = lip_profile();
  p.marker_motion["chin"] = {{3, {0, -1, 0}}, {14, {0, 0, 1}}};
  p.marker_motion["lip_bot"] = {{3, {0, -0.9, 0}}, {52, {0, 1, 0}}, {5, {0, 0.5, 0}}};
  const MarkerModel plain = build_marker_model(p);
  const double mns = 30.0 / 1024.0;
  ASSERT_NE(step_of(plain, "lip_bot", 3), nullptr);
  EXPECT_NEAR(step_of(plain, "lip_bot", 3)->step.y(), -0.9 * mns, 1e-12);
  EXPECT_NEAR(step_of(plain, "lip_bot", 52)->step.y(), mns, 1e-12);
  EXPECT_EQ(step_of(plain, "lip_bot", 5), nullptr);  // not fitted: no marker on 2.3

  // raise_b_midlip = raise_b_midlip_o (the hierarchy): the inner lip's pull on the marker
  // counts as the outer FAP's. thrust_jaw (depth only) is never folded in.
  MarkerModelOptions o;
  o.derived_rules = {{5, 52, 1.0, true, "inner = outer"}, {14, 3, 0.5, false, "thrust"}};
  const MarkerModel folded = build_marker_model(p, o);
  EXPECT_NEAR(step_of(folded, "lip_bot", 52)->step.y(), 1.5 * mns, 1e-12);
  EXPECT_NEAR(step_of(folded, "chin", 3)->step.z(), 0.0, 1e-12);
}

}  // namespace
}  // namespace rostro::mapping
