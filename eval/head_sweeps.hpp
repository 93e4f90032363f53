#pragma once
// Head turns carried by the FAP stream itself: sine sweeps written into head_pitch (48),
// head_yaw (49) and head_roll (50), so the deformer turns the rendered head and the truth
// .fap holds the motion a capture should read back. (`rostro synth --yaw` orbits the camera
// instead: that motion is in no FAP and spoils a capture's first-second calibration.)
//
// Signs are the FAP table's (and mapping::head_rotation_faps'): yaw positive toward the face's
// left, pitch positive down; 1 AU = 1e-5 rad.

#include "facecore/fap_frame.hpp"

namespace rostro::eval {

struct HeadSweeps {
  double yaw_deg = 0;     // amplitude of the left-right sweep
  double pitch_deg = 0;   // amplitude of the nod, at 0.73 times the yaw's frequency so the two
                          // do not move in lockstep
  double roll_deg = 0;    // amplitude of the tilt, at 0.57 times the yaw's frequency
  double period_s = 4.0;  // one full left-right sweep
  double start_s = 0.0;   // the head stays as the stream has it before this time (a neutral lead)
};

// Adds the sweeps to FAPs 48-50 of every frame from `start_s` on (frame time = position in the
// stream / fps), on top of whatever head rotation the stream already has; values rounded to
// whole AU as a .fap stores them. Each sweep starts at zero. Throws InputError for a
// non-positive period or a stream without a frame rate.
void add_head_sweeps(FapStream& stream, const HeadSweeps& sweeps);

// One AU per 1e-5 rad: `deg` degrees as a head rotation FAP value.
double degrees_to_au(double deg);

}  // namespace rostro::eval
