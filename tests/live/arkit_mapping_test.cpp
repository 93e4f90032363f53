#include "live/arkit_mapping.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "facecore/error.hpp"

namespace rostro::live {
namespace {

float weight(const ArkitMapping& m, const FapFrame& f, const std::string& name) {
  std::vector<float> w;
  m.evaluate(f, w);
  for (std::size_t i = 0; i < m.rules().size(); ++i)
    if (m.rules()[i].name == name) return w[i];
  ADD_FAILURE() << name << " not in the mapping";
  return -1;
}

TEST(ArkitMapping, DefaultTableNamesAll52Shapes) {
  const ArkitMapping m = ArkitMapping::load_default();
  EXPECT_EQ(m.rules().size(), 52u);
}

TEST(ArkitMapping, WeightsFollowFapsAndClamp) {
  const ArkitMapping m = ArkitMapping::load_default();
  FapFrame f;
  EXPECT_EQ(weight(m, f, "jawOpen"), 0.0f);
  f.set(3, 350);  // open_jaw, half of its full scale (700)
  EXPECT_NEAR(weight(m, f, "jawOpen"), 0.5f, 1e-6);
  f.set(3, 5000);
  EXPECT_EQ(weight(m, f, "jawOpen"), 1.0f);
  f.set(19, 1024);  // close_t_l_eyelid: the left eye closes, the right does not
  EXPECT_EQ(weight(m, f, "eyeBlinkLeft"), 1.0f);
  EXPECT_EQ(weight(m, f, "eyeBlinkRight"), 0.0f);
  f.set(59, -150);  // raise_l_cornerlip_o negative: a frown, not a smile
  EXPECT_EQ(weight(m, f, "mouthSmileLeft"), 0.0f);
  EXPECT_NEAR(weight(m, f, "mouthFrownLeft"), 0.5f, 1e-6);
}

TEST(ArkitMapping, MalformedTablesAreNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "rostro-arkit";
  std::filesystem::create_directories(dir);
  auto expect_error = [&](const std::string& text, const std::string& fragment) {
    std::ofstream(dir / "m.json") << text;
    try {
      ArkitMapping::load(dir / "m.json");
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error("{", "not valid JSON");
  expect_error(R"({"blendshapes": {"jawOpen": {"open_jaw": 700}}})", "expected all 52");
  expect_error(R"({"blendshapes": {"jawOpen": {"open_mouth": 700}}})",
               "unknown low-level FAP 'open_mouth'");
  expect_error(R"({"blendshapes": {"jawClench": {}}})", "'jawClench' is not an ARKit blend shape");
  expect_error(R"({"blendshapes": {"jawOpen": {"open_jaw": 0}}})", "scale 0");
}

}  // namespace
}  // namespace rostro::live
