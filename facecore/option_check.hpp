#pragma once
// Range checks for an options struct's validate(): a value out of range throws InputError in
// one line that names the option and the value, e.g.
//   TrackerOptions::lk_window = 0: should be > 0
// Each check passes only a number inside the range (NaN fails every check).

#include <string>
#include <utility>

namespace rostro {

class OptionCheck {
 public:
  // `owner`: the struct's name, e.g. "TrackerOptions".
  explicit OptionCheck(std::string owner) : owner_(std::move(owner)) {}

  const OptionCheck& above(const char* name, double value, double bound) const;
  const OptionCheck& at_least(const char* name, double value, double least) const;
  const OptionCheck& within(const char* name, double value, double least, double most) const;
  const OptionCheck& positive(const char* name, double value) const {
    return above(name, value, 0);
  }
  const OptionCheck& not_negative(const char* name, double value) const {
    return at_least(name, value, 0);
  }

 private:
  [[noreturn]] void fail(const char* name, double value, const std::string& should) const;
  std::string owner_;
};

// `options` once options.validate() passed: for a constructor's member initialisers.
template <typename Options>
const Options& validated(const Options& options) {
  options.validate();
  return options;
}

}  // namespace rostro
