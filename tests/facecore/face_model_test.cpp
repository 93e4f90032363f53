// The face model loader: the default head round-trips, and each kind of bad description is
// one clear InputError.

#include "facecore/face_model.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "facecore/error.hpp"
#include "facecore/head_generator.hpp"
#include "facecore/texture.hpp"

namespace rostro {
namespace {

namespace fs = std::filesystem;

class FaceModelFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(ROSTRO_BINARY_DIR) / "test_face_model" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A tiny square face: four vertices, two triangles, the FAPU points and one region.
    std::ofstream(dir_ / "face.obj")
        << "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\n"
           "usemtl skin\nf 1 2 3\nf 1 3 4\n";
    description_ = {{"mesh", "face.obj"},
                    {"feature_points",
                     {{"3.1", 3},
                      {"3.3", 0},
                      {"3.5", 2},
                      {"3.6", 3},
                      {"9.15", 1},
                      {"2.2", 0},
                      {"8.3", 1},
                      {"8.4", 0}}},
                    {"regions", nlohmann::json::array({{{"name", "cheek"},
                                                        {"function", "raised_cosine"},
                                                        {"feature_points", {"3.5"}},
                                                        {"vertices", {0, 1, 2}}}})}};
  }
  fs::path write(const nlohmann::json& j) {
    const fs::path p = dir_ / "face.json";
    std::ofstream(p) << j.dump();
    return p;
  }
  std::string error_of(const nlohmann::json& j) {
    try {
      load_face_model(write(j));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
  nlohmann::json description_;
};

TEST_F(FaceModelFiles, LoadsAValidDescription) {
  const FaceModel m = load_face_model(write(description_));
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.colors.size(), 4u);
  EXPECT_EQ(m.colors[1], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(m.feature_points.at({3, 5}), 2);
  ASSERT_EQ(m.regions.size(), 1u);
  EXPECT_EQ(m.regions[0].kind, InfluenceKind::RaisedCosine);
  EXPECT_DOUBLE_EQ(m.fapu.es0, 1.0);  // |3.5.x - 3.6.x| = |1 - 0|
}

TEST_F(FaceModelFiles, VertexIndexOutOfRangeIsOneClearError) {
  description_["regions"][0]["vertices"] = {0, 1, 7};
  const std::string e = error_of(description_);
  EXPECT_NE(e.find("face.json"), std::string::npos) << e;
  EXPECT_NE(e.find("vertex index 7 is out of range"), std::string::npos) << e;
  EXPECT_NE(e.find("cheek"), std::string::npos) << e;
  description_["feature_points"]["3.5"] = 4;
  EXPECT_NE(error_of(description_).find("out of range"), std::string::npos);
}

TEST_F(FaceModelFiles, UnknownFeaturePointIsOneClearError) {
  description_["feature_points"]["3.99"] = 1;
  EXPECT_NE(error_of(description_).find("unknown feature point '3.99'"), std::string::npos);
  description_["feature_points"].erase("3.99");
  description_["regions"][0]["feature_points"] = {"12.1"};
  EXPECT_NE(error_of(description_).find("unknown feature point '12.1'"), std::string::npos);
  // A known point the model does not place.
  description_["regions"][0]["feature_points"] = {"4.1"};
  EXPECT_NE(error_of(description_).find("feature point 4.1 is not in the model"),
            std::string::npos);
}

TEST_F(FaceModelFiles, RegionWithoutFeaturePointIsOneClearError) {
  description_["regions"][0]["feature_points"] = nlohmann::json::array();
  const std::string e = error_of(description_);
  EXPECT_NE(e.find("region 'cheek': has no feature point"), std::string::npos) << e;
}

TEST_F(FaceModelFiles, OtherMistakesAreInputErrors) {
  description_["regions"][0]["function"] = "gaussian";
  EXPECT_NE(error_of(description_).find("function must be"), std::string::npos);
  EXPECT_NE(error_of(nlohmann::json{{"feature_points", nlohmann::json::object()}}).find("'mesh'"),
            std::string::npos);
  std::ofstream(dir_ / "face.obj") << "v 0 0 0\nf 1 2 3\n";
  EXPECT_NE(error_of(description_).find("out of range"), std::string::npos);
  std::ofstream(dir_ / "bad.json") << "{ not json";
  EXPECT_THROW(load_face_model(dir_ / "bad.json"), InputError);
  EXPECT_THROW(load_face_model(dir_ / "missing.json"), InputError);
}

TEST_F(FaceModelFiles, TurnWeightsAreReadAndTheirMistakesNamed) {
  description_["turn_weights"] = {{"vertices", {0, 1}}, {"weights", {0.0, 0.5}}};
  const FaceModel m = load_face_model(write(description_));
  EXPECT_EQ(m.turn_weights.vertices, (std::vector<int>{0, 1}));
  EXPECT_EQ(m.turn_weights.weights, (std::vector<double>{0.0, 0.5}));
  description_["turn_weights"]["weights"] = {0.0, 1.5};
  EXPECT_NE(error_of(description_).find("turn_weights: a weight is 1.5"), std::string::npos);
  description_["turn_weights"]["weights"] = {0.0};
  EXPECT_NE(error_of(description_).find("turn_weights: 1 weights for 2 vertices"),
            std::string::npos);
  description_["turn_weights"] = {{"vertices", {0, 9}}, {"weights", {0.0, 0.0}}};
  EXPECT_NE(error_of(description_).find("turn_weights: vertex index 9 is out of range"),
            std::string::npos);
  description_["turn_weights"] = {{"vertices", {0}}};
  EXPECT_NE(error_of(description_).find("needs both 'vertices' and 'weights'"), std::string::npos);
}

TEST_F(FaceModelFiles, GeneratedHeadRoundTripsThroughObjAndJson) {
  const FaceModel a = generate_head(HeadOptions{3000});
  save_face_model(a, dir_ / "head", "head");
  const FaceModel b = load_face_model(dir_ / "head" / "head.json");
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t v = 0; v < a.positions.size(); ++v)
    ASSERT_LT((a.positions[v] - b.positions[v]).norm(), 1e-4f);
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.triangle_materials.size(), b.triangle_materials.size());
  for (std::size_t t = 0; t < a.triangle_materials.size(); ++t)
    ASSERT_EQ(a.materials[static_cast<std::size_t>(a.triangle_materials[t])],
              b.materials[static_cast<std::size_t>(b.triangle_materials[t])]);
  EXPECT_EQ(a.feature_points, b.feature_points);
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t r = 0; r < a.regions.size(); ++r) {
    EXPECT_EQ(a.regions[r].vertices, b.regions[r].vertices) << a.regions[r].name;
    EXPECT_EQ(a.regions[r].kind, b.regions[r].kind) << a.regions[r].name;
    EXPECT_EQ(a.regions[r].anchors, b.regions[r].anchors) << a.regions[r].name;
  }
  EXPECT_EQ(a.parts.left_eyeball.vertices, b.parts.left_eyeball.vertices);
  ASSERT_FALSE(a.turn_weights.empty());
  EXPECT_EQ(a.turn_weights.vertices, b.turn_weights.vertices);
  ASSERT_EQ(a.turn_weights.weights.size(), b.turn_weights.weights.size());
  for (std::size_t i = 0; i < a.turn_weights.weights.size(); ++i)
    ASSERT_NEAR(a.turn_weights.weights[i], b.turn_weights.weights[i], 5e-4);
  EXPECT_NEAR(a.fapu.mw0, b.fapu.mw0, 1e-3);
  // The skin's texture and coordinates come back; the eyes and teeth have none.
  ASSERT_FALSE(b.texture.empty());
  EXPECT_EQ(a.texture.rgb, b.texture.rgb);
  ASSERT_EQ(a.texcoords.size(), b.texcoords.size());
  std::size_t textured = 0;
  for (std::size_t v = 0; v < a.texcoords.size(); ++v) {
    ASSERT_EQ(a.texcoords[v].allFinite(), b.texcoords[v].allFinite()) << "vertex " << v;
    if (!a.texcoords[v].allFinite()) continue;
    ++textured;
    ASSERT_LT((a.texcoords[v] - b.texcoords[v]).norm(), 1e-5f) << "vertex " << v;
  }
  EXPECT_GT(textured, a.texcoords.size() / 2);
  for (int v : a.parts.left_eyeball.vertices)
    EXPECT_FALSE(a.texcoords[static_cast<std::size_t>(v)].allFinite());
}

TEST_F(FaceModelFiles, TextureNamedButMissingOrBrokenIsOneClearError) {
  description_["texture"] = "face.png";
  std::ofstream(dir_ / "face.obj") << "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\n"
                                      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                      "usemtl skin\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  EXPECT_NE(error_of(description_).find("face.png: the texture image does not exist"),
            std::string::npos);
  std::ofstream(dir_ / "face.png") << "not a png";
  EXPECT_NE(error_of(description_).find("face.png: the texture is not an image"),
            std::string::npos);
  Texture t;
  t.width = t.height = 2;
  t.rgb.assign(12, 200);
  write_texture(t, dir_ / "face.png");
  const FaceModel m = load_face_model(write(description_));
  ASSERT_EQ(m.texcoords.size(), 4u);
  EXPECT_EQ(m.texcoords[3], Eigen::Vector2f(0, 1));
  EXPECT_EQ(m.texcoords[2], Eigen::Vector2f(0, 1));  // u = 1 is u = 0: u wraps around
  EXPECT_EQ(m.texture.width, 2);
  // Without "texture" the coordinates point into nothing and are dropped.
  description_.erase("texture");
  EXPECT_TRUE(load_face_model(write(description_)).texcoords.empty());
}

TEST(DefaultHead, LoadsFromData) {
  const fs::path path = fs::path(ROSTRO_DATA_DIR) / "head" / "head.json";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is not generated yet";
  const FaceModel m = load_face_model(path);
  EXPECT_GT(m.positions.size(), 4000u);
  EXPECT_TRUE(m.has_feature_point({7, 1}));
}

}  // namespace
}  // namespace rostro
