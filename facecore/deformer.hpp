#pragma once
// Deforms a face model by a frame of FAPs. Everything linear in the FAP values (regions,
// jaw-following parts, pupil dilation, eyeball thrust, tongue roll) is compiled once per
// model; a frame is then a weighted sum per vertex plus the rotations of the eyeballs (FAPs
// 23-26, about their pivots) and of the head (FAPs 48-50, about 7.1), which a neck's vertices
// follow by their share (the model's turn_weights).
//
// A frame walks runs of consecutive vertices weighted on the same feature points: the runs of
// none are placed rigidly (their neutral position turned with the head, about half of the
// generated heads), the others sum their weighted displacements. Runs are split over threads
// (OpenMP) on large meshes. Deformed into a DeformedMesh, frame after frame, the rigid runs are
// left as they are while the head does not turn.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "facecore/face_model.hpp"
#include "facecore/fap_frame.hpp"

namespace rostro {

class Deformer;
class ExpressionLibrary;

// Positions kept from frame to frame by one Deformer: it remembers the head turn they hold, so
// that a frame whose turn is the same skips the vertices nothing else moves. The positions are
// read-only outside the Deformer for that reason.
class DeformedMesh {
 public:
  const std::vector<Eigen::Vector3f>& positions() const { return positions_; }

 private:
  friend class Deformer;
  std::vector<Eigen::Vector3f> positions_;
  std::uint64_t deformer_ = 0;        // Deformer::id_ of the one that placed positions_, or 0
  Eigen::Matrix<float, 12, 1> turn_;  // ... with this head turn (rotation, shift)
};

class Deformer {
 public:
  // Compiles the model; throws InputError for a region that cannot be compiled (e.g. an RBF
  // region whose feature points coincide). The model and library must outlive the Deformer.
  // With a library, deform() first expands FAPs 1 (viseme) and 2 (expression).
  explicit Deformer(const FaceModel& model, const ExpressionLibrary* library = nullptr);

  // Threads a frame is split over: 0 (the default) uses every core on meshes of
  // kParallelVertices or more and one thread below, where the split costs more than it saves.
  void set_threads(int threads);
  int threads() const;
  static constexpr std::size_t kParallelVertices = 50000;

  // Deformed vertex positions for this frame; `positions` is resized to the mesh.
  // Unset FAPs are 0 (neutral); all FAPs 0 gives the neutral mesh exactly.
  void deform(const FapFrame& frame, std::vector<Eigen::Vector3f>& positions) const;
  // The same from a plain vector of the 68 low-level values (index id - 1; 1 and 2 ignored).
  void deform(const Eigen::VectorXd& faps, std::vector<Eigen::Vector3f>& positions) const;
  // The same into a mesh kept from the previous frame: the same positions, but the vertices
  // only the head's turn moves are not placed again when the turn has not changed.
  void deform(const FapFrame& frame, DeformedMesh& mesh) const;
  void deform(const Eigen::VectorXd& faps, DeformedMesh& mesh) const;

  // Area-weighted vertex normals of a (deformed) mesh of this model.
  void normals(const std::vector<Eigen::Vector3f>& positions,
               std::vector<Eigen::Vector3f>& normals) const;

  // The linear part as one 3V x 68 matrix (row 3v+axis, column id-1), with the rigid
  // rotations left out; built on demand for inspection and tests.
  Eigen::SparseMatrix<double> linear_map() const;

  const FaceModel& model() const { return model_; }

 private:
  Eigen::VectorXd low_level(const FapFrame& frame) const;
  static Eigen::VectorXd low_level(const Eigen::VectorXd& faps);
  // Places every vertex, or all but the still runs when `keep_still` (they hold this turn).
  void deform_low_level(const Eigen::VectorXd& faps, bool keep_still,
                        std::vector<Eigen::Vector3f>& out) const;
  void deform_low_level(const Eigen::VectorXd& faps, DeformedMesh& mesh) const;

  const FaceModel& model_;
  const ExpressionLibrary* library_;
  std::uint64_t id_;  // unique to this model's compilation (a copy shares it: same result)
  int threads_ = 0;
  // Feature-point channels: displacement (3-vector) of point k = channel_faps_[k] x faps.
  std::vector<FeaturePointId> channel_points_;
  Eigen::MatrixXd channel_faps_;  // (3K x 68): x, y, z rows per channel
  // Vertices [begin, end) weighted on the same `count` channels (at `channels` in
  // run_channels_), their weights packed per vertex from `weights` in run_weights_: vertex u's
  // weights at weights + (u - begin) x count. A run of count 0 is placed rigidly. One channel
  // list per run keeps the inner loop's length and channels the same from vertex to vertex.
  // A still run is rigid and holds none of the vertices moved after the loop (direct terms,
  // eyeballs): only the head's turn moves it.
  struct VertexRun {
    int begin, end, count, weights, channels;
    bool still;
    float turn_share;  // of the head's turn (the model's turn_weights; 1 for the head)
  };
  std::vector<VertexRun> runs_;
  std::vector<float> run_weights_;
  std::vector<int> run_channels_;
  // Per-vertex vector terms that are not a weight times a point's motion (pupil dilation,
  // eyeball thrust, tongue roll): vertex += value of `fap` x (x, y, z), added after the loop
  // above and turned with the head. The terms of one FAP are direct_terms_[begin, end).
  struct DirectTerm {
    int vertex;
    float x, y, z;
  };
  struct DirectFap {
    int fap, begin, end;
  };
  std::vector<DirectTerm> direct_terms_;
  std::vector<DirectFap> direct_faps_;
  Eigen::MatrixXf neutral_;  // (3 x V)
};

}  // namespace rostro
