// Reading storyboards: the seed's layout (parts inline or in .sb files, "none"), sequencing by
// duration, and one clear line for each kind of bad entry.

#include "script/storyboard_reader.hpp"

#include <gtest/gtest.h>

#include "facecore/error.hpp"
#include "script_test_util.hpp"

namespace rostro::script {
namespace {

std::string error_of(const std::string& body) {
  const auto dir = test::scratch("reader-errors");
  const auto story = test::write(dir / "story.lua", body);
  try {
    read_storyboard(story, 1);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StoryboardReader, SeedLayoutWithSequenceFilesAndNone) {
  const auto dir = test::scratch("reader-seed");
  test::write(dir / "expressions.sb", "{ {'joy', 2.0, 0.5}, {'surprise', 1.0} }\n");
  test::write(dir / "eyes.sb", "return { {'blinks'}, {'look', 'left', at = 1, duration = 0.5} }\n");
  const auto story = test::write(dir / "story.lua",
                                 "storyboard = { speech = 'none', expressions = 'expressions.sb',\n"
                                 "  eyes = 'eyes.sb', head = { {'nod', at = 0.5} }, fps = 30 }\n");
  const Storyboard b = read_storyboard(story, 1);
  EXPECT_TRUE(b.speech.empty());
  ASSERT_EQ(b.expressions.size(), 2u);
  EXPECT_EQ(b.expressions[0].expression, 1);
  EXPECT_DOUBLE_EQ(b.expressions[0].intensity, 0.5);
  EXPECT_DOUBLE_EQ(b.expressions[0].end, 2.0);
  // Without `at`, an entry follows the one before it.
  EXPECT_DOUBLE_EQ(b.expressions[1].at, 2.0);
  EXPECT_DOUBLE_EQ(b.expressions[1].end, 3.0);
  EXPECT_EQ(b.expressions[1].origin, (dir / "expressions.sb").string() + "[2]");
  ASSERT_EQ(b.eyes.size(), 2u);
  EXPECT_EQ(b.eyes[1].kind, EyeKind::Look);
  EXPECT_GT(b.eyes[1].path.at(0).yaw_deg, 0.0);  // the character's left
  ASSERT_EQ(b.head.size(), 1u);
  EXPECT_DOUBLE_EQ(b.head[0].end, 1.1);  // a nod lasts 0.6 s by default
  EXPECT_DOUBLE_EQ(b.fps, 30.0);
}

TEST(StoryboardReader, ScriptsComputeTheirEntries) {
  const auto story = test::story(
      "reader-compute", "loop.lua",
      "local eyes = {}\nfor i = 0, 9 do\n"
      "  eyes[#eyes + 1] = {'look', i % 2 == 0 and 'left' or 'right', at = 2 * i, duration = 1}\n"
      "end\nreturn { eyes = eyes }\n");
  const Storyboard b = read_storyboard(story, 1);
  ASSERT_EQ(b.eyes.size(), 10u);
  EXPECT_DOUBLE_EQ(b.eyes[9].at, 18.0);
  EXPECT_LT(b.eyes[9].path[0].yaw_deg, 0.0);
}

TEST(StoryboardReader, BadEntriesGiveOneLineNamingTheEntry) {
  struct Case {
    const char* body;
    const char* message;
  };
  const Case cases[] = {
      {"storyboard = { expressions = { {'joy', 1}, {'smug', 1} } }",
       "story.lua: expressions[2]: unknown expression 'smug'"},
      {"storyboard = { expressions = { {'joy', -1} } }", "expressions[1]: negative duration"},
      {"storyboard = { eyes = { {'look', 'left', at = 2}, {'blink', at = 1} } }",
       "eyes[2]: time runs backwards"},
      {"storyboard = { expressions = { {'joy', at = 2, to = 1} } }", "time runs backwards"},
      {"storyboard = { eyes = { {'wink'} } }", "unknown eye behaviour 'wink'"},
      {"storyboard = { head = { {'bow'} } }", "unknown head action 'bow'"},
      {"storyboard = { eyes = { {'saccades', 'bored'} } }", "unknown saccade style"},
      {"storyboard = { expressions = { {'joy', durration = 1} } }", "unknown field durration"},
      {"storyboard = { eyes = { {'look', 'sideways'} } }", "unknown direction 'sideways'"},
      {"x = 1", "sets no storyboard"},
      {"storyboard = { speech = { text = 'x', sound = '../a.wav' } }",
       "outside the script's folder"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.body);
    EXPECT_NE(e.find(c.message), std::string::npos) << c.body << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace rostro::script
