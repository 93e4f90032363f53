#pragma once
// Lua 5.4, embedded and sandboxed, for storyboard scripts. A script may compute (loops,
// functions, string, table, math, utf8, coroutine) but not reach the system: there is no
// os, io, debug, package, dofile or loadfile; load() takes text only; print() goes to stderr;
// require(NAME) loads NAME.lua from the script's own folder (or below it) and nothing else.
// math.random is seeded from the given seed, so a script gives the same scene every run.
// Errors come out as InputError "FILE:LINE: message".

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

struct lua_State;

namespace rostro::script {

struct SandboxOptions {
  std::size_t max_memory_bytes = std::size_t{512} << 20;  // allocations beyond fail
  long long max_instructions = 2'000'000'000;             // VM instructions per run
  bool allow_outside = false;  // require() and named files may leave the folder
  // Polled every 100000 instructions; true stops the script with an error (Ctrl-C).
  std::function<bool()> stop_requested;
};

class LuaSandbox {
 public:
  // `folder`: the only folder require() and sequence files read from. Throws InputError
  // when it does not exist.
  LuaSandbox(std::filesystem::path folder, std::uint64_t seed, SandboxOptions options = {});
  ~LuaSandbox();
  LuaSandbox(const LuaSandbox&) = delete;
  LuaSandbox& operator=(const LuaSandbox&) = delete;

  lua_State* state() { return L_; }

  // Runs a Lua file and leaves its first result (or nil) on the stack. `file` may be
  // anywhere (the storyboard itself); its name appears in messages as given.
  void run_file(const std::filesystem::path& file);
  // Loads a sequence file named by a script ("eyes.sb"): inside the folder, a Lua chunk that
  // returns a table, or a bare table constructor. Leaves the table on the stack.
  void load_sequence(const std::string& name, const std::string& origin);

  // Where `name` (relative to the folder) lives, refusing names that leave the folder:
  // throws InputError "<origin>: '<name>' is outside the script's folder".
  std::filesystem::path inside(const std::string& name, const std::string& origin) const;
  const std::filesystem::path& folder() const { return folder_; }
  // How the folder's files are named in messages: as the storyboard was given.
  std::string display(const std::filesystem::path& inside_path) const;

  struct Budget;  // memory and instructions used so far (lua_sandbox.cpp)

 private:
  void call(int args, const std::string& what);
  static int require(lua_State* L);

  std::filesystem::path folder_;     // canonical
  std::filesystem::path shown_dir_;  // the folder as the user wrote it
  bool allow_outside_ = false;
  std::unique_ptr<Budget> budget_;
  lua_State* L_ = nullptr;
};

}  // namespace rostro::script
