// Randomised round trips: many generated streams, each written in every format and read
// back to the same stream.

#include <gtest/gtest.h>

#include <random>

#include "facecore/fap_io.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

FapStream random_stream(std::mt19937& rng) {
  std::uniform_int_distribution<int> frames(0, 40), value(-2000, 2000), small(0, 63), coin(0, 3);
  std::uniform_int_distribution<int> fps_pick(0, 3);
  FapStream s;
  s.header.name = "random_" + std::to_string(rng() % 1000);
  s.header.fps = std::array<double, 4>{25, 30, 60, 29.97}[static_cast<std::size_t>(fps_pick(rng))];
  long index = static_cast<long>(rng() % 5);
  const int n = frames(rng);
  for (int i = 0; i < n; ++i) {
    FapFrame f;
    f.index = index;
    f.time_s = static_cast<double>(index) / s.header.fps;
    index += 1 + (coin(rng) == 0 ? 2 : 0);  // gaps are allowed
    for (int id = 3; id <= kFapCount; ++id)
      if (coin(rng) == 0) f.set(id, value(rng));
    if (coin(rng) == 0) f.set_viseme({small(rng) % 15, small(rng) % 15, small(rng), 0});
    if (coin(rng) == 0)
      f.set_expression({small(rng) % 7, small(rng), small(rng) % 7, small(rng), 0, coin(rng) % 2});
    s.frames.push_back(f);
  }
  return s;
}

TEST(FapRoundTrip, RandomStreamsSurviveEveryFormat) {
  const auto dir = test::scratch_dir("fap-roundtrip");
  std::mt19937 rng(20261121);
  for (int trial = 0; trial < 150; ++trial) {
    const FapStream s = random_stream(rng);
    for (const char* ext : {".fap", ".csv", ".json"}) {
      SCOPED_TRACE(std::string("trial ") + std::to_string(trial) + ext);
      const auto path = dir / (std::string("r") + ext);
      write_fap_stream(path, s);
      const FapStream r = read_fap_stream(path);
      EXPECT_EQ(r.header.name, s.header.name);
      EXPECT_DOUBLE_EQ(r.header.fps, s.header.fps);
      ASSERT_EQ(r.frames.size(), s.frames.size());
      for (std::size_t i = 0; i < s.frames.size(); ++i) {
        EXPECT_EQ(r.frames[i].index, s.frames[i].index);
        EXPECT_NEAR(r.frames[i].time_s, s.frames[i].time_s, 1e-9);
        EXPECT_EQ(r.frames[i].mask, s.frames[i].mask);
        EXPECT_EQ(r.frames[i].values, s.frames[i].values);
        if (s.frames[i].has(1)) {
          EXPECT_EQ(r.frames[i].viseme, s.frames[i].viseme);
        }
        if (s.frames[i].has(2)) {
          EXPECT_EQ(r.frames[i].expression, s.frames[i].expression);
        }
      }
    }
  }
}

}  // namespace
}  // namespace rostro
