// Every kind of broken .fap gives an InputError naming the file, the line and what was
// expected; the validator lists every problem instead of the first.

#include <gtest/gtest.h>

#include "fap_test_util.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

struct Case {
  const char* name;
  std::string text;
  const char* line;      // ":N:" expected in the message
  const char* expected;  // a fragment of the message
};

std::vector<Case> cases() {
  const std::string m3 = test::mask_line({3});
  return {
      {"empty", "", "", "empty file"},
      {"header_fields", "2.1 name 25\n", ":1:", "expected 'version name fps frame_count'"},
      {"header_version", "v2 name 25 1\n", ":1:", "version"},
      {"header_fps", "2.1 name fast 1\n", ":1:", "fps"},
      {"header_count", "2.1 name 25 -3\n", ":1:", "frame count"},
      {"mask_length", "2.1 n 25 1\n0 1 0\n0\n", ":2:", "expected 68"},
      {"mask_value", "2.1 n 25 1\n" + test::mask_line({3}).replace(0, 1, "2") + "\n0 5\n",
       ":2:", "expected 0 or 1"},
      {"value_count", "2.1 n 25 1\n" + m3 + "\n0 5 6\n", ":3:", "expected 2"},
      {"non_number", "2.1 n 25 1\n" + m3 + "\n0 abc\n", ":3:", "expected a number"},
      {"frame_number", "2.1 n 25 1\n" + m3 + "\nx 5\n", ":3:", "frame number"},
      {"out_of_order", "2.1 n 25 2\n" + m3 + "\n1 5\n" + m3 + "\n1 6\n", ":5:", "out of order"},
      {"truncated_frames", "2.1 n 25 3\n" + m3 + "\n0 5\n", "", "truncated"},
      {"truncated_mask", "2.1 n 25 1\n" + m3 + "\n", "", "truncated"},
      {"extra_frames", "2.1 n 25 1\n" + m3 + "\n0 5\n" + m3 + "\n1 6\n", ":4:", "more frames"},
      {"viseme_short", "2.1 n 25 1\n" + test::mask_line({1}) + "\n0 1 2 3\n", ":3:", "expected 5"},
  };
}

TEST(FapMalformed, EachCaseNamesFileLineAndExpectation) {
  const auto dir = test::scratch_dir("fap-malformed");
  for (const Case& c : cases()) {
    const auto path = test::write_text(dir / (std::string(c.name) + ".fap"), c.text);
    const std::string error = test::read_error(path);
    ASSERT_FALSE(error.empty()) << c.name << " read without error";
    EXPECT_NE(error.find(path.string()), std::string::npos) << c.name << ": " << error;
    EXPECT_NE(error.find(c.line), std::string::npos) << c.name << ": " << error;
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.name << ": " << error;
  }
}

TEST(FapMalformed, ValidatorListsEveryProblem) {
  const auto dir = test::scratch_dir("fap-validate");
  const std::string m3 = test::mask_line({3});
  const auto path = test::write_text(dir / "v.fap", "2.1 n 25 4\n" + m3 + "\n0 abc\n" + m3 +
                                                        "\n1 5\n0 1\n2 7\n" + m3 + "\n3 1 2\n");
  const auto problems = validate_fap_file(path);
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_NE(problems[0].find(":3:"), std::string::npos) << problems[0];
  EXPECT_NE(problems[1].find(":6:"), std::string::npos) << problems[1];
  EXPECT_NE(problems[2].find(":9:"), std::string::npos) << problems[2];
}

TEST(FapMalformed, ValidFileHasNoProblems) {
  const auto dir = test::scratch_dir("fap-valid");
  const auto path =
      test::write_text(dir / "ok.fap", "2.1 n 25 1\n" + test::mask_line({3}) + "\n0 5\n");
  EXPECT_TRUE(validate_fap_file(path).empty());
}

TEST(FapMalformed, MissingFileAndUnknownExtension) {
  EXPECT_NE(test::read_error("/nonexistent/x.fap").find("cannot open"), std::string::npos);
  EXPECT_NE(test::read_error("notes.txt").find("unknown extension"), std::string::npos);
}

}  // namespace
}  // namespace rostro
