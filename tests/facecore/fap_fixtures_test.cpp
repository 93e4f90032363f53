// The eight Xface files from the field must read as they are, with their frame counts and
// values as written.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "facecore/fap_io.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

const char* kFixtures[] = {"anger", "beg", "disgust", "fear", "happy-for", "hate", "joy", "pride"};

// An independent, naive reading of the value lines: every second content line after the
// header, split on whitespace. Used to check values "as written".
std::vector<std::vector<double>> naive_value_lines(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> content;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    content.push_back(line);
  }
  std::vector<std::vector<double>> values;
  for (std::size_t i = 2; i < content.size(); i += 2) {
    std::stringstream ss(content[i]);
    std::vector<double> row;
    double v;
    while (ss >> v) row.push_back(v);
    values.push_back(row);
  }
  return values;
}

TEST(XfaceFixtures, AllEightReadWithTheirCountsAndValues) {
  const auto dir = test::xface_dir();
  if (dir.empty()) GTEST_SKIP() << "../shared/fixtures/xface not present; skipping fixture tests";
  for (const char* name : kFixtures) {
    SCOPED_TRACE(name);
    const auto path = dir / (std::string(name) + ".fap");
    const FapStream s = read_fap_stream(path);
    EXPECT_DOUBLE_EQ(s.header.fps, 25);
    EXPECT_TRUE(s.frames.size() == 107 || s.frames.size() == 108) << s.frames.size();
    EXPECT_EQ(static_cast<long>(s.frames.size()), s.header.frame_count);
    EXPECT_NE(s.header.name.find("\\"), std::string::npos) << "the name token is a Windows path";
    const auto expected = naive_value_lines(path);
    ASSERT_EQ(expected.size(), s.frames.size());
    for (std::size_t f = 0; f < s.frames.size(); ++f) {
      const FapFrame& frame = s.frames[f];
      EXPECT_EQ(frame.index, static_cast<long>(expected[f][0]));
      std::vector<double> got{static_cast<double>(frame.index)};
      for (int id = 1; id <= kFapCount; ++id) {
        if (!frame.has(id)) continue;
        if (id == kVisemeFap) {
          for (int v :
               {frame.viseme.select1, frame.viseme.select2, frame.viseme.blend, frame.viseme.def})
            got.push_back(v);
        } else if (id == kExpressionFap) {
          const auto& e = frame.expression;
          for (int v : {e.select1, e.intensity1, e.select2, e.intensity2, e.init_face, e.def})
            got.push_back(v);
        } else {
          got.push_back(frame.get(id));
        }
      }
      ASSERT_EQ(got, expected[f]) << "frame " << f;
    }
  }
}

TEST(XfaceFixtures, RewriteGivesTheSameStream) {
  const auto dir = test::xface_dir();
  if (dir.empty()) GTEST_SKIP() << "../shared/fixtures/xface not present; skipping fixture tests";
  const auto out = test::scratch_dir("xface-rewrite");
  for (const char* name : kFixtures) {
    SCOPED_TRACE(name);
    const FapStream original = read_fap_stream(dir / (std::string(name) + ".fap"));
    write_fap_stream(out / "copy.fap", original);
    const FapStream copy = read_fap_stream(out / "copy.fap");
    EXPECT_EQ(copy.header.name, original.header.name);
    ASSERT_EQ(copy.frames.size(), original.frames.size());
    for (std::size_t i = 0; i < copy.frames.size(); ++i)
      EXPECT_EQ(copy.frames[i], original.frames[i]);
  }
}

}  // namespace
}  // namespace rostro
