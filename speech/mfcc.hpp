#pragma once
// Spectral features for alignment: mel-frequency cepstral coefficients (MFCC) with their
// deltas, one vector every 10 ms. Two recordings of the same words by different voices give
// similar feature sequences, so dynamic time warping can match them (speech/dtw.hpp).

#include <vector>

#include "speech/audio.hpp"

namespace rostro::speech {

struct MfccOptions {
  int analysis_rate = 16000;  // both signals are resampled to this rate first
  double window_s = 0.025;
  double hop_s = 0.010;
  int filters = 26;
  // c0 (replaced by log energy) .. c6: the higher cepstra describe the speaker more than
  // the phoneme, and aligning two voices measured better without them (docs/speech.md).
  int cepstra = 7;
  double low_hz = 100.0;
  double high_hz = 8000.0;    // lowered to what both signals carry (see band_top)
  bool normalise = true;      // per-utterance mean and variance normalisation
  double delta_weight = 1.0;  // deltas scaled by this after normalisation
  // Vocal tract length normalisation: the filter that nominally sits at F Hz is placed at
  // warp x F in this signal's spectrum, so a voice whose formants lie warp times higher
  // gives the features of one whose formants do not.
  double warp = 1.0;
};

// Row-major frames x dims; frame i covers [i*hop, i*hop + window) of the audio.
struct Features {
  int frames = 0;
  int dims = 0;
  double hop_s = 0.01;
  std::vector<float> values;

  const float* row(int i) const { return values.data() + static_cast<std::size_t>(i) * dims; }
  float* row(int i) { return values.data() + static_cast<std::size_t>(i) * dims; }
};

// The highest frequency two signals both carry: 8 kHz audio has nothing above 4 kHz, and
// comparing a band one signal lacks only adds noise.
double band_top(const Audio& a, const Audio& b, double limit_hz = 8000.0);

// MFCC (with log energy in place of c0) and their deltas: 2 x cepstra dims per frame.
Features mfcc(const Audio& audio, const MfccOptions& options = {});

// Log energy per analysis frame in dB (full scale 0 dB), on the same frame grid as mfcc().
std::vector<float> frame_energy_db(const Audio& audio, const MfccOptions& options = {});

}  // namespace rostro::speech
