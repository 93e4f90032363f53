#pragma once
// Shared by the libFuzzer harnesses: each reads one input from memory with a reader rostro
// uses on files. Bad input must end in rostro::InputError (one clear line for the user);
// anything else (another exception, a crash, a sanitizer report) is a finding.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "facecore/error.hpp"

namespace rostro::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

template <typename Read>
int run(Read read) {
  try {
    read();
  } catch (const InputError&) {
    // The expected way to reject bad input.
  }
  return 0;
}

}  // namespace rostro::fuzz
