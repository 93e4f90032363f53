#include "eval/suite.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

std::filesystem::path temp_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("rostro_suite_test_" + name);
  std::ofstream(path) << text;
  return path;
}

std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Suite, DefaultSuiteHasTheIssuesScenarios) {
  const SuiteDefinition d = load_suite(default_suite_path());
  ASSERT_EQ(d.scenarios.size(), 6u);
  const SuiteScenario* turns = nullptr;
  const SuiteScenario* fps60 = nullptr;
  for (const auto& s : d.scenarios) {
    if (s.name == "turns") turns = &s;
    if (s.name == "fps60") fps60 = &s;
  }
  ASSERT_NE(turns, nullptr);
  EXPECT_EQ(turns->synth.yaw_deg, 25);
  EXPECT_EQ(turns->synth.pitch_deg, 15);
  EXPECT_EQ(turns->seconds, 4);  // the file's default
  ASSERT_NE(fps60, nullptr);
  EXPECT_EQ(fps60->fps, 60);
}

TEST(Suite, UnknownKeyIsNamed) {
  const auto path = temp_file("bad.json", R"({"scenarios": [{"name": "a", "yawn": 3}]})");
  try {
    load_suite(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("yawn"), std::string::npos) << e.what();
  }
}

TEST(Suite, MarkdownSectionIsReplacedAndTheRestKept) {
  const auto path = temp_file("doc.md",
                              "# Title\n\nIntro.\n\n## Suite table\n\nold table\n\n"
                              "## Closed loop: FAPs\n\nkept\n");
  replace_markdown_section(path, "## Suite table", "new table\n");
  const std::string text = read_all(path);
  EXPECT_EQ(text,
            "# Title\n\nIntro.\n\n## Suite table\n\nnew table\n\n## Closed loop: FAPs\n\nkept\n");
  replace_markdown_section(path, "## Other", "appended\n");
  EXPECT_NE(read_all(path).find("kept\n\n## Other\n\nappended\n"), std::string::npos);
}

TEST(Suite, LossTableHasAColumnPerReasonCounted) {
  SuiteRow a, b;
  a.name = "still", a.title = "still head";
  b.name = "turns", b.title = "head turns";
  a.lost_by[static_cast<std::size_t>(tracking::LostReason::Jump)] = 3;
  b.lost_by[static_cast<std::size_t>(tracking::LostReason::LidBand)] = 12;
  EXPECT_EQ(loss_table_markdown({a, b}),
            "| scenario | jump | lid band |\n|---|---:|---:|\n| still head | 3 | 0 |\n"
            "| head turns | 0 | 12 |\n");
  EXPECT_EQ(loss_table_text({a, b}),
            "scenario     jump lid band\nstill           3        0\nturns           0       12\n");
}

}  // namespace
}  // namespace rostro::eval
