// libFuzzer harness: the MBROLA .pho reader, from memory.

#include <sstream>
#include <string>

#include "fuzz/fuzz_util.hpp"
#include "speech/pho_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run([&] {
    std::istringstream in{std::string(rostro::fuzz::as_text(data, size))};
    rostro::speech::parse_pho(in, "fuzz");
  });
}
