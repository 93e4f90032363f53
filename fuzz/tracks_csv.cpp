// libFuzzer harness: the tracks CSV reader, from memory.

#include "tracking/tracks_csv.hpp"

#include "fuzz/fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run([&] {
    rostro::tracking::TracksReader reader("fuzz", rostro::fuzz::as_text(data, size));
    rostro::tracking::TrackedFrame frame;
    while (reader.next(frame)) {
    }
  });
}
