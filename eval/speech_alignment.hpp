#pragma once
// `rostro eval alignment`: how well `rostro speak --audio --text` places phonemes in a
// recording. Each case is a recording whose phoneme times are known and which the alignment's
// reference (espeak-ng's default voice at its default rate) did not produce: other espeak-ng
// voices, rates and pitches, added noise, other sample rates, and flite (a second
// synthesiser that reports its own segment times) when installed. Of flite's voices only the
// clustergen ones (slt, rms, awb) are used: the diphone voice kal prints segment times that
// add up to 0.2 s more per sentence than the audio it writes.

#include <string>
#include <vector>

#include "eval/error_stats.hpp"

namespace rostro::eval {

struct AlignmentCase {
  std::string name;
  std::string language;  // es, pt, en: the transcript's language and the reference voice
  std::string text;
  std::string synthesiser;  // "espeak-ng" or "flite"
  std::string voice;        // of the recording
  int rate_wpm = 0;         // espeak-ng only; 0 default
  int pitch = -1;           // espeak-ng only; -1 default
  double snr_db = 0.0;      // white noise at this signal-to-noise ratio; 0 none
  int sample_rate = 0;      // the recording resampled to this; 0 keeps the synthesiser's
  int repeat = 1;           // the text said this many times (a long take, for drift)
};

// The built-in cases (about 20 s of speech each, one of 60 s).
std::vector<AlignmentCase> default_alignment_cases();

// "espeak-ng es+f3, 140 wpm, pitch 70, noise 20 dB SNR, 44100 Hz": how the recording was made.
std::string describe(const AlignmentCase& c);

struct AlignmentScore {
  std::string name;
  std::string recording;  // describe(case)
  bool skipped = false;
  std::string skip_reason;
  double duration_s = 0.0;
  double match_ratio = 0.0;    // the alignment's transcript check (AlignmentOptions)
  ErrorStats boundary_ms;      // |aligned - true| phoneme start, for phonemes matched by symbol
  double early_median_ms = 0;  // boundaries in the first 10 s
  double late_median_ms = 0;   // boundaries in the last 10 s (drift shows as a rise)
  int bilabials = 0;           // true p/b/m in the recording
  int bilabials_late = 0;      // whose nearest closed-lips frame is more than one frame away
  double bilabial_worst_frames = 0;
  double wrong_text_ratio = 0;  // the same recording checked against another transcript
  double uncovered_s = 0;       // speech the alignment reports as not in the transcript
  double shape_agreement = 0;   // share of 10 ms steps whose Rhubarb mouth shape is the truth's
  // English only: PocketSphinx phone recognition of the same recording, with no transcript.
  bool recognised = false;
  double recognised_shape_agreement = 0;
  int recognised_bilabials_found = 0;  // true p/b/m with a recognised one within 50 ms
};

// Runs one case at `fps` (bilabial frames); the wrong-text ratio checks the recording against
// another text of the same language. Throws on a failure other than a missing synthesiser.
AlignmentScore score_alignment(const AlignmentCase& c, double fps = 25.0);

// The Markdown table of the scores, and the line stating the aims.
std::string alignment_table(const std::vector<AlignmentScore>& scores);

}  // namespace rostro::eval
