#pragma once
// Deforms a face model by a frame of FAPs. Everything linear in the FAP values (regions,
// jaw-following parts, pupil dilation, eyeball thrust, tongue roll) is compiled once per
// model into sparse matrices; a frame is then one sparse product plus the rotations of the
// eyeballs (FAPs 23-26, about their pivots) and of the head (FAPs 48-50, about 7.1).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "facecore/face_model.hpp"
#include "facecore/fap_frame.hpp"

namespace rostro {

class ExpressionLibrary;

class Deformer {
 public:
  // Compiles the model; throws InputError for a region that cannot be compiled (e.g. an RBF
  // region whose feature points coincide). The model and library must outlive the Deformer.
  // With a library, deform() first expands FAPs 1 (viseme) and 2 (expression).
  explicit Deformer(const FaceModel& model, const ExpressionLibrary* library = nullptr);

  // Deformed vertex positions for this frame; `positions` is resized to the mesh.
  // Unset FAPs are 0 (neutral); all FAPs 0 gives the neutral mesh exactly.
  void deform(const FapFrame& frame, std::vector<Eigen::Vector3f>& positions) const;
  // The same from a plain vector of the 68 low-level values (index id - 1; 1 and 2 ignored).
  void deform(const Eigen::VectorXd& faps, std::vector<Eigen::Vector3f>& positions) const;

  // Area-weighted vertex normals of a (deformed) mesh of this model.
  void normals(const std::vector<Eigen::Vector3f>& positions,
               std::vector<Eigen::Vector3f>& normals) const;

  // The linear part as one 3V x 68 matrix (row 3v+axis, column id-1), with the rigid
  // rotations left out; built on demand for inspection and tests.
  Eigen::SparseMatrix<double> linear_map() const;

  const FaceModel& model() const { return model_; }

 private:
  void deform_low_level(const Eigen::VectorXd& faps, std::vector<Eigen::Vector3f>& out) const;

  const FaceModel& model_;
  const ExpressionLibrary* library_;
  // Feature-point channels: displacement (3-vector) of point k = channel_faps_[k] x faps.
  std::vector<FeaturePointId> channel_points_;
  Eigen::MatrixXd channel_faps_;  // (3K x 68): x, y, z rows per channel
  // Vertex displacement (V x 3) = weights_ (V x K) x channel displacements (K x 3).
  Eigen::SparseMatrix<float, Eigen::RowMajor> weights_;
  // Per-vertex vector terms that are not a weight times a point's motion (3V x 68).
  Eigen::SparseMatrix<float> direct_;
  Eigen::MatrixXf neutral_;  // (3 x V)
};

}  // namespace rostro
