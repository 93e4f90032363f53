#include "eval/head_sweeps.hpp"

#include <cmath>

#include "facecore/error.hpp"
#include "facecore/fapu.hpp"

namespace rostro::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kHeadPitch = 48, kHeadYaw = 49, kHeadRoll = 50;

}  // namespace

double degrees_to_au(double deg) {
  return deg * kPi / 180.0 / kAngleUnitRad;
}

void add_head_sweeps(FapStream& stream, const HeadSweeps& s) {
  if (s.yaw_deg == 0 && s.pitch_deg == 0 && s.roll_deg == 0) return;
  if (!(s.period_s > 0)) throw InputError("head sweeps: the period must be positive");
  const double fps = stream.header.fps;
  if (!(fps > 0)) throw InputError("head sweeps: the FAP stream has no frame rate");
  for (std::size_t i = 0; i < stream.frames.size(); ++i) {
    const double t = static_cast<double>(i) / fps - s.start_s;
    if (t < -1e-9) continue;
    const double w = 2 * kPi * std::max(0.0, t) / s.period_s;
    FapFrame& f = stream.frames[i];
    // Set wherever a sweep is asked for, zero crossings included, so the truth has it.
    const auto add = [&](int id, double amplitude_deg, double phase) {
      if (amplitude_deg != 0)
        f.set(id, std::round(f.get(id) + degrees_to_au(amplitude_deg * std::sin(phase))));
    };
    add(kHeadYaw, s.yaw_deg, w);
    add(kHeadPitch, s.pitch_deg, 0.73 * w);
    add(kHeadRoll, s.roll_deg, 0.57 * w);
  }
}

}  // namespace rostro::eval
