#include "facecore/option_check.hpp"

#include <fmt/format.h>

#include "facecore/error.hpp"

namespace rostro {

const OptionCheck& OptionCheck::above(const char* name, double value, double bound) const {
  if (!(value > bound)) fail(name, value, fmt::format("> {:g}", bound));
  return *this;
}

const OptionCheck& OptionCheck::at_least(const char* name, double value, double least) const {
  if (!(value >= least)) fail(name, value, fmt::format(">= {:g}", least));
  return *this;
}

const OptionCheck& OptionCheck::within(const char* name, double value, double least,
                                       double most) const {
  if (!(value >= least && value <= most))
    fail(name, value, fmt::format("in {:g}..{:g}", least, most));
  return *this;
}

void OptionCheck::fail(const char* name, double value, const std::string& should) const {
  throw InputError(fmt::format("{}::{} = {:g}: should be {}", owner_, name, value, should));
}

}  // namespace rostro
