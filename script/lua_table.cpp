#include "script/lua_table.hpp"

#include <cmath>
#include <cstring>
#include <lua.hpp>

#include "facecore/error.hpp"

namespace rostro::script {

LuaTable::LuaTable(lua_State* L, int index, std::string origin)
    : L_(L), index_(lua_absindex(L, index)), origin_(std::move(origin)) {
  if (!lua_istable(L_, index_))
    fail(std::string("should be a table, not a ") + luaL_typename(L_, index_));
}

void LuaTable::fail(const std::string& what) const {
  throw InputError(origin_ + ": " + what);
}

void LuaTable::allow(std::initializer_list<const char*> names, int positions) const {
  lua_pushnil(L_);
  while (lua_next(L_, index_) != 0) {
    lua_pop(L_, 1);
    bool known = false;
    std::string key;
    if (lua_type(L_, -1) == LUA_TSTRING) {
      key = lua_tostring(L_, -1);
      for (const char* n : names) known |= key == n;
    } else if (lua_isinteger(L_, -1)) {
      const lua_Integer i = lua_tointeger(L_, -1);
      known = i >= 1 && i <= positions;
      key = "[" + std::to_string(i) + "]";
    } else {
      key = std::string("a ") + luaL_typename(L_, -1) + " key";
    }
    if (!known) {
      std::string list;
      for (const char* n : names) list += (list.empty() ? "" : ", ") + std::string(n);
      lua_pop(L_, 1);
      fail("unknown field " + key + (list.empty() ? "" : " (expected " + list + ")"));
    }
  }
}

// Raw access: the tables are read after the script ran, outside Lua's protected mode, where a
// metamethod's error would end the program.
int LuaTable::push(const char* name) const {
  lua_pushstring(L_, name);
  return lua_rawget(L_, index_);
}
int LuaTable::push(int position) const {
  return lua_rawgeti(L_, index_, position);
}

bool LuaTable::has(const char* name) const {
  const bool present = push(name) != LUA_TNIL;
  lua_pop(L_, 1);
  return present;
}

long long LuaTable::length() const {
  return static_cast<long long>(lua_rawlen(L_, index_));
}

std::optional<double> LuaTable::number_on_top(const std::string& name) const {
  std::optional<double> out;
  const int type = lua_type(L_, -1);
  if (type == LUA_TNUMBER) out = lua_tonumber(L_, -1);
  lua_pop(L_, 1);
  if (type != LUA_TNIL && type != LUA_TNUMBER)
    fail(name + " should be a number, not a " + lua_typename(L_, type));
  if (out && !std::isfinite(*out)) fail(name + " should be a finite number");
  return out;
}

std::optional<std::string> LuaTable::string_on_top(const std::string& name) const {
  std::optional<std::string> out;
  const int type = lua_type(L_, -1);
  if (type == LUA_TSTRING) out = lua_tostring(L_, -1);
  lua_pop(L_, 1);
  if (type != LUA_TNIL && type != LUA_TSTRING)
    fail(name + " should be a string, not a " + lua_typename(L_, type));
  return out;
}

std::optional<double> LuaTable::number(const char* name) const {
  push(name);
  return number_on_top(name);
}
std::optional<double> LuaTable::number(int position) const {
  push(position);
  return number_on_top("entry " + std::to_string(position));
}
std::optional<std::string> LuaTable::string(const char* name) const {
  push(name);
  return string_on_top(name);
}
std::optional<std::string> LuaTable::string(int position) const {
  push(position);
  return string_on_top("entry " + std::to_string(position));
}

std::optional<bool> LuaTable::boolean(const char* name) const {
  const int type = push(name);
  const bool value = lua_toboolean(L_, -1);
  lua_pop(L_, 1);
  if (type == LUA_TNIL) return std::nullopt;
  if (type != LUA_TBOOLEAN) fail(std::string(name) + " should be true or false");
  return value;
}

}  // namespace rostro::script
