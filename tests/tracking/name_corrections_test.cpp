// Carrying a second look's name corrections back to the frames given out before it.
#include "tracking/name_corrections.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace rostro::tracking {
namespace {

// Frames 0..n-1 of markers a to f in a row 30 px apart, moving 1 px right a frame; b unseen.
std::vector<TrackedFrame> take(int n) {
  std::vector<TrackedFrame> frames;
  for (int k = 0; k < n; ++k) {
    TrackedFrame f;
    f.frame = k;
    for (const char* id : {"a", "b", "c", "d", "e", "f"}) {
      MarkerObservation o;
      o.marker = id;
      o.valid = std::string(id) != "b";
      o.position = o.valid ? cv::Point2d(30.0 * (id[0] - 'a') + k, 50) : cv::Point2d(NAN, NAN);
      o.quality = o.valid ? 1 : 0;
      f.markers.push_back(o);
    }
    frames.push_back(f);
  }
  return frames;
}

const MarkerObservation& at(const TrackedFrame& f, const std::string& id) {
  for (const MarkerObservation& o : f.markers)
    if (o.marker == id) return o;
  throw std::logic_error("no marker " + id);
}

TrackedFrame correction(long frame, long since, std::vector<NameCorrection> corrections) {
  TrackedFrame now = take(static_cast<int>(frame) + 1).back();
  now.corrected_since = since;
  now.corrections = std::move(corrections);
  return now;
}

TEST(NameCorrections, ARenamedDotTakesItsNewNameBackToTheStart) {
  std::vector<TrackedFrame> frames = take(10);
  apply_name_corrections(frames, correction(10, 0, {{"a", "b"}}));
  for (const TrackedFrame& f : frames) {
    EXPECT_FALSE(at(f, "a").valid) << f.frame;
    ASSERT_TRUE(at(f, "b").valid) << f.frame;
    EXPECT_EQ(at(f, "b").position.x, static_cast<double>(f.frame));  // a's old track
    EXPECT_TRUE(at(f, "c").valid);
  }
}

TEST(NameCorrections, SwappedNamesTradeTracksAndANameOnNoDotIsUnseen) {
  std::vector<TrackedFrame> frames = take(6);
  apply_name_corrections(frames, correction(6, 2, {{"a", "c"}, {"c", "a"}}));
  for (const TrackedFrame& f : frames) {
    const bool after = f.frame >= 2;  // the frames before the start keep their names
    const auto k = static_cast<double>(f.frame);
    EXPECT_EQ(at(f, "a").position.x, after ? 60.0 + k : k) << f.frame;
    EXPECT_EQ(at(f, "c").position.x, after ? k : 60.0 + k) << f.frame;
  }
  frames = take(6);
  apply_name_corrections(frames, correction(6, 0, {{"c", ""}}));
  for (const TrackedFrame& f : frames) {
    EXPECT_FALSE(at(f, "c").valid);
    EXPECT_TRUE(std::isnan(at(f, "c").position.x));
    EXPECT_TRUE(at(f, "a").valid);
  }
}

TEST(NameCorrections, OnlyTheTrackThatLedToTheRenameIsRenamed) {
  // a lost on frame 4: what it followed before is not what the second look saw.
  std::vector<TrackedFrame> frames = take(10);
  for (MarkerObservation& o : frames[4].markers)
    if (o.marker == "a") o.valid = false;
  // ... and a jump on frame 7 (re-found on another blob 20 px off, while the face moved 1 px):
  // only frames 7-9 were the renamed dot.
  for (int k = 7; k < 10; ++k)
    for (MarkerObservation& o : frames[static_cast<std::size_t>(k)].markers)
      if (o.marker == "a") o.position.y += 20;
  apply_name_corrections(frames, correction(10, 0, {{"a", "b"}}));
  for (const TrackedFrame& f : frames) {
    const bool renamed = f.frame >= 7;
    EXPECT_EQ(at(f, "b").valid, renamed) << f.frame;
    EXPECT_EQ(at(f, "a").valid, !renamed && f.frame != 4) << f.frame;
  }
}

TEST(NameCorrections, AFaceMovingFastIsNoJump) {
  // Every marker 24 px further a frame (a quick turn): more than half their spacing, but with
  // the face, so the renamed track runs back to the start.
  std::vector<TrackedFrame> frames = take(10);
  for (TrackedFrame& f : frames)
    for (MarkerObservation& o : f.markers) o.position.x += 24.0 * static_cast<double>(f.frame);
  TrackedFrame now = correction(10, 0, {{"a", "b"}});
  for (MarkerObservation& o : now.markers) o.position.x += 240;
  apply_name_corrections(frames, now);
  for (const TrackedFrame& f : frames) EXPECT_TRUE(at(f, "b").valid) << f.frame;
}

TEST(NameCorrections, AWindowHoldsFramesUntilNoLaterFrameCanCorrectThem) {
  CorrectionWindow window(3);
  std::vector<TrackedFrame> out;
  std::vector<TrackedFrame> frames = take(8);
  for (int k = 0; k < 5; ++k) {
    const std::vector<TrackedFrame> ready = window.push(frames[static_cast<std::size_t>(k)]);
    EXPECT_EQ(ready.size(), k < 3 ? 0u : 1u) << k;
    out.insert(out.end(), ready.begin(), ready.end());
  }
  // Frame 5 corrects from frame 2 on: 2, 3 and 4 are still held, 0 and 1 are out as they were.
  for (const TrackedFrame& f : window.push(correction(5, 2, {{"a", "b"}}))) out.push_back(f);
  for (const TrackedFrame& f : window.flush()) out.push_back(f);
  ASSERT_EQ(out.size(), 6u);
  for (const TrackedFrame& f : out) {
    EXPECT_EQ(out[static_cast<std::size_t>(f.frame)].frame, f.frame);  // in order
    EXPECT_EQ(at(f, "b").valid, f.frame >= 2 && f.frame < 5) << f.frame;
  }
  EXPECT_TRUE(window.flush().empty());
  CorrectionWindow none(0);
  EXPECT_EQ(none.push(frames[0]).size(), 1u);  // no horizon: straight through
}

// A pair's names given back when its dots part (TrackerOptions::swap_back_pairs): each
// correction holds from the frame its lost name was lost on.
TEST(NameCorrections, ACorrectionMayHoldFromALaterFrame) {
  std::vector<TrackedFrame> frames = take(10);
  apply_name_corrections(frames, correction(10, 3, {{"a", "b", 6}, {"c", "d", 3}}));
  for (const TrackedFrame& f : frames) {
    EXPECT_EQ(at(f, "a").valid, f.frame < 6) << f.frame;
    EXPECT_EQ(at(f, "b").valid, f.frame >= 6) << f.frame;
    EXPECT_EQ(at(f, "c").valid, f.frame < 3) << f.frame;
    const auto k = static_cast<double>(f.frame);
    EXPECT_EQ(at(f, "d").position.x, f.frame < 3 ? 90.0 + k : 60.0 + k) << f.frame;
  }
}

TEST(NameCorrections, DescribedInOneLine) {
  const TrackedFrame now = correction(10, 0, {{"lip_bot", "lip_bot_l"}, {"mouth_l", ""}});
  EXPECT_EQ(describe_corrections(now),
            "frames 0-9 renamed: lip_bot was lip_bot_l, mouth_l was no marker");
  const TrackedFrame later = correction(10, 2, {{"chin", "chin_boss", 2}, {"a", "b", 5}});
  EXPECT_EQ(describe_corrections(later),
            "frames 2-9 renamed: chin was chin_boss, a was b (frames 5-9)");
}

}  // namespace
}  // namespace rostro::tracking
