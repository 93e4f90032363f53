// The expression and viseme libraries and the expansion of the high-level FAPs 1 and 2.

#include "facecore/expression_library.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "facecore/error.hpp"

namespace rostro {
namespace {

namespace fs = std::filesystem;

ExpressionLibrary library() {
  return ExpressionLibrary::load(fs::path(ROSTRO_DATA_DIR) / "expressions.json",
                                 fs::path(ROSTRO_DATA_DIR) / "visemes.json");
}

int fap(const char* name) {
  return *find_fap(name);
}

TEST(ExpressionLibrary, LoadsNeutralTheSixExpressionsAndFifteenVisemes) {
  const ExpressionLibrary lib = library();
  EXPECT_TRUE(lib.expression(0).mask.none());
  for (int i = 1; i < kExpressionCount; ++i) EXPECT_GT(lib.expression(i).mask.count(), 5u) << i;
  EXPECT_TRUE(lib.viseme(0).mask.none());
  for (int i = 1; i < kVisemeCount; ++i) EXPECT_GT(lib.viseme(i).mask.count(), 2u) << i;
  // Plausible content: joy raises the lip corners, surprise opens the jaw and lifts brows,
  // "aa" opens the jaw wide, "uh" rounds the lips.
  EXPECT_GT(lib.find_expression("joy")->get(fap("raise_l_cornerlip_o")), 100);
  EXPECT_GT(lib.find_expression("surprise")->get(fap("open_jaw")), 200);
  EXPECT_GT(lib.find_expression("surprise")->get(fap("raise_l_m_eyebrow")), 100);
  EXPECT_LT(lib.find_expression("sadness")->get(fap("raise_l_cornerlip")), 0);
  EXPECT_GT(lib.viseme(10).get(fap("open_jaw")), 300);
  EXPECT_LT(lib.viseme(14).get(fap("stretch_l_cornerlip")), 0);
  EXPECT_EQ(ExpressionLibrary::expression_name(3), "anger");
  EXPECT_EQ(ExpressionLibrary::expression_index("disgust"), 5);
  EXPECT_EQ(lib.find_expression("smug"), nullptr);
  EXPECT_THROW(lib.viseme(15), std::out_of_range);
}

TEST(ExpressionLibrary, ExpandsExpressionsWithTheirIntensities) {
  const ExpressionLibrary lib = library();
  const int jaw = fap("open_jaw"), brow = fap("raise_l_i_eyebrow");
  FapFrame f;
  f.set_expression({6, 63, 4, 21, 0, 0});  // full surprise + a third of fear
  const FapFrame e = lib.expand(f);
  EXPECT_TRUE(e.has(kExpressionFap));
  EXPECT_NEAR(e.get(jaw), lib.expression(6).get(jaw) + lib.expression(4).get(jaw) / 3.0, 1e-9);
  EXPECT_NEAR(e.get(brow), lib.expression(6).get(brow) + lib.expression(4).get(brow) / 3.0, 1e-9);
}

TEST(ExpressionLibrary, ExpandsVisemesWithTheirBlend) {
  const ExpressionLibrary lib = library();
  const int jaw = fap("open_jaw");
  FapFrame f;
  f.set_viseme({10, 14, 21, 0});  // a third "aa", two thirds "uh"
  const FapFrame e = lib.expand(f);
  EXPECT_NEAR(e.get(jaw), lib.viseme(10).get(jaw) / 3.0 + lib.viseme(14).get(jaw) * 2.0 / 3.0,
              1e-9);
}

TEST(ExpressionLibrary, NeverOverwritesLowLevelFapsTheFrameSets) {
  const ExpressionLibrary lib = library();
  const int jaw = fap("open_jaw"), corner = fap("raise_l_cornerlip_o");
  FapFrame f;
  f.set_expression({1, 63, 0, 0, 0, 0});
  f.set(corner, -42);
  f.set(jaw, 0);
  const FapFrame e = lib.expand(f);
  EXPECT_EQ(e.get(corner), -42);
  EXPECT_TRUE(e.has(jaw));
  EXPECT_EQ(e.get(jaw), 0);
  EXPECT_EQ(e.get(fap("raise_r_cornerlip_o")), lib.expression(1).get(fap("raise_r_cornerlip_o")));
}

TEST(ExpressionLibrary, SavedLibraryReadsBackWithTheEditedEntries) {
  ExpressionLibrary lib = library();
  FapFrame joy = *lib.find_expression("joy");
  joy.set(fap("open_jaw"), 420);
  joy.set(fap("raise_l_m_eyebrow"), 12.5);
  lib.set_expression(1, joy);
  FapFrame aa = lib.viseme(10);
  aa.clear(fap("open_jaw"));
  lib.set_viseme(10, aa);
  const fs::path dir = fs::temp_directory_path() / "rostro-library-save";
  fs::create_directories(dir);
  lib.save(dir / "expressions.json", dir / "visemes.json");
  const ExpressionLibrary back =
      ExpressionLibrary::load(dir / "expressions.json", dir / "visemes.json");
  for (int i = 0; i < kExpressionCount; ++i) EXPECT_EQ(back.expression(i), lib.expression(i)) << i;
  for (int i = 0; i < kVisemeCount; ++i) EXPECT_EQ(back.viseme(i), lib.viseme(i)) << i;
  EXPECT_EQ(back.find_expression("joy")->get(fap("open_jaw")), 420);
  EXPECT_FALSE(back.viseme(10).has(fap("open_jaw")));
  EXPECT_THROW(lib.set_expression(7, joy), std::out_of_range);
  // A folder that does not exist: an InputError, and nothing is written.
  EXPECT_THROW(lib.save(dir / "no" / "e.json", dir / "no" / "v.json"), InputError);
  fs::remove_all(dir);
}

TEST(ExpressionLibrary, BadFilesAreInputErrors) {
  const fs::path dir = fs::path(ROSTRO_BINARY_DIR) / "test_expression_library";
  fs::create_directories(dir);
  std::ofstream(dir / "e.json") << R"({"expressions": {"neutral": {}, "joy": {"grin_widely": 3}}})";
  const fs::path visemes = fs::path(ROSTRO_DATA_DIR) / "visemes.json";
  try {
    ExpressionLibrary::load(dir / "e.json", visemes);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grin_widely"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "e2.json") << R"({"expressions": {"neutral": {}}})";
  EXPECT_THROW(ExpressionLibrary::load(dir / "e2.json", visemes), InputError);
}

}  // namespace
}  // namespace rostro
