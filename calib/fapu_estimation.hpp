#pragma once
// The actor's FAPU from the marked feature points, estimating the FAPU points that carry no
// marker from nearby markers (the seed's lost Eqs. 4.12-4.15, re-derived; docs/mapping.md):
//   3.5 / 3.6  pupils      midpoint of the eye corners (3.7+3.11 / 3.12+3.8), else of the lids
//   9.15       nose base   midpoint of the nose wings 9.1+9.2, else of 9.5+9.4, else nose tip
//   2.2        inner lip   the outer upper-lip marker 8.1
//   IRISD0                 the left (else right) lid markers when they sit on the lid margins,
//                          else ES0 x the prior's IRISD0/ES0
// Each estimate adds the prior's offset between the anchors and the point, scaled to the actor,
// so a face shaped like the prior gets its FAPU exactly. A point with no rule and no marker is
// taken from the prior aligned to the markers (centroid and scale).

#include <map>
#include <string>

#include "facecore/fapu.hpp"

namespace rostro::calib {

struct FapuEstimate {
  Fapu fapu;
  std::map<std::string, std::string> notes;  // feature point or "IRISD0" -> how it was estimated
  double scale_to_prior = 1;                 // actor length unit per prior length unit
};

// `marked`: feature point -> position in a frame with x toward the face's left and y up
// (head-frame mm, or image pixels with y flipped and z = 0). `prior`: a full face (mm).
// `lids_on_margin`: the marked lid points 3.1-3.4 lie on the lid margins (landmarks do), so
// their distance is IRISD0; false for dots, which are painted on the skin beside the lashes and
// would over-measure it. Throws InputError when fewer than two marked points are also in the
// prior.
FapuEstimate estimate_fapu(const FeaturePointPositions& marked, const FeaturePointPositions& prior,
                           bool lids_on_margin = true);

}  // namespace rostro::calib
