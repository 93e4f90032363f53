#pragma once
// Reading one Lua table (a storyboard entry) with its fields checked: known names only,
// numbers finite, strings where strings belong. Every message names the entry:
// "story.lua: expressions[2]: intensity should be a number in 0..1".

#include <initializer_list>
#include <optional>
#include <string>

struct lua_State;

namespace rostro::script {

class LuaTable {
 public:
  // The table at stack `index` (made absolute); throws InputError when it is not a table.
  LuaTable(lua_State* L, int index, std::string origin);

  // Throws when a key is neither one of `names` nor a position 1..`positions`.
  void allow(std::initializer_list<const char*> names, int positions) const;
  bool has(const char* name) const;
  std::optional<double> number(const char* name) const;
  std::optional<double> number(int position) const;
  std::optional<std::string> string(const char* name) const;
  std::optional<std::string> string(int position) const;
  std::optional<bool> boolean(const char* name) const;
  // Pushes field `name` (or position) and returns its Lua type; the caller pops it.
  int push(const char* name) const;
  int push(int position) const;
  // Number of array entries (the border, #t).
  long long length() const;

  int index() const { return index_; }
  lua_State* state() const { return L_; }
  const std::string& origin() const { return origin_; }
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::optional<double> number_on_top(const std::string& name) const;
  std::optional<std::string> string_on_top(const std::string& name) const;

  lua_State* L_;
  int index_;
  std::string origin_;
};

}  // namespace rostro::script
