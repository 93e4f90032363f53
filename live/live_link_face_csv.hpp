#pragma once
// FAP frames as the CSV Epic's Live Link Face app records, which Unreal's Live Link Face
// importer and Blender add-ons (Faceit and others) read: one row per frame of
//   Timecode,BlendShapeCount,EyeBlinkLeft,...,TongueOut,HeadYaw,HeadPitch,HeadRoll,
//   LeftEyeYaw,LeftEyePitch,LeftEyeRoll,RightEyeYaw,RightEyePitch,RightEyeRoll
// Timecode is HH:MM:SS:FF.fff (FF the frame within the second at the nominal whole rate,
// .fff the fraction of a frame), BlendShapeCount is 61 (52 shapes and 9 angles), shapes are
// 0..1 from an ArkitMapping, angles are radians in ARKit's face frame, whose senses are
// MPEG-4's: yaw to the face's left, pitch down, roll to the face's right.

#include <string>
#include <vector>

#include "facecore/fap_frame.hpp"
#include "live/arkit_mapping.hpp"

namespace rostro::live {

class LiveLinkFaceCsv {
 public:
  // Throws InputError for a frame rate that is not positive.
  LiveLinkFaceCsv(ArkitMapping mapping, double fps);

  // The header row, ending in a newline.
  static std::string header();
  // The row of one frame, ending in a newline; the time is the frame's time_s.
  std::string row(const FapFrame& frame);

  // "HH:MM:SS:FF.fff" for `time_s` at `fps` (the frame counted at the nearest whole rate).
  static std::string timecode(double time_s, double fps);

 private:
  ArkitMapping mapping_;
  double fps_;
  std::vector<std::size_t> column_rule_;  // Live Link Face column -> mapping rule
  std::vector<float> weights_;
};

}  // namespace rostro::live
