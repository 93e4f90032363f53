#include "eval/ibug_pts.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

namespace fs = std::filesystem;

class IbugPts : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(ROSTRO_BINARY_DIR) / "test_eval_tmp" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }
  // 68 points, point i (1-based) at (i + offset, 2 i).
  static std::string pts68(double offset = 0) {
    std::string s = "version: 1\nn_points:  68\n{\n";
    for (int i = 1; i <= 68; ++i)
      s += std::to_string(i + offset) + " " + std::to_string(2.0 * i) + "\n";
    return s + "}\n";
  }
  std::string error_of(const std::string& text) {
    try {
      read_pts(write("bad.pts", text));
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
};

TEST_F(IbugPts, ReadsA68PointFile) {
  const auto points = read_pts(write("a.pts", pts68()));
  ASSERT_EQ(points.size(), 68u);
  EXPECT_DOUBLE_EQ(points[36].x, 37.0);
  EXPECT_DOUBLE_EQ(points[36].y, 74.0);
}

TEST_F(IbugPts, MalformedFilesNameTheFileLineAndProblem) {
  EXPECT_NE(error_of("version: 1\nn_points: 2\n{\n1 2\n3 x\n}\n").find("bad.pts:5:"),
            std::string::npos);
  EXPECT_NE(error_of("version: 1\nn_points: 3\n{\n1 2\n3 4\n}\n").find("n_points says 3"),
            std::string::npos);
  EXPECT_NE(error_of("version: 1\nn_points: 1\n{\n1 2\n").find("not closed"), std::string::npos);
  EXPECT_NE(error_of("version: 1\n{\n1 2\n}\n").find("n_points"), std::string::npos);
  EXPECT_NE(error_of("hello\n").find("bad.pts:1:"), std::string::npos);
  EXPECT_NE(error_of("").find("no point block"), std::string::npos);
  EXPECT_NE(error_of("n_points: 1\n{\n1 2 3\n}\n").find("expected a point"), std::string::npos);
  EXPECT_THROW(read_pts(dir_ / "missing.pts"), InputError);
}

TEST_F(IbugPts, DefaultMappingPutsTheOuterEyeCornersOn37And46) {
  const IbugMapping m = default_ibug_mapping();
  EXPECT_EQ(m.point_count, 68);
  const IbugMarker* left = nullptr;
  const IbugMarker* right = nullptr;
  for (const IbugMarker& k : m.markers) {
    if (k.feature_point.str() == "3.7") left = &k;
    if (k.feature_point.str() == "3.12") right = &k;
  }
  ASSERT_NE(left, nullptr);
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(left->points, std::vector<int>{45});  // 0-based
  EXPECT_EQ(right->points, std::vector<int>{36});
  EXPECT_EQ(left->marker, "3.7");
}

TEST_F(IbugPts, SequenceFromAFolderInNaturalOrderAveragesPoints) {
  write("seq/frame_10.pts", pts68(10));
  write("seq/frame_2.pts", pts68(2));
  write("seq/notes.txt", "ignored");
  const auto files = list_pts_sequence(dir_ / "seq");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].filename(), "frame_2.pts");
  const auto frames = read_pts_sequence(files, default_ibug_mapping(), 5, 25.0);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].frame, 5);
  EXPECT_EQ(frames[1].frame, 6);
  EXPECT_DOUBLE_EQ(frames[1].time_s, 0.04);
  bool found = false;
  for (const auto& o : frames[1].markers)
    if (o.feature_point.str() == "3.2") {  // midpoint of iBUG 38 and 39
      found = true;
      EXPECT_DOUBLE_EQ(o.position.x, 38.5 + 10);
      EXPECT_DOUBLE_EQ(o.position.y, 77.0);
      EXPECT_TRUE(o.valid);
    }
  EXPECT_TRUE(found);
}

TEST_F(IbugPts, SequenceFromAListAndItsErrors) {
  write("a.pts", pts68());
  write("b.pts", "n_points: 3\n{\n1 1\n2 2\n3 3\n}\n");
  EXPECT_EQ(list_pts_sequence(write("list.txt", "# frames\na.pts\n\na.pts\n")).size(), 2u);
  EXPECT_THROW(list_pts_sequence(write("empty.txt", "# nothing\n")), InputError);
  EXPECT_THROW(list_pts_sequence(write("wrong.txt", "a.png\n")), InputError);
  const auto short_files = list_pts_sequence(write("short.txt", "b.pts\n"));
  EXPECT_THROW(read_pts_sequence(short_files, default_ibug_mapping()), InputError);
  fs::create_directories(dir_ / "empty");
  EXPECT_THROW(list_pts_sequence(dir_ / "empty"), InputError);
}

TEST_F(IbugPts, MappingErrors) {
  EXPECT_THROW(read_ibug_mapping(write("m1.json", "{")), InputError);
  EXPECT_THROW(read_ibug_mapping(write("m2.json", R"({"markers": []})")), InputError);
  EXPECT_THROW(read_ibug_mapping(write("m3.json", R"({"markers": [{"fp": "99.1", "ibug": [1]}]})")),
               InputError);
  EXPECT_THROW(read_ibug_mapping(write("m4.json", R"({"markers": [{"fp": "3.7", "ibug": [0]}]})")),
               InputError);
  const auto m = read_ibug_mapping(
      write("ok.json",
            R"({"index_base": 0, "markers": [{"marker": "eye", "fp": "3.7", "ibug": [0, 4]}]})"));
  EXPECT_EQ(m.point_count, 5);
  EXPECT_EQ(m.markers[0].marker, "eye");
}

TEST(NaturalOrder, DigitRunsCompareAsNumbers) {
  EXPECT_TRUE(natural_less("f2", "f10"));
  EXPECT_FALSE(natural_less("f10", "f2"));
  EXPECT_TRUE(natural_less("000009.pts", "000010.pts"));
  EXPECT_TRUE(natural_less("a", "b"));
  EXPECT_FALSE(natural_less("a1", "a1"));
}

}  // namespace
}  // namespace rostro::eval
