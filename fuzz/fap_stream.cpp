// libFuzzer harness: a FAP stream reader, from memory. Built three times, once per format
// (ROSTRO_FUZZ_FORMAT is Fap, Csv or Json): fuzz_fap_text, fuzz_fap_csv, fuzz_fap_json.

#include "facecore/fap_io.hpp"
#include "fuzz/fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rostro::fuzz::run([&] {
    auto source = rostro::open_fap_source("fuzz", rostro::fuzz::as_text(data, size),
                                          rostro::FapFormat::ROSTRO_FUZZ_FORMAT);
    rostro::FapFrame frame;
    while (source->next(frame)) {
    }
  });
}
