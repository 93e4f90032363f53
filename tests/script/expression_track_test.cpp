// Expression envelopes: linear ramps as in the seed, the smooth ease, an open end.

#include "script/expression_track.hpp"

#include <gtest/gtest.h>

namespace rostro::script {
namespace {

ExpressionItem joy(double at, double end, double ramp, Ease ease = Ease::Linear) {
  ExpressionItem e;
  e.expression = 1;
  e.at = at;
  e.end = end;
  e.ramp_in = e.ramp_out = ramp;
  e.intensity = 0.8;
  e.ease = ease;
  return e;
}

TEST(ExpressionTrack, LinearRampsHoldAndRampOut) {
  const ExpressionItem e = joy(1.0, 3.0, 0.5);
  EXPECT_EQ(ExpressionTrack::weight(e, 0.99), 0.0);
  EXPECT_DOUBLE_EQ(ExpressionTrack::weight(e, 1.25), 0.8 * 0.5);
  EXPECT_DOUBLE_EQ(ExpressionTrack::weight(e, 2.0), 0.8);
  EXPECT_DOUBLE_EQ(ExpressionTrack::weight(e, 2.75), 0.8 * 0.5);
  EXPECT_EQ(ExpressionTrack::weight(e, 3.0), 0.0);
}

TEST(ExpressionTrack, SmoothEaseStartsAndEndsSlowly) {
  const ExpressionItem e = joy(0.0, 4.0, 1.0, Ease::Smooth);
  EXPECT_LT(ExpressionTrack::weight(e, 0.1), 0.8 * 0.1);
  EXPECT_DOUBLE_EQ(ExpressionTrack::weight(e, 0.5), 0.8 * 0.5);
  EXPECT_GT(ExpressionTrack::weight(e, 0.9), 0.8 * 0.9);
}

TEST(ExpressionTrack, OpenEndHoldsAndTheLayerScalesTheLibraryVector) {
  const ExpressionLibrary library = ExpressionLibrary::load_default();
  ExpressionItem e = joy(0.0, kOpenEnd, 0.2);
  e.ramp_out = 0.0;
  const ExpressionTrack track({e}, library);
  FapVector value{}, activity{};
  track.sample(1e4, value, activity);
  const FapVector full = speech::low_level_vector(library.expression(1));
  EXPECT_DOUBLE_EQ(speech::fap(value, 41), 0.8 * speech::fap(full, 41));
  EXPECT_DOUBLE_EQ(speech::fap(activity, 41), 0.8);
  EXPECT_EQ(speech::fap(activity, 31), 0.0);  // joy leaves the inner brows alone
}

}  // namespace
}  // namespace rostro::script
