// libFuzzer harness: the marker layout JSON reader, from memory.

#include "tracking/layout.hpp"

#include <string>

#include "fuzz/fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run([&] {
    rostro::tracking::parse_layout(std::string(rostro::fuzz::as_text(data, size)), "fuzz");
  });
}
