#pragma once
// Exporter for 2D animation: the mouth shapes of Rhubarb Lip Sync (A-F basic, G-H and X
// extended) timed from any phoneme sequence rostro animates, written in Rhubarb's own
// output formats so the tools that read Rhubarb read rostro (docs/speech.md, "Mouth cues").

#include <filesystem>
#include <string>
#include <vector>

#include "speech/phoneme.hpp"

namespace rostro::speech {

struct MouthCue {
  double start_s = 0.0;
  double end_s = 0.0;
  char shape = 'X';  // A closed (p b m), B teeth (most consonants, ee), C open (e), D wide
                     // (a), E rounded (o), F puckered (u, w), G f/v, H l, X rest
};

// The shape for one phoneme: from its MPEG-4 viseme, with l (H) split from n.
char mouth_shape(const Phoneme& phoneme);

// Cues covering [0, duration_s] on a 10 ms grid (Rhubarb's resolution): consecutive equal
// shapes merged, no cue shorter than one step.
std::vector<MouthCue> mouth_cues(const std::vector<Phoneme>& phonemes, double duration_s);

enum class CueFormat { Tsv, Json, Xml, Dat };

// By extension: .tsv, .json, .xml, .dat. Throws InputError for anything else.
CueFormat cue_format_for(const std::filesystem::path& path);

// The file's text. `sound_file` goes into the json and xml metadata; `dat_fps` sets the
// frame numbers of .dat (Moho switch data; Rhubarb accepts 24-100).
std::string format_cues(const std::vector<MouthCue>& cues, CueFormat format,
                        const std::string& sound_file, double duration_s, double dat_fps = 24.0);

// Writes through a temporary file: the destination is whole or untouched.
void write_cues(const std::filesystem::path& path, const std::vector<MouthCue>& cues,
                const std::string& sound_file, double duration_s, double dat_fps = 24.0);

}  // namespace rostro::speech
