// dlib's 68-point model as rostro runs it, against dlib's own output on real photographs
// (../shared/fixtures/faces/training_with_face_landmarks.xml: dlib's landmarks for each face
// box of four PASCAL VOC photos) and on bad model files.

#include "tracking/landmark_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::tracking {
namespace {

const std::filesystem::path kFaces = std::filesystem::path(ROSTRO_SHARED_DIR) / "fixtures/faces";

struct AnnotatedFace {
  std::string image;
  cv::Rect2d box;
  std::vector<cv::Point2d> parts;  // dlib's landmarks, iBUG order
};

// The imglab XML, read with one regular expression per element kind (it is machine-written).
std::vector<AnnotatedFace> read_annotations(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  const std::regex element(
      "<image file='([^']+)'|<box top='(-?\\d+)' left='(-?\\d+)' width='(\\d+)' "
      "height='(\\d+)'|<part name='(\\d+)' x='(-?\\d+)' y='(-?\\d+)'/>");
  std::vector<AnnotatedFace> faces;
  std::string image;
  for (std::sregex_iterator it(xml.begin(), xml.end(), element), end; it != end; ++it) {
    const std::smatch& m = *it;
    if (m[1].matched) {
      image = m[1];
    } else if (m[2].matched) {
      faces.push_back(
          {image, {std::stod(m[3]), std::stod(m[2]), std::stod(m[4]), std::stod(m[5])}, {}});
    } else if (!faces.empty()) {
      faces.back().parts.emplace_back(std::stod(m[7]), std::stod(m[8]));
    }
  }
  return faces;
}

bool have_model() {
  return std::filesystem::exists(default_landmark_model());
}

TEST(LandmarkModel, AgreesWithDlibOwnOutputOnRealPhotos) {
  if (!std::filesystem::exists(kFaces / "training_with_face_landmarks.xml"))
    GTEST_SKIP() << "../shared/fixtures/faces is absent";
  if (!have_model()) GTEST_SKIP() << "no " << default_landmark_model() << " (libdlib-data)";
  const auto faces = read_annotations(kFaces / "training_with_face_landmarks.xml");
  ASSERT_GE(faces.size(), 10u);
  LandmarkModel model(default_landmark_model());
  std::vector<double> errors;
  for (const AnnotatedFace& face : faces) {
    ASSERT_EQ(face.parts.size(), 68u) << face.image;
    const cv::Mat gray = cv::imread((kFaces / face.image).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << face.image;
    const auto points = model.fit(gray, face.box);
    ASSERT_EQ(points.size(), 68u);
    for (std::size_t i = 0; i < points.size(); ++i)
      errors.push_back(cv::norm(points[i] - face.parts[i]));
  }
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  std::printf("%zu faces: median %.2f px, 95th percentile %.2f px from dlib's own landmarks\n",
              faces.size(), median, errors[errors.size() * 95 / 100]);
  // dlib's file holds whole pixels; rostro keeps the sub-pixel fit, so up to 0.7 px apart.
  EXPECT_LE(median, 1.0);
  EXPECT_LE(errors[errors.size() * 95 / 100], 1.5);
}

TEST(LandmarkModel, FindsEveryFaceTheAnnotationsHoldAndFitsEach) {
  if (!std::filesystem::exists(kFaces / "training_with_face_landmarks.xml"))
    GTEST_SKIP() << "../shared/fixtures/faces is absent";
  if (!have_model()) GTEST_SKIP() << "no " << default_landmark_model() << " (libdlib-data)";
  const auto faces = read_annotations(kFaces / "training_with_face_landmarks.xml");
  LandmarkModel model(default_landmark_model());
  int found = 0;
  for (const AnnotatedFace& face : faces) {
    const cv::Mat gray = cv::imread((kFaces / face.image).string(), cv::IMREAD_GRAYSCALE);
    // Faces as small as the smallest annotated one (about 37 px).
    const auto detections = model.detect(gray, {0, 0, gray.cols, gray.rows}, 36, 0.0);
    for (const FaceDetection& d : detections)
      if ((d.box & face.box).area() > 0.5 * face.box.area()) {
        ++found;
        EXPECT_EQ(model.fit(gray, d.box).size(), 68u);
        break;
      }
  }
  std::printf("found %d of %zu annotated faces\n", found, faces.size());
  // dlib's own annotations came from this detector; a few faces were boxed by hand.
  EXPECT_GE(found, static_cast<int>(faces.size()) * 3 / 4) << found << " of " << faces.size();
}

TEST(LandmarkModel, SeveralFacesInOnePhoto) {
  if (!std::filesystem::exists(kFaces / "bald_guys.jpg"))
    GTEST_SKIP() << "../shared/fixtures/faces is absent";
  if (!have_model()) GTEST_SKIP() << "no " << default_landmark_model() << " (libdlib-data)";
  const cv::Mat gray = cv::imread((kFaces / "bald_guys.jpg").string(), cv::IMREAD_GRAYSCALE);
  LandmarkModel model(default_landmark_model());
  const auto faces = model.detect(gray, {0, 0, gray.cols, gray.rows}, 120, 0.0);
  EXPECT_GE(faces.size(), 2u);
  for (const FaceDetection& d : faces) {
    const auto points = model.fit(gray, d.box);
    ASSERT_EQ(points.size(), 68u);
    // The landmarks lie on the face the detector boxed.
    cv::Rect2d grown(d.box.x - d.box.width * 0.25, d.box.y - d.box.height * 0.25, d.box.width * 1.5,
                     d.box.height * 1.5);
    for (const cv::Point2d& p : points) EXPECT_TRUE(grown.contains(p)) << p;
  }
}

TEST(LandmarkModel, MissingModelNamesThePathAndThePackage) {
  try {
    LandmarkModel model("/nonexistent/landmarks.dat");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/nonexistent/landmarks.dat"), std::string::npos) << what;
    EXPECT_NE(what.find("libdlib-data"), std::string::npos) << what;
  }
}

TEST(LandmarkModel, CorruptModelIsOneInputError) {
  const auto path = std::filesystem::temp_directory_path() / "rostro-corrupt-landmarks.dat";
  for (const std::string& content : {std::string("not a model at all"), std::string(4, '\0'),
                                     std::string("\x01\x02\x03\x04\x05\x06\x07\x08", 8)}) {
    std::ofstream(path, std::ios::binary) << content;
    try {
      LandmarkModel model(path);
      FAIL() << "no error for " << content.size() << " bytes";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
  // A truncated real model.
  if (have_model()) {
    std::ifstream real(default_landmark_model(), std::ios::binary);
    std::string head(100000, '\0');
    real.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(path, std::ios::binary) << head;
    EXPECT_THROW(LandmarkModel{path}, InputError);
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rostro::tracking
