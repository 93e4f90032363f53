#include "live/live_link_face_csv.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "facecore/error.hpp"
#include "facecore/fapu.hpp"

namespace rostro::live {
namespace {

// Live Link Face's column order, which is not Apple's (jaw and mouth right come first).
constexpr std::array<const char*, kArkitShapeCount> kColumns = {"eyeBlinkLeft",
                                                                "eyeLookDownLeft",
                                                                "eyeLookInLeft",
                                                                "eyeLookOutLeft",
                                                                "eyeLookUpLeft",
                                                                "eyeSquintLeft",
                                                                "eyeWideLeft",
                                                                "eyeBlinkRight",
                                                                "eyeLookDownRight",
                                                                "eyeLookInRight",
                                                                "eyeLookOutRight",
                                                                "eyeLookUpRight",
                                                                "eyeSquintRight",
                                                                "eyeWideRight",
                                                                "jawForward",
                                                                "jawRight",
                                                                "jawLeft",
                                                                "jawOpen",
                                                                "mouthClose",
                                                                "mouthFunnel",
                                                                "mouthPucker",
                                                                "mouthRight",
                                                                "mouthLeft",
                                                                "mouthSmileLeft",
                                                                "mouthSmileRight",
                                                                "mouthFrownLeft",
                                                                "mouthFrownRight",
                                                                "mouthDimpleLeft",
                                                                "mouthDimpleRight",
                                                                "mouthStretchLeft",
                                                                "mouthStretchRight",
                                                                "mouthRollLower",
                                                                "mouthRollUpper",
                                                                "mouthShrugLower",
                                                                "mouthShrugUpper",
                                                                "mouthPressLeft",
                                                                "mouthPressRight",
                                                                "mouthLowerDownLeft",
                                                                "mouthLowerDownRight",
                                                                "mouthUpperUpLeft",
                                                                "mouthUpperUpRight",
                                                                "browDownLeft",
                                                                "browDownRight",
                                                                "browInnerUp",
                                                                "browOuterUpLeft",
                                                                "browOuterUpRight",
                                                                "cheekPuff",
                                                                "cheekSquintLeft",
                                                                "cheekSquintRight",
                                                                "noseSneerLeft",
                                                                "noseSneerRight",
                                                                "tongueOut"};

constexpr int kAngleCount = 9;

}  // namespace

LiveLinkFaceCsv::LiveLinkFaceCsv(ArkitMapping mapping, double fps)
    : mapping_(std::move(mapping)), fps_(fps) {
  if (!(fps > 0) || !std::isfinite(fps))
    throw InputError(fmt::format("Live Link Face CSV: frame rate {} is not positive", fps));
  const auto& rules = mapping_.rules();
  for (const char* name : kColumns)
    for (std::size_t i = 0; i < rules.size(); ++i)
      if (rules[i].name == name) column_rule_.push_back(i);
  // ArkitMapping::load() checks that all 52 are named once.
  if (column_rule_.size() != kColumns.size())
    throw InputError("Live Link Face CSV: the ARKit mapping does not name all 52 shapes");
}

std::string LiveLinkFaceCsv::header() {
  std::string h = "Timecode,BlendShapeCount";
  for (const char* name : kColumns) h += "," + pascal_case(name);
  h += ",HeadYaw,HeadPitch,HeadRoll,LeftEyeYaw,LeftEyePitch,LeftEyeRoll,RightEyeYaw,"
       "RightEyePitch,RightEyeRoll\n";
  return h;
}

std::string LiveLinkFaceCsv::timecode(double time_s, double fps) {
  const long rate = std::max(1L, std::lround(fps));
  const double frames = std::max(0.0, time_s) * static_cast<double>(rate);
  const auto whole = static_cast<long>(std::floor(frames + 1e-9));
  const long thousandths =
      std::min(999L, std::lround((frames - static_cast<double>(whole)) * 1000));
  const long seconds = whole / rate;
  return fmt::format("{:02}:{:02}:{:02}:{:02}.{:03}", seconds / 3600, seconds / 60 % 60,
                     seconds % 60, whole % rate, thousandths);
}

std::string LiveLinkFaceCsv::row(const FapFrame& frame) {
  mapping_.evaluate(frame, weights_);
  std::string r = timecode(frame.time_s, fps_);
  r += fmt::format(",{}", kArkitShapeCount + kAngleCount);
  for (std::size_t rule : column_rule_) r += fmt::format(",{:.6f}", weights_[rule]);
  const auto angle = [&](int fap) { return frame.get(fap) * kAngleUnitRad; };
  // Head yaw, pitch, roll (FAPs 49, 48, 50); the eyes' yaw and pitch (23/25 left, 24/26
  // right); MPEG-4 has no eye roll.
  for (double a :
       {angle(49), angle(48), angle(50), angle(23), angle(25), 0.0, angle(24), angle(26), 0.0})
    r += fmt::format(",{:.6f}", a);
  r += '\n';
  return r;
}

}  // namespace rostro::live
