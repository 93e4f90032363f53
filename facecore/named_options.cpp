#include "facecore/named_options.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>

#include "facecore/error.hpp"

namespace rostro::detail {
namespace {

[[noreturn]] void bad_value(const std::string& what, const std::string& text, const char* want) {
  throw InputError(fmt::format("option {}: '{}' is not {}", what, text, want));
}

}  // namespace

void parse_option_value(const std::string& what, const std::string& text, double& out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') bad_value(what, text, "a number");
  out = v;
}

void parse_option_value(const std::string& what, const std::string& text, int& out) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < -2147483647L || v > 2147483647L)
    bad_value(what, text, "a whole number");
  out = static_cast<int>(v);
}

void parse_option_value(const std::string& what, const std::string& text, bool& out) {
  if (text == "true" || text == "1")
    out = true;
  else if (text == "false" || text == "0")
    out = false;
  else
    bad_value(what, text, "true or false");
}

std::pair<std::string, std::string> split_assignment(const std::string& owner,
                                                     const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("{} option '{}': expected NAME=VALUE", owner, assignment));
  return {assignment.substr(0, eq), assignment.substr(eq + 1)};
}

void unknown_option(const std::string& owner, const std::string& name,
                    const std::vector<std::string>& known) {
  throw InputError(
      fmt::format("{} has no option '{}' (known: {})", owner, name, fmt::join(known, ", ")));
}

}  // namespace rostro::detail
