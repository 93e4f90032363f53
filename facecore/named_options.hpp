#pragma once
// An options struct's scalar fields set by name, "NAME=VALUE" (`rostro eval suite
// --tracker-option eyes.max_dot_growth_found=1.3`): each struct lists its fields once, with
// ROSTRO_NAMED_OPTION, and set_named_option() applies one assignment. Values are numbers, or
// true/false for a switch; a bad name or value throws InputError in one line. Ranges are the
// struct's validate()'s business.

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace rostro {

template <typename Options>
struct NamedOption {
  std::string name;  // the field's path in the struct, e.g. "dots.min_diameter_px"
  std::function<void(Options&, const std::string& value)> set;
};

namespace detail {
// `text` as the field's type, or InputError naming `what` (the option) and the text.
void parse_option_value(const std::string& what, const std::string& text, double& out);
void parse_option_value(const std::string& what, const std::string& text, int& out);
void parse_option_value(const std::string& what, const std::string& text, bool& out);
// "NAME=VALUE" split, or InputError naming `owner`.
std::pair<std::string, std::string> split_assignment(const std::string& owner,
                                                     const std::string& assignment);
[[noreturn]] void unknown_option(const std::string& owner, const std::string& name,
                                 const std::vector<std::string>& known);
}  // namespace detail

template <typename Options, typename T>
NamedOption<Options> named_option(std::string name, T& (*field)(Options&)) {
  return {name, [name, field](Options& o, const std::string& value) {
            detail::parse_option_value(name, value, field(o));
          }};
}

// One table row: ROSTRO_NAMED_OPTION(TrackerOptions, dots.min_diameter_px).
#define ROSTRO_NAMED_OPTION(Options, path) \
  ::rostro::named_option<Options>(         \
      #path, +[](Options & o) -> auto& { return o.path; })

// Applies "NAME=VALUE" to `options`. `owner` names the struct in errors ("TrackerOptions").
template <typename Options>
void set_named_option(Options& options, const std::vector<NamedOption<Options>>& table,
                      const std::string& owner, const std::string& assignment) {
  const auto [name, value] = detail::split_assignment(owner, assignment);
  std::vector<std::string> known;
  for (const NamedOption<Options>& o : table) {
    if (o.name == name) return o.set(options, value);
    known.push_back(o.name);
  }
  detail::unknown_option(owner, name, known);
}

}  // namespace rostro
