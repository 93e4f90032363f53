// libFuzzer harness: the camera intrinsics reader (OpenCV FileStorage YAML, XML or JSON),
// from memory.

#include <string>

#include "calib/camera_intrinsics.hpp"
#include "fuzz/fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run([&] {
    rostro::calib::parse_intrinsics(std::string(rostro::fuzz::as_text(data, size)), "fuzz");
  });
}
