#include "facecore/fap_table.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "facecore/feature_point.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

TEST(FapTable, Has68FapsNumberedInOrder) {
  ASSERT_EQ(fap_table().size(), 68u);
  for (int id = 1; id <= 68; ++id) EXPECT_EQ(fap_info(id).id, id);
  EXPECT_THROW(fap_info(0), std::out_of_range);
  EXPECT_THROW(fap_info(69), std::out_of_range);
}

TEST(FapTable, NamesAreUniqueAndFindable) {
  std::set<std::string_view> names;
  for (const FapInfo& f : fap_table()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_EQ(find_fap(f.name), f.id);
  }
  EXPECT_EQ(find_fap("open_jaw"), 3);
  EXPECT_FALSE(find_fap("no_such_fap").has_value());
}

TEST(FapTable, UnitsMatchTheStandardGroups) {
  // Xface's FAPFile::scaleFAPVect assigns units by index; the seed notes list it.
  for (int id : {3, 4, 5, 8, 9, 10, 11, 12, 13, 14, 16, 17, 18, 44, 46, 51, 52, 55, 60})
    EXPECT_EQ(fap_info(id).unit, FapUnit::MNS) << id;
  for (int id : {6, 7, 15, 43, 45, 53, 54}) EXPECT_EQ(fap_info(id).unit, FapUnit::MW) << id;
  for (int id : {19, 20, 21, 22, 29, 30}) EXPECT_EQ(fap_info(id).unit, FapUnit::IRISD) << id;
  for (int id : {23, 24, 25, 26, 47, 48, 49, 50}) EXPECT_EQ(fap_info(id).unit, FapUnit::AU) << id;
  for (int id : {27, 28, 37, 38, 39, 40}) EXPECT_EQ(fap_info(id).unit, FapUnit::ES) << id;
  for (int id : {31, 36, 41, 42, 61, 68}) EXPECT_EQ(fap_info(id).unit, FapUnit::ENS) << id;
}

TEST(FapTable, AxesFollowThePositiveDirection) {
  using A = std::array<double, 3>;
  EXPECT_EQ(fap_axis(fap_info(3)), (A{0, -1, 0}));  // open_jaw: down
  EXPECT_EQ(fap_axis(fap_info(6)), (A{1, 0, 0}));   // stretch_l_cornerlip: left = +x
  EXPECT_EQ(fap_axis(fap_info(7)), (A{-1, 0, 0}));  // stretch_r_cornerlip: right
  EXPECT_EQ(fap_axis(fap_info(14)), (A{0, 0, 1}));  // thrust_jaw: forward
  EXPECT_EQ(fap_axis(fap_info(48)), (A{0, 0, 0}));  // head_pitch is a rotation
}

TEST(FapTable, MatchesTheReferenceCsv) {
  const auto csv = test::shared_dir() / "reference" / "mpeg4_faps.csv";
  if (!std::filesystem::exists(csv)) GTEST_SKIP() << "../shared/reference not present: " << csv;
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("fap,", 0) == 0) continue;
    std::stringstream ss(line);
    std::string id, name, unit, dir, positive, fp;
    std::getline(ss, id, ',');
    std::getline(ss, name, ',');
    std::getline(ss, unit, ',');
    std::getline(ss, dir, ',');
    std::getline(ss, positive, ',');
    std::getline(ss, fp, ',');
    const FapInfo& f = fap_info(std::stoi(id));
    EXPECT_EQ(f.name, name);
    EXPECT_EQ(unit_name(f.unit), unit);
    if (dir != "-") {
      EXPECT_EQ(f.bidirectional, dir == "B") << name;
    }
    EXPECT_EQ(std::string(f.feature_point), fp == "-" ? "" : fp) << name;
    ++rows;
  }
  EXPECT_EQ(rows, 68);
}

TEST(FeaturePoints, Has84ParseableUniquePoints) {
  ASSERT_EQ(feature_point_table().size(), 84u);
  std::set<FeaturePointId> seen;
  for (const FeaturePointInfo& p : feature_point_table()) {
    EXPECT_TRUE(seen.insert(p.id).second);
    EXPECT_EQ(parse_feature_point(p.id.str()), p.id);
  }
  EXPECT_FALSE(parse_feature_point("1.1").has_value());
  EXPECT_FALSE(parse_feature_point("2.15").has_value());
  EXPECT_FALSE(parse_feature_point("2").has_value());
  EXPECT_FALSE(parse_feature_point("x.1").has_value());
}

TEST(FeaturePoints, EveryFapPointIsKnown) {
  for (const FapInfo& f : fap_table()) {
    if (f.feature_point.empty()) continue;
    const std::string first(f.feature_point.substr(0, f.feature_point.find(' ')));
    EXPECT_TRUE(parse_feature_point(first).has_value()) << f.name;
  }
}

TEST(FeaturePoints, MirrorPairsLeftAndRightFaps) {
  // Every FAP named _l_ has a twin named _r_ whose feature point is the mirror of its own.
  for (const FapInfo& f : fap_table()) {
    const std::string name(f.name);
    const auto pos = name.find("_l_");
    if (pos == std::string::npos || f.feature_point.empty()) continue;
    std::string twin_name = name;
    twin_name.replace(pos, 3, "_r_");
    const auto twin = find_fap(twin_name);
    ASSERT_TRUE(twin) << twin_name;
    const auto a = parse_feature_point(f.feature_point);
    const auto b = parse_feature_point(fap_info(*twin).feature_point);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(mirror(*a), *b) << name;
    EXPECT_EQ(mirror(*b), *a) << name;
  }
  EXPECT_EQ(mirror({9, 3}), (FeaturePointId{9, 3}));  // nose tip is on the mid-line
  EXPECT_EQ(mirror({3, 7}), (FeaturePointId{3, 12}));
}

}  // namespace
}  // namespace rostro
