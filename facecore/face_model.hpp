#pragma once
// A face model: a triangle mesh, where its MPEG-4 feature points are, the influence regions
// that spread each feature point's motion to the vertices around it, and the rigid parts
// (eyeballs, teeth, tongue, jaw). It is read from a JSON description beside an OBJ mesh;
// the format is documented in docs/face-model.md.

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "facecore/fapu.hpp"
#include "facecore/feature_point.hpp"
#include "facecore/texture.hpp"

namespace rostro {

// How a region turns its feature points' displacements into vertex displacements.
enum class InfluenceKind {
  RaisedCosine,    // one feature point: w = (1 + cos(pi d / d_max)) / 2, d under `metric`
  Rbf,             // points bounding the region: multiquadric RBF interpolating displacements
  AveragedCosine,  // several points not bounding it: average of the per-point raised cosines
  Rigid,           // every vertex moves by `gain` x the feature point's displacement
};

struct InfluenceRegion {
  std::string name;
  InfluenceKind kind = InfluenceKind::RaisedCosine;
  std::vector<FeaturePointId> feature_points;  // the points whose motion drives the region
  std::vector<int> vertices;                   // the vertices it moves (0-based)
  // Optional per-vertex multipliers, parallel to `vertices` (empty: all 1). They let a
  // region fade out toward its border; a feature point's own vertex should keep 1.
  std::vector<double> vertex_weights;
  // Per-axis scale of the distance used by cosine regions: {1,1,1} is the 3D distance,
  // {0,1,0} the distance along y only ("raised cosine on one axis").
  Eigen::Vector3d metric = Eigen::Vector3d::Ones();
  double d_max = 0.0;        // cosine reach; 0: the farthest vertex of the region
  std::vector<int> anchors;  // RBF only: vertices held still (extra centres with zero motion)
  std::vector<int> faps;     // only these FAPs drive the region (empty: every FAP on its points)
  double gain = 1.0;         // Rigid only
};

// A part of the mesh that moves as a whole.
struct RigidPart {
  std::vector<int> vertices;
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();  // centre of rotation (eyeballs, jaw hinge)
  // Fraction of the jaw's motion (the displacement of 2.1 by FAPs 3, 14, 15) the part
  // follows: lower teeth 1, tongue less, upper teeth 0.
  double jaw_gain = 0.0;
  bool empty() const { return vertices.empty(); }
};

struct RigidParts {
  RigidPart left_eyeball;   // rotates with FAPs 23 and 25 about its pivot, thrusts with 27
  RigidPart right_eyeball;  // FAPs 24, 26, 28
  RigidPart upper_teeth;
  RigidPart lower_teeth;
  RigidPart tongue;  // also bends with FAPs 43-47 through its regions
  RigidPart jaw;     // vertices that follow the jaw rigidly (mouth floor)
};

// Vertices that follow the head's turn (FAPs 48-50) only in part: a neck that twists and bends
// between the head and shoulders that stay where they are. A vertex not listed follows the
// turn whole.
struct TurnWeights {
  std::vector<int> vertices;
  std::vector<double> weights;  // parallel to `vertices`: the share of the turn, 0..1
  bool empty() const { return vertices.empty(); }
};

struct FaceModel {
  std::string name;
  std::vector<Eigen::Vector3f> positions;  // neutral mesh, model units (mm)
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside
  std::vector<Eigen::Vector3f> colors;     // per vertex, linear 0..1 (empty: none)
  // Where each vertex samples `texture` (u, v in 0..1, v up; u wraps around, so a triangle
  // across u = 0 takes the short way). Empty: no texture; a vertex with non-finite coordinates
  // is not textured and shows its colour. A textured vertex's colour is the texture's there,
  // for renderers without textures.
  std::vector<Eigen::Vector2f> texcoords;
  Texture texture;
  std::vector<std::string> materials;            // material names ("skin", "iris", ...)
  std::vector<int> triangle_materials;           // per triangle index into materials
  std::map<FeaturePointId, int> feature_points;  // feature point -> vertex
  std::vector<InfluenceRegion> regions;
  RigidParts parts;
  TurnWeights turn_weights;
  Eigen::Vector3d head_pivot = Eigen::Vector3d::Zero();  // 7.1: head rotation (FAPs 48-50)
  Fapu fapu;  // computed from the feature points of the neutral mesh

  std::size_t vertex_count() const { return positions.size(); }
  bool has_feature_point(FeaturePointId id) const { return feature_points.count(id) != 0; }
  // Neutral position of a feature point; throws InputError when the model lacks it.
  Eigen::Vector3d feature_point(FeaturePointId id) const;
  FeaturePointPositions feature_point_positions() const;
  // Checks indices, points and regions; throws InputError naming `source` and the problem.
  void validate(const std::string& source) const;
};

// Reads a face model description (JSON) and the OBJ mesh it names (relative to the JSON).
// Throws InputError for a missing file, bad syntax, a vertex index out of range, an unknown
// feature point or a region without a feature point.
FaceModel load_face_model(const std::filesystem::path& description);

// The default head, data/head/head.json.
FaceModel load_default_face_model();

// The face model `description` names, or the default head when it is empty: a command's
// optional --head.
FaceModel load_face_model_or_default(const std::filesystem::path& description);

// Writes `<dir>/<stem>.obj` (vertex colours as `v x y z r g b`) and `<dir>/<stem>.json`
// atomically.
void save_face_model(const FaceModel& model, const std::filesystem::path& dir,
                     const std::string& stem = "head");

}  // namespace rostro
