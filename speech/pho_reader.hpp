#pragma once
// Recognition stage for recorded or externally synthesised speech: an MBROLA .pho file
// ("phoneme duration_ms [position% pitch_hz]..." per line, ';' comments, '_' silence).
// Phoneme times are the running sum of the durations from audio time 0.

#include <filesystem>
#include <istream>
#include <string>
#include <vector>

#include "speech/phoneme.hpp"

namespace rostro::speech {

// Throws InputError "file:line: what" for a malformed line.
std::vector<RawPhoneme> read_pho(const std::filesystem::path& path);
std::vector<RawPhoneme> parse_pho(std::istream& in, const std::string& name);

}  // namespace rostro::speech
