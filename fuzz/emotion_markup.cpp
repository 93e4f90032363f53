// libFuzzer harness: the emotion markup parser of `rostro speak` text.

#include "speech/emotion_markup.hpp"

#include "fuzz/fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run(
      [&] { rostro::speech::parse_emotion_markup(rostro::fuzz::as_text(data, size), "fuzz"); });
}
