#pragma once
// A built-in generic adult face: all 84 MPEG-4 feature points in millimetres, used as the
// 3D prior for a marker set when no head model is at hand (see docs/mapping.md).
//
// Frame (the FAP frame of facecore/fap_table.hpp): x toward the face's left, y up, z out of
// the face; origin midway between the pupils. Proportions are rough averages for an adult
// (pupils 63 mm apart, eye-nose 45 mm, nose-mouth 21 mm, mouth 50 mm wide); depths are
// plausible rather than measured. Only ratios and depth offsets matter to the fit.

#include "facecore/fapu.hpp"

namespace rostro::calib {

const FeaturePointPositions& generic_face_points();

}  // namespace rostro::calib
