#pragma once
// Facial animation parameter units: distances measured on a neutral face, divided by 1024,
// so that a FAP value means the same expression on faces of any size.

#include <Eigen/Core>
#include <map>

#include "facecore/fap_table.hpp"
#include "facecore/feature_point.hpp"

namespace rostro {

using FeaturePointPositions = std::map<FeaturePointId, Eigen::Vector3d>;

struct Fapu {
  // The five neutral-face distances, in the face's length unit (model units, mm or px).
  double es0 = 0;     // eye separation, |3.5.x - 3.6.x|
  double ens0 = 0;    // eye-nose separation, |3.5.y - 9.15.y|
  double mns0 = 0;    // mouth-nose separation, |9.15.y - 2.2.y|
  double mw0 = 0;     // mouth width, |8.3.x - 8.4.x|
  double irisd0 = 0;  // iris diameter, |3.1.y - 3.3.y| (left eye)

  // The size of one unit of `unit`: distance / 1024, or 1e-5 rad for AU (0 for None).
  double unit_size(FapUnit unit) const;

  // Converts a FAP value from one unit to another through these distances (AU stays AU).
  double convert(double value, FapUnit from, FapUnit to) const;
};

inline constexpr double kAngleUnitRad = 1e-5;

// The FAPU formulas of DESIGN.md. Throws InputError naming the first missing point.
Fapu fapu_from_feature_points(const FeaturePointPositions& points);

}  // namespace rostro
