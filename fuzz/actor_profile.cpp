// libFuzzer harness: the actor profile JSON reader, from memory.

#include "calib/actor_profile.hpp"

#include <string>

#include "fuzz/fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run([&] {
    rostro::calib::actor_profile_from_json(std::string(rostro::fuzz::as_text(data, size)), "fuzz");
  });
}
