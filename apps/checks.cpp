#include "apps/checks.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "facecore/error.hpp"
#include "facecore/fap_frame.hpp"

namespace rostro::app {

void check_fps(double fps, const std::string& option) {
  if (!valid_fps(fps))
    throw InputError(fmt::format("{} {}: expected a frame rate in (0, {}]", option, fps, kMaxFps));
}

void check_seconds(double seconds, const std::string& option, double max) {
  if (!(seconds > 0.0 && seconds <= max))
    throw InputError(
        fmt::format("{} {}: expected a duration in (0, {}] seconds", option, seconds, max));
}

void check_not_an_input(std::initializer_list<NamedOutput> outputs,
                        std::initializer_list<std::string> inputs) {
  for (const NamedOutput& output : outputs) {
    if (output.path.empty()) continue;
    std::error_code ec;
    const auto out = std::filesystem::weakly_canonical(output.path, ec);
    if (ec) continue;  // an unreadable path: the write itself will say what is wrong
    for (const std::string& input : inputs) {
      if (input.empty()) continue;
      const auto in = std::filesystem::weakly_canonical(input, ec);
      if (!ec && in == out)
        throw InputError(fmt::format("{} {}: that is an input of this command; write elsewhere",
                                     output.option, output.path));
    }
  }
}

void warn_if_xface_cannot_read(const FapSink& sink, const std::string& path) {
  if (const std::string why = sink.xface_warning(); !why.empty())
    std::fprintf(stderr, "rostro: warning: %s: %s\n", path.c_str(), why.c_str());
}

}  // namespace rostro::app
