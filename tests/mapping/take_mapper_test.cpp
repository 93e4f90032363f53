// TakeMapper: a take mapped in order, calibrating from its first frames when no profile is
// given (what `rostro capture` and `rostro eval loop` do).

#include "mapping/take_mapper.hpp"

#include <gtest/gtest.h>

#include <random>

#include "facecore/error.hpp"
#include "tests/support/synthetic_face.hpp"
#include "tracking/layout.hpp"

namespace rostro {
namespace {

constexpr int kOpenJaw = 3;

// `neutral` still frames, then the jaw opening frame by frame (test::jaw_opening_take).
std::vector<tracking::TrackedFrame> take(const test::SyntheticActor& actor, long neutral,
                                         long moving) {
  return test::jaw_opening_take(actor, neutral, moving, test::head_pose(0, 0, 0), 3);
}

struct Collected {
  std::vector<FapFrame> frames;
  std::vector<long> ready_after;  // how many frames had been pushed when each came out
};

Collected run(mapping::TakeMapper& mapper, const std::vector<tracking::TrackedFrame>& frames) {
  Collected c;
  long pushed = 0;
  for (const auto& f : frames) {
    ++pushed;
    for (FapFrame& out : mapper.push(f)) {
      c.frames.push_back(std::move(out));
      c.ready_after.push_back(pushed);
    }
  }
  for (FapFrame& out : mapper.finish()) {
    c.frames.push_back(std::move(out));
    c.ready_after.push_back(pushed + 1);  // at finish()
  }
  return c;
}

void expect_every_frame_once_in_order(const Collected& c,
                                      const std::vector<tracking::TrackedFrame>& in) {
  ASSERT_EQ(c.frames.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) EXPECT_EQ(c.frames[i].index, in[i].frame) << i;
}

class TakeMapperTest : public ::testing::Test {
 protected:
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const test::SyntheticActor actor = test::make_actor();
};

TEST_F(TakeMapperTest, CalibratesAfterNFramesThenMapsEveryFrameOnceInOrder) {
  const long n = 10;
  const auto frames = take(actor, n, 15);
  mapping::TakeMapper mapper(layout, {}, actor.camera, std::nullopt, n);
  const Collected c = run(mapper, frames);
  expect_every_frame_once_in_order(c, frames);
  EXPECT_TRUE(mapper.self_calibrated());
  EXPECT_EQ(mapper.calibration_frames_used(), n);
  ASSERT_NE(mapper.profile(), nullptr);
  EXPECT_EQ(mapper.profile()->neutral_frames, n);
  // Nothing before the n-th frame; the n held back come out together at the n-th, then one
  // per push.
  for (std::size_t i = 0; i < c.frames.size(); ++i)
    EXPECT_EQ(c.ready_after[i], std::max<long>(n, static_cast<long>(i) + 1)) << i;
  // The frames are mapped, not just passed along: the jaw keeps opening after the neutral part.
  const auto jaw = [&](std::size_t i) { return c.frames[i].get(kOpenJaw); };
  EXPECT_NEAR(jaw(0), 0.0, 15.0);
  EXPECT_GT(jaw(c.frames.size() - 1), jaw(n + 5));
  EXPECT_GT(jaw(n + 5), jaw(n));
}

TEST_F(TakeMapperTest, ShortTakeCalibratesAtFinish) {
  const auto frames = take(actor, 6, 0);
  mapping::TakeMapper mapper(layout, {}, actor.camera, std::nullopt, 25);
  for (const auto& f : frames) EXPECT_TRUE(mapper.push(f).empty());
  EXPECT_FALSE(mapper.ready());
  EXPECT_EQ(mapper.held_back(), 6);
  const auto rest = mapper.finish();
  ASSERT_EQ(rest.size(), frames.size());
  for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_EQ(rest[i].index, frames[i].frame);
  EXPECT_TRUE(mapper.self_calibrated());
  EXPECT_EQ(mapper.calibration_frames_used(), 6);
  EXPECT_EQ(mapper.held_back(), 0);
}

TEST_F(TakeMapperTest, GivenProfileMapsAtOnce) {
  const auto frames = take(actor, 2, 8);
  const auto profile = test::exact_profile(actor, test::head_pose(0, 0, 0));
  mapping::TakeMapper mapper(layout, {}, actor.camera, profile, 25);
  EXPECT_TRUE(mapper.ready());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto out = mapper.push(frames[i]);
    ASSERT_EQ(out.size(), 1u) << "frame " << i;
    EXPECT_EQ(out[0].index, frames[i].frame);
    // The exact profile reads the driven jaw: 40 per frame after the two neutral ones.
    const double truth = i < 2 ? 0.0 : 40.0 * static_cast<double>(i - 1);
    EXPECT_NEAR(out[0].get(kOpenJaw), truth, 10.0) << "frame " << i;
  }
  EXPECT_TRUE(mapper.finish().empty());
  EXPECT_FALSE(mapper.self_calibrated());
  EXPECT_EQ(mapper.calibration_frames_used(), 0);
  EXPECT_TRUE(mapper.last_pose().has_value());
}

TEST_F(TakeMapperTest, EmptyTakeWithoutProfileIsAnInputError) {
  mapping::TakeMapper mapper(layout, {}, actor.camera, std::nullopt, 25);
  EXPECT_THROW(mapper.finish(), InputError);
}

}  // namespace
}  // namespace rostro

namespace rostro {
namespace {

// Frames whose every observation is invalid: before the face is found, and while it is lost.
tracking::TrackedFrame nothing_seen(tracking::TrackedFrame f) {
  for (auto& m : f.markers) m.valid = false;
  return f;
}

TEST_F(TakeMapperTest, CalibrationWindowStartsWithTheFaceAndLostFramesCarryNoFaps) {
  auto frames = take(actor, 20, 10);
  // The face is found only at frame 5 (a late start), and lost for frames 25-26.
  for (long i : {0, 1, 2, 3, 4, 25, 26})
    frames[static_cast<std::size_t>(i)] = nothing_seen(frames[static_cast<std::size_t>(i)]);
  mapping::MapperOptions options;
  mapping::TakeMapper mapper(layout, options, actor.camera, std::nullopt, 10);
  const Collected c = run(mapper, frames);
  expect_every_frame_once_in_order(c, frames);
  // Calibrated on ten frames with the face (5-14), so the mapper waited for frame 14.
  EXPECT_EQ(mapper.calibration_frames_used(), 10);
  EXPECT_EQ(c.ready_after.front(), 15);
  for (long i : {0L, 1L, 25L, 26L})
    EXPECT_FALSE(c.frames[static_cast<std::size_t>(i)].mask.any()) << "frame " << i;
  EXPECT_TRUE(c.frames[27].has(kOpenJaw));
  EXPECT_GT(c.frames[29].get(kOpenJaw), 100);
}

TEST_F(TakeMapperTest, ATakeWithNothingSeenIsOneInputError) {
  auto frames = take(actor, 5, 0);
  for (auto& f : frames) f = nothing_seen(f);
  mapping::TakeMapper mapper(layout, {}, actor.camera, std::nullopt, 10);
  for (const auto& f : frames) EXPECT_TRUE(mapper.push(f).empty());
  EXPECT_THROW(mapper.finish(), InputError);
}

}  // namespace
}  // namespace rostro
