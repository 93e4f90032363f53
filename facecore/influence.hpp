#pragma once
// Influence functions: how much of each feature point's displacement a vertex of a region
// receives. All of them are fixed per neutral mesh, so they are evaluated once, when a
// Deformer is built (seed004-notes section 5).

#include <Eigen/Core>
#include <vector>

#include "facecore/face_model.hpp"

namespace rostro {

// (1 + cos(pi d / d_max)) / 2 for d < d_max, else 0: 1 at the point, 0 at the reach.
double raised_cosine(double d, double d_max);

// Multiquadric kernel sqrt(r^2 + s^2).
double multiquadric(double r, double s);

// The weights of one region: vertex `vertices[i]` moves by sum_k weights(i, k) x the
// displacement of feature point `model.feature_points[region.feature_points[k]]`.
struct RegionWeights {
  std::vector<int> vertices;
  Eigen::MatrixXd weights;  // |vertices| x |feature points|
};

// Throws InputError naming the region when it cannot be compiled (coincident RBF centres, a
// singular system).
RegionWeights compile_region(const FaceModel& model, const InfluenceRegion& region);

}  // namespace rostro
