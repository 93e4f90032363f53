#include "facecore/fapu.hpp"

#include <gtest/gtest.h>

#include "facecore/error.hpp"

namespace rostro {
namespace {

FeaturePointPositions neutral_face() {
  // A face 100 units across: pupils 60 apart, nose base 40 below them, mouth 20 below.
  FeaturePointPositions p;
  p[{3, 5}] = {30, 0, 0};
  p[{3, 6}] = {-30, 0, 0};
  p[{3, 1}] = {30, 6, 0};
  p[{3, 3}] = {30, -6, 0};
  p[{9, 15}] = {0, -40, 0};
  p[{2, 2}] = {0, -60, 0};
  p[{8, 3}] = {25, -62, 0};
  p[{8, 4}] = {-25, -62, 0};
  return p;
}

TEST(Fapu, FromFeaturePointsUsesTheDesignFormulas) {
  const Fapu f = fapu_from_feature_points(neutral_face());
  EXPECT_DOUBLE_EQ(f.es0, 60);
  EXPECT_DOUBLE_EQ(f.ens0, 40);
  EXPECT_DOUBLE_EQ(f.mns0, 20);
  EXPECT_DOUBLE_EQ(f.mw0, 50);
  EXPECT_DOUBLE_EQ(f.irisd0, 12);
  EXPECT_DOUBLE_EQ(f.unit_size(FapUnit::MNS), 20.0 / 1024);
  EXPECT_DOUBLE_EQ(f.unit_size(FapUnit::AU), 1e-5);
  EXPECT_DOUBLE_EQ(f.unit_size(FapUnit::None), 0);
}

TEST(Fapu, ConvertKeepsTheDistance) {
  const Fapu f = fapu_from_feature_points(neutral_face());
  // 1024 MW = 50 units = 2560 MNS.
  EXPECT_DOUBLE_EQ(f.convert(1024, FapUnit::MW, FapUnit::MNS), 2560);
  EXPECT_DOUBLE_EQ(f.convert(77, FapUnit::ENS, FapUnit::ENS), 77);
}

TEST(Fapu, MissingPointIsNamed) {
  auto p = neutral_face();
  p.erase({9, 15});
  try {
    fapu_from_feature_points(p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("9.15"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rostro
