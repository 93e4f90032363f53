#include "script/lua_sandbox.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <lua.hpp>
#include <sstream>

#include "facecore/error.hpp"

namespace rostro::script {

struct LuaSandbox::Budget {
  std::size_t used = 0;
  std::size_t max_memory = 0;  // the limit while a script runs
  std::size_t limit = 0;       // the configured one
  long long instructions = 0;
  long long max_instructions = 0;
  std::function<bool()> stop_requested;
};

namespace {

constexpr int kHookEvery = 100000;  // instructions between two budget checks
constexpr const char* kLoadedKey = "rostro.loaded";

void* budget_alloc(void* ud, void* ptr, std::size_t old_size, std::size_t new_size) {
  auto* b = static_cast<LuaSandbox::Budget*>(ud);
  const std::size_t old = ptr ? old_size : 0;
  if (new_size == 0) {
    std::free(ptr);
    b->used -= old;
    return nullptr;
  }
  if (new_size > old && b->used - old + new_size > b->max_memory) return nullptr;
  void* p = std::realloc(ptr, new_size);
  if (p) b->used = b->used - old + new_size;
  return p;
}

void budget_hook(lua_State* L, lua_Debug* ar) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  auto* b = static_cast<LuaSandbox::Budget*>(ud);
  b->instructions += kHookEvery;
  if (b->stop_requested && b->stop_requested()) {
    lua_getinfo(L, "Sl", ar);
    lua_pushfstring(L, "%s:%d: stopped", ar->short_src, ar->currentline);
    lua_error(L);
  }
  if (b->instructions <= b->max_instructions) return;
  lua_getinfo(L, "Sl", ar);
  lua_pushfstring(L, "%s:%d: the script ran more than %I instructions (an endless loop?)",
                  ar->short_src, ar->currentline, static_cast<lua_Integer>(b->max_instructions));
  lua_error(L);
}

// "FILE:LINE: message" already?
bool has_position(const std::string& m) {
  const auto colon = m.find(':');
  if (colon == std::string::npos || colon == 0) return false;
  std::size_t i = colon + 1;
  const std::size_t digits = i;
  while (i < m.size() && std::isdigit(static_cast<unsigned char>(m[i]))) ++i;
  return i > digits && i < m.size() && m[i] == ':';
}

// pcall's message handler: one line, prefixed with the innermost Lua position when the
// error did not carry one (error(msg, 0), errors from C functions).
int message_handler(lua_State* L) {
  const char* raw = lua_tostring(L, 1);
  std::string message;
  {
    if (raw) {
      message = raw;
    } else if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING) {
      message = lua_tostring(L, -1);
    } else {
      message = std::string("error object is a ") + luaL_typename(L, 1) + " value";
    }
    std::replace(message.begin(), message.end(), '\n', ' ');
    if (!has_position(message)) {
      lua_Debug ar;
      for (int level = 1; lua_getstack(L, level, &ar); ++level) {
        lua_getinfo(L, "Sl", &ar);
        if (ar.currentline > 0) {
          message =
              std::string(ar.short_src) + ":" + std::to_string(ar.currentline) + ": " + message;
          break;
        }
      }
    }
    lua_pushstring(L, message.c_str());
  }
  return 1;
}

int sandbox_print(lua_State* L) {
  const int n = lua_gettop(L);
  for (int i = 1; i <= n; ++i) {
    std::size_t len = 0;
    const char* s = luaL_tolstring(L, i, &len);
    if (i > 1) std::fputc('\t', stderr);
    std::fwrite(s, 1, len, stderr);
    lua_pop(L, 1);
  }
  std::fputc('\n', stderr);
  return 0;
}

// load() with text chunks only: a binary chunk can crash the interpreter.
int sandbox_load(lua_State* L) {
  if (lua_gettop(L) < 3) lua_settop(L, 2);
  lua_pushstring(L, "t");
  if (lua_gettop(L) > 3) lua_replace(L, 3);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
  return lua_gettop(L);
}

bool read_file(const std::filesystem::path& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

}  // namespace

LuaSandbox::LuaSandbox(std::filesystem::path folder, std::uint64_t seed, SandboxOptions options)
    : shown_dir_(folder),
      allow_outside_(options.allow_outside),
      budget_(std::make_unique<Budget>()) {
  std::error_code ec;
  folder_ = std::filesystem::canonical(folder.empty() ? "." : folder, ec);
  if (ec) throw InputError(folder.string() + ": the script's folder does not exist");
  budget_->limit = options.max_memory_bytes;
  budget_->max_memory = options.max_memory_bytes;
  budget_->max_instructions = options.max_instructions;
  budget_->stop_requested = options.stop_requested;
  L_ = lua_newstate(budget_alloc, budget_.get());
  if (!L_) throw std::runtime_error("cannot start Lua: out of memory");

  const std::pair<const char*, lua_CFunction> libs[] = {
      {LUA_GNAME, luaopen_base},        {LUA_TABLIBNAME, luaopen_table},
      {LUA_STRLIBNAME, luaopen_string}, {LUA_MATHLIBNAME, luaopen_math},
      {LUA_UTF8LIBNAME, luaopen_utf8},  {LUA_COLIBNAME, luaopen_coroutine}};
  for (const auto& [name, open] : libs) {
    luaL_requiref(L_, name, open, 1);
    lua_pop(L_, 1);
  }
  for (const char* name : {"dofile", "loadfile"}) {
    lua_pushnil(L_);
    lua_setglobal(L_, name);
  }
  lua_pushcfunction(L_, sandbox_print);
  lua_setglobal(L_, "print");
  lua_getglobal(L_, "load");
  lua_pushcclosure(L_, sandbox_load, 1);
  lua_setglobal(L_, "load");
  lua_pushlightuserdata(L_, this);
  lua_pushcclosure(L_, &LuaSandbox::require, 1);
  lua_setglobal(L_, "require");
  lua_newtable(L_);
  lua_setfield(L_, LUA_REGISTRYINDEX, kLoadedKey);

  // Deterministic math.random: the same seed, the same scene.
  lua_getglobal(L_, LUA_MATHLIBNAME);
  lua_getfield(L_, -1, "randomseed");
  lua_pushinteger(L_, static_cast<lua_Integer>(seed));
  lua_call(L_, 1, 0);
  lua_pop(L_, 1);

  lua_sethook(L_, budget_hook, LUA_MASKCOUNT, kHookEvery);
}

LuaSandbox::~LuaSandbox() {
  if (L_) lua_close(L_);
}

std::filesystem::path LuaSandbox::inside(const std::string& name, const std::string& origin) const {
  const std::filesystem::path p = std::filesystem::weakly_canonical(folder_ / name);
  const std::filesystem::path rel = p.lexically_relative(folder_);
  if (name.empty() || ((rel.empty() || *rel.begin() == "..") && !allow_outside_))
    throw InputError(origin + ": '" + name + "' is outside the script's folder (" +
                     shown_dir_.string() + "; --allow-outside permits it)");
  return p;
}

std::string LuaSandbox::display(const std::filesystem::path& inside_path) const {
  return (shown_dir_ / inside_path.lexically_relative(folder_)).lexically_normal().string();
}

void LuaSandbox::call(int args, const std::string& what) {
  const int base = lua_gettop(L_) - args;  // the function's slot
  lua_pushcfunction(L_, message_handler);
  lua_insert(L_, base);
  budget_->instructions = 0;
  budget_->max_memory = budget_->limit;
  const int status = lua_pcall(L_, args, 1, base);
  // Reading the results happens outside protected mode, where a failed allocation would end
  // the program: the limit applies to scripts only.
  budget_->max_memory = std::numeric_limits<std::size_t>::max();
  lua_remove(L_, base);
  if (status != LUA_OK) {
    std::string message = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : what + ": Lua error";
    lua_pop(L_, 1);
    if (status == LUA_ERRMEM) message = what + ": the script used more memory than allowed";
    throw InputError(message);
  }
}

void LuaSandbox::run_file(const std::filesystem::path& file) {
  std::string text;
  if (!read_file(file, text)) throw InputError(file.string() + ": cannot read the script");
  const std::string chunk = "@" + file.string();
  if (luaL_loadbufferx(L_, text.data(), text.size(), chunk.c_str(), "t") != LUA_OK) {
    std::string message = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    throw InputError(message);
  }
  call(0, file.string());
}

void LuaSandbox::load_sequence(const std::string& name, const std::string& origin) {
  const std::filesystem::path path = inside(name, origin);
  std::string text;
  if (!read_file(path, text))
    throw InputError(origin + ": cannot read the sequence file '" + name + "'");
  const std::string shown = display(path);
  const std::string chunk = "@" + shown;
  if (luaL_loadbufferx(L_, text.data(), text.size(), chunk.c_str(), "t") != LUA_OK) {
    // A bare table constructor, as the seed's .sb files hold, is a chunk once returned.
    std::string first = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    const std::string returned = "return " + text;
    if (luaL_loadbufferx(L_, returned.data(), returned.size(), chunk.c_str(), "t") != LUA_OK) {
      lua_pop(L_, 1);
      throw InputError(first);
    }
  }
  call(0, shown);
  if (!lua_istable(L_, -1)) {
    lua_pop(L_, 1);
    throw InputError(shown + ": a sequence file should return a table of entries");
  }
}

int LuaSandbox::require(lua_State* L) {
  auto* self = static_cast<LuaSandbox*>(lua_touserdata(L, lua_upvalueindex(1)));
  const char* name = luaL_checkstring(L, 1);
  lua_getfield(L, LUA_REGISTRYINDEX, kLoadedKey);
  lua_getfield(L, -1, name);
  if (!lua_isnil(L, -1)) return 1;
  lua_pop(L, 1);

  // C++ objects live in this block only: lua_error() below does not unwind them.
  bool failed = false;
  {
    std::string relative = name;
    std::replace(relative.begin(), relative.end(), '.', '/');
    relative += ".lua";
    std::string text;
    try {
      const std::filesystem::path path = self->inside(relative, "require");
      if (!read_file(path, text)) {
        lua_pushfstring(L, "require '%s': no file %s", name, self->display(path).c_str());
        failed = true;
      } else {
        const std::string chunk = "@" + self->display(path);
        failed = luaL_loadbufferx(L, text.data(), text.size(), chunk.c_str(), "t") != LUA_OK;
      }
    } catch (const std::exception&) {
      lua_pushfstring(L, "require '%s': outside the script's folder %s", name,
                      self->shown_dir_.string().c_str());
      failed = true;
    }
  }
  if (failed) {
    if (has_position(lua_tostring(L, -1))) return lua_error(L);
    luaL_where(L, 1);
    lua_insert(L, -2);
    lua_concat(L, 2);
    return lua_error(L);
  }
  lua_pushstring(L, name);
  lua_call(L, 1, 1);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    lua_pushboolean(L, 1);
  }
  lua_pushvalue(L, -1);
  lua_setfield(L, -3, name);
  return 1;
}

}  // namespace rostro::script
