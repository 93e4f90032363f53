// PipelinedTakeMapper: TakeMapper on a worker thread (`rostro capture` on two cores). The
// same FAP frames as TakeMapper, bit for bit and in order; the calibration frames held back;
// finish() maps the rest; the calibration's error thrown on the caller's thread; no deadlock
// when the queue is full or the mapper is dropped mid-take.

#include "mapping/pipelined_take_mapper.hpp"

#include <gtest/gtest.h>

#include <random>

#include "facecore/error.hpp"
#include "mapping/hierarchy.hpp"
#include "mapping/take_mapper.hpp"
#include "tests/support/synthetic_face.hpp"
#include "tracking/layout.hpp"

namespace rostro {
namespace {

constexpr int kOpenJaw = 3;

// `neutral` still frames, then the jaw opening frame by frame (test::jaw_opening_take).
std::vector<tracking::TrackedFrame> take(const test::SyntheticActor& actor, long neutral,
                                         long moving) {
  return test::jaw_opening_take(actor, neutral, moving, test::head_pose(3, -2, 1), 5);
}

mapping::MapperOptions with_hierarchy() {
  mapping::MapperOptions o;
  o.hierarchy = mapping::default_hierarchy();
  return o;
}

std::vector<FapFrame> run_plain(mapping::TakeMapper& mapper,
                                const std::vector<tracking::TrackedFrame>& frames) {
  std::vector<FapFrame> out;
  for (const auto& f : frames)
    for (FapFrame& r : mapper.push(f)) out.push_back(std::move(r));
  for (FapFrame& r : mapper.finish()) out.push_back(std::move(r));
  return out;
}

struct Collected {
  std::vector<FapFrame> frames;
  std::vector<long> returned_at;  // the push (1-based) that returned each; pushes + 1: finish
};

Collected run_pipelined(mapping::PipelinedTakeMapper& mapper,
                        const std::vector<tracking::TrackedFrame>& frames) {
  Collected c;
  long pushed = 0;
  for (const auto& f : frames) {
    ++pushed;
    for (FapFrame& r : mapper.push(f))
      c.frames.push_back(std::move(r)), c.returned_at.push_back(pushed);
  }
  for (FapFrame& r : mapper.finish())
    c.frames.push_back(std::move(r)), c.returned_at.push_back(pushed + 1);
  return c;
}

void expect_identical(const std::vector<FapFrame>& a, const std::vector<FapFrame>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].index, b[i].index) << i;
    EXPECT_EQ(a[i].mask, b[i].mask) << i;
    EXPECT_EQ(a[i].values, b[i].values) << "frame " << i << ": values differ";  // bit for bit
  }
}

class PipelinedTakeMapperTest : public ::testing::Test {
 protected:
  const tracking::MarkerLayout layout = tracking::load_layout(tracking::default_layout_path());
  const test::SyntheticActor actor = test::make_actor();
};

TEST_F(PipelinedTakeMapperTest, SameFramesAsTakeMapperAfterTheCalibrationHoldBack) {
  const long n = 10;
  const auto frames = take(actor, n, 30);
  mapping::TakeMapper plain(layout, with_hierarchy(), actor.camera, std::nullopt, n);
  const std::vector<FapFrame> expected = run_plain(plain, frames);

  mapping::PipelinedTakeMapper pipelined(layout, with_hierarchy(), actor.camera, std::nullopt, n);
  // The first n - 1 frames are all held back: nothing can come out before the calibration.
  for (long i = 0; i + 1 < n; ++i)
    EXPECT_TRUE(pipelined.push(frames[static_cast<std::size_t>(i)]).empty()) << i;
  EXPECT_EQ(pipelined.held_back(), n - 1);
  EXPECT_FALSE(pipelined.self_calibrated());
  Collected c;
  for (long i = n - 1; i < static_cast<long>(frames.size()); ++i)
    for (FapFrame& r : pipelined.push(frames[static_cast<std::size_t>(i)]))
      c.frames.push_back(std::move(r)), c.returned_at.push_back(i + 1);
  for (FapFrame& r : pipelined.finish()) c.frames.push_back(std::move(r));
  expect_identical(c.frames, expected);
  // A push returns only frames pushed before it (its own is still queued).
  for (std::size_t i = 0; i < c.returned_at.size(); ++i)
    EXPECT_LT(c.frames[i].index, c.returned_at[i]) << i;
  EXPECT_EQ(pipelined.held_back(), 0);
  EXPECT_TRUE(pipelined.self_calibrated());
  EXPECT_EQ(pipelined.calibration_frames_used(), n);
  // The frames were fitted, not passed along: the jaw opens.
  EXPECT_GT(c.frames.back().get(kOpenJaw), c.frames[static_cast<std::size_t>(n) + 5].get(kOpenJaw));
}

TEST_F(PipelinedTakeMapperTest, GivenProfileAndAFullQueueEveryFrameOnceInOrder) {
  const auto frames = take(actor, 2, 40);
  const auto profile = test::exact_profile(actor, test::head_pose(3, -2, 1));
  mapping::TakeMapper plain(layout, with_hierarchy(), actor.camera, profile, 25);
  const std::vector<FapFrame> expected = run_plain(plain, frames);
  // A queue of one: push waits for the worker nearly every frame.
  mapping::PipelinedTakeMapper pipelined(layout, with_hierarchy(), actor.camera, profile, 25, 1);
  const Collected c = run_pipelined(pipelined, frames);
  expect_identical(c.frames, expected);
  EXPECT_FALSE(pipelined.self_calibrated());
}

TEST_F(PipelinedTakeMapperTest, ShortTakeCalibratesAtFinish) {
  const auto frames = take(actor, 6, 0);
  mapping::PipelinedTakeMapper pipelined(layout, {}, actor.camera, std::nullopt, 25);
  const Collected c = run_pipelined(pipelined, frames);
  ASSERT_EQ(c.frames.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(c.frames[i].index, frames[i].frame);
    EXPECT_EQ(c.returned_at[i], 7) << "only finish() calibrates a take this short";
  }
  EXPECT_EQ(pipelined.calibration_frames_used(), 6);
}

TEST_F(PipelinedTakeMapperTest, CalibrationErrorReachesTheCaller) {
  // Every marker lost: the calibration has nothing to work on.
  auto frames = take(actor, 5, 0);
  for (auto& f : frames)
    for (auto& m : f.markers) m.valid = false;
  mapping::PipelinedTakeMapper pipelined(layout, {}, actor.camera, std::nullopt, 3);
  EXPECT_THROW(
      {
        for (const auto& f : frames) pipelined.push(f);
        pipelined.finish();
      },
      InputError);
  // And once failed, it keeps saying so.
  EXPECT_THROW(pipelined.finish(), InputError);
}

TEST_F(PipelinedTakeMapperTest, EmptyTakeWithoutProfileIsAnInputError) {
  mapping::PipelinedTakeMapper pipelined(layout, {}, actor.camera, std::nullopt, 25);
  EXPECT_THROW(pipelined.finish(), InputError);
}

TEST_F(PipelinedTakeMapperTest, DroppedMidTakeStopsWithoutWaiting) {
  const auto frames = take(actor, 2, 30);
  const auto profile = test::exact_profile(actor, test::head_pose(3, -2, 1));
  {
    mapping::PipelinedTakeMapper pipelined(layout, {}, actor.camera, profile, 25, 4);
    for (const auto& f : frames) pipelined.push(f);
    // Destroyed with frames queued and no finish(): must return (the test would hang).
  }
  SUCCEED();
}

}  // namespace
}  // namespace rostro
