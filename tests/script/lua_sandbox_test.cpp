// The sandbox: scripts compute but cannot reach the system or files outside their folder.

#include "script/lua_sandbox.hpp"

#include <gtest/gtest.h>

#include <lua.hpp>

#include "facecore/error.hpp"
#include "script_test_util.hpp"

namespace rostro::script {
namespace {

// The error message running `story` gives, or "" when it runs.
std::string error_of(const std::filesystem::path& story, SandboxOptions options = {}) {
  try {
    LuaSandbox sandbox(story.parent_path(), 1, options);
    sandbox.run_file(story);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LuaSandbox, RefusesOsIoAndTheLoaders) {
  const auto dir = test::scratch("sandbox-refuses");
  const auto victim = test::write(dir / "victim.txt", "keep me\n");
  const auto remove =
      test::write(dir / "remove.lua", "-- tries to delete\nos.remove('victim.txt')\n");
  EXPECT_EQ(error_of(remove).rfind(remove.string() + ":2: ", 0), 0u) << error_of(remove);
  EXPECT_NE(error_of(remove).find("'os'"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(victim));

  const auto open = test::write(dir / "open.lua", "local f = io.open('new.txt', 'w')\n");
  EXPECT_NE(error_of(open).find("open.lua:1: "), std::string::npos) << error_of(open);
  EXPECT_FALSE(std::filesystem::exists(dir / "new.txt"));

  for (const char* call : {"dofile('victim.txt')", "loadfile('victim.txt')", "debug.getinfo(1)",
                           "package.loadlib('x', 'y')"}) {
    const auto f = test::write(dir / "loader.lua", std::string("\n") + call + "\n");
    EXPECT_NE(error_of(f).find("loader.lua:2: "), std::string::npos) << call << ": " << error_of(f);
  }
}

TEST(LuaSandbox, RequireStaysInsideTheFolder) {
  const auto root = test::scratch("sandbox-require");
  test::write(root / "secret.lua", "return { leaked = true }\n");
  const auto dir = root / "story";
  test::write(dir / "lib" / "moves.lua", "return { wave = function() return 42 end }\n");
  const auto inside = test::write(dir / "inside.lua",
                                  "local m = require('lib.moves')\nassert(m.wave() == 42)\n"
                                  "assert(require('lib.moves') == m)\n");
  EXPECT_EQ(error_of(inside), "");

  const auto outside = test::write(dir / "outside.lua", "\n\nlocal s = require('..secret')\n");
  const std::string e = error_of(outside);
  EXPECT_NE(e.find("outside.lua:3: "), std::string::npos) << e;
  EXPECT_NE(e.find("outside the script's folder"), std::string::npos) << e;
  const auto dotted = test::write(dir / "dotted.lua", "require('../secret')\n");
  EXPECT_NE(error_of(dotted).find("outside the script's folder"), std::string::npos);
  const auto absolute =
      test::write(dir / "absolute.lua", "require('" + (root / "secret").string() + "')\n");
  EXPECT_NE(error_of(absolute).find("outside"), std::string::npos) << error_of(absolute);

  // A symbolic link inside the folder that points out of it is outside too.
  std::filesystem::create_symlink(root / "secret.lua", dir / "link.lua");
  const auto link = test::write(dir / "link_user.lua", "require('link')\n");
  EXPECT_NE(error_of(link).find("outside"), std::string::npos) << error_of(link);

  SandboxOptions allow;
  allow.allow_outside = true;
  EXPECT_EQ(error_of(link, allow), "");
}

TEST(LuaSandbox, SyntaxAndRuntimeErrorsNameFileAndLine) {
  const auto dir = test::scratch("sandbox-errors");
  const auto syntax = test::write(dir / "syntax.lua", "local a = 1\nlocal b = = 2\n");
  EXPECT_EQ(error_of(syntax).rfind(syntax.string() + ":2: ", 0), 0u) << error_of(syntax);
  const auto runtime = test::write(dir / "runtime.lua", "local t = nil\n\nprint(t.x)\n");
  EXPECT_EQ(error_of(runtime).rfind(runtime.string() + ":3: ", 0), 0u) << error_of(runtime);
  const auto raw = test::write(dir / "raw.lua", "error('two\\nlines', 0)\n");
  EXPECT_EQ(error_of(raw), raw.string() + ":1: two lines");
  const auto module = test::write(dir / "m.lua", "return 1 + nil\n");
  const auto user = test::write(dir / "user.lua", "require('m')\n");
  EXPECT_NE(error_of(user).find("m.lua:1: "), std::string::npos) << error_of(user);
}

TEST(LuaSandbox, LoadTakesTextOnlyAndEndlessLoopsStop) {
  const auto dir = test::scratch("sandbox-limits");
  const auto binary = test::write(
      dir / "binary.lua", "local f = load(string.dump(function() return 1 end))\nassert(f)\n");
  EXPECT_NE(error_of(binary).find("binary.lua:2: "), std::string::npos) << error_of(binary);
  const auto text = test::write(dir / "text.lua", "assert(load('return 1 + 1')() == 2)\n");
  EXPECT_EQ(error_of(text), "");

  SandboxOptions small;
  small.max_instructions = 1'000'000;
  const auto loop = test::write(dir / "loop.lua", "local i = 0\nwhile true do i = i + 1 end\n");
  EXPECT_NE(error_of(loop, small).find("loop.lua:2: the script ran more than"), std::string::npos)
      << error_of(loop, small);
  SandboxOptions stop;
  int polls = 0;
  stop.stop_requested = [&polls] { return ++polls == 3; };  // Ctrl-C during the loop
  EXPECT_NE(error_of(loop, stop).find("loop.lua:2: stopped"), std::string::npos)
      << error_of(loop, stop);
  small.max_memory_bytes = 4 << 20;
  const auto hog = test::write(dir / "hog.lua", "local s = string.rep('x', 64 * 1024 * 1024)\n");
  EXPECT_NE(error_of(hog, small).find("memory"), std::string::npos) << error_of(hog, small);
}

TEST(LuaSandbox, MathRandomFollowsTheSeed) {
  const auto dir = test::scratch("sandbox-random");
  const auto story = test::write(dir / "r.lua", "return math.random(1, 1000000)\n");
  const auto draw = [&](std::uint64_t seed) {
    LuaSandbox sandbox(dir, seed);
    sandbox.run_file(story);
    return lua_tointeger(sandbox.state(), -1);
  };
  EXPECT_EQ(draw(7), draw(7));
  EXPECT_NE(draw(7), draw(8));
}

}  // namespace
}  // namespace rostro::script
