#include "speech/speech_presence.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "facecore/error.hpp"
#include "speech/audio_file.hpp"

namespace rostro::speech {
namespace {

// Pitch lives well below 4 kHz: 8 kHz and 20 ms steps keep a minute under 0.1 s.
constexpr int kRate = 8000;
constexpr int kWindow = 320;  // 40 ms: two periods of a 50 Hz voice
constexpr int kHop = 160;     // 20 ms
constexpr int kShortestLag = kRate / 400;
constexpr int kLongestLag = kRate / 50;
// A frame is periodic when its normalised autocorrelation at some pitch lag reaches this.
constexpr double kPeriodic = 0.5;

// Thresholds, from measurement (docs/speech.md): speech (real voices, espeak-ng and flite,
// also under noise at 10 dB SNR) measured 40-91 % voiced frames and a loudness spread of
// 4.6-10.6 dB; alsa-utils' Noise.wav 25 % and 1.1 dB, white noise 0 % and 0.3 dB, two
// held tones 100 % and 0.1 dB.
constexpr double kSilentDb = -60.0;
constexpr double kMinVoicedShare = 0.2;
constexpr double kMinSpreadDb = 3.0;

double periodicity(const std::vector<double>& x) {
  double energy = 0.0;
  for (double v : x) energy += v * v;
  if (energy <= 0.0) return 0.0;
  double best = 0.0;
  for (int lag = kShortestLag; lag <= kLongestLag; ++lag) {
    double r = 0.0, e1 = 0.0, e2 = 0.0;
    for (int k = 0; k + lag < kWindow; ++k) {
      r += x[k] * x[k + lag];
      e1 += x[k] * x[k];
      e2 += x[k + lag] * x[k + lag];
    }
    if (e1 > 0 && e2 > 0) best = std::max(best, r / std::sqrt(e1 * e2));
  }
  return best;
}

}  // namespace

SpeechPresence measure_speech_presence(const Audio& audio) {
  const Audio a = resample(audio, kRate);
  SpeechPresence out;
  const auto n = static_cast<long>(a.samples.size());
  std::vector<double> loudness;
  std::vector<std::vector<double>> frames;
  for (long start = 0; start + kWindow <= n; start += kHop) {
    std::vector<double> x(kWindow);
    double mean = 0.0;
    for (int k = 0; k < kWindow; ++k) {
      x[k] = a.samples[static_cast<std::size_t>(start + k)] / 32768.0;
      mean += x[k];
    }
    mean /= kWindow;
    double power = 0.0;
    for (double& v : x) {
      v -= mean;
      power += v * v;
    }
    loudness.push_back(10.0 * std::log10(power / kWindow + 1e-12));
    frames.push_back(std::move(x));
  }
  if (loudness.empty()) return out;
  out.loudest_db = *std::max_element(loudness.begin(), loudness.end());
  // Loud: within 30 dB of the loudest frame.
  std::vector<double> loud;
  long voiced = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (loudness[i] < out.loudest_db - 30.0) continue;
    loud.push_back(loudness[i]);
    voiced += periodicity(frames[i]) >= kPeriodic;
  }
  out.voiced_share = static_cast<double>(voiced) / static_cast<double>(frames.size());
  double mean = 0.0, var = 0.0;
  for (double l : loud) mean += l;
  mean /= static_cast<double>(loud.size());
  for (double l : loud) var += (l - mean) * (l - mean);
  out.loudness_spread_db = std::sqrt(var / static_cast<double>(loud.size()));
  return out;
}

void require_speech(const Audio& audio, const std::string& name) {
  const SpeechPresence p = measure_speech_presence(audio);
  if (p.loudest_db < kSilentDb)
    throw InputError(
        where(name, 0, fmt::format("silent (its loudest 40 ms at {:.0f} dBFS)", p.loudest_db)));
  if (p.voiced_share < kMinVoicedShare || p.loudness_spread_db < kMinSpreadDb)
    throw InputError(
        where(name, 0,
              fmt::format("no speech found ({:.0f} % voiced frames, loudness varying by {:.1f} dB; "
                          "speech measures over 40 % and 4.5 dB): noise or a tone?",
                          100 * p.voiced_share, p.loudness_spread_db)));
}

}  // namespace rostro::speech
