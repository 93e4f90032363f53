#include "tracking/apriltag_detector.hpp"

#include <cstdlib>
#include <opencv2/imgproc.hpp>

#include "facecore/error.hpp"

extern "C" {
#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagStandard41h12.h>
}

namespace rostro::tracking {
namespace {

struct FamilyFunctions {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr FamilyFunctions kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
};

const FamilyFunctions& family_functions(const std::string& name) {
  for (const FamilyFunctions& f : kFamilies)
    if (name == f.name) return f;
  throw InputError("unknown AprilTag family '" + name +
                   "' (known: tag36h11, tag25h9, tag16h5, tagStandard41h12, tagCircle21h7)");
}

// A family created for one look-up and destroyed after it.
struct ScopedFamily {
  const FamilyFunctions& fn;
  apriltag_family_t* family;
  explicit ScopedFamily(const std::string& name)
      : fn(family_functions(name)), family(fn.create()) {}
  ~ScopedFamily() { fn.destroy(family); }
  ScopedFamily(const ScopedFamily&) = delete;
  ScopedFamily& operator=(const ScopedFamily&) = delete;
};

}  // namespace

struct AprilTagDetector::Impl {
  apriltag_detector_t* detector = nullptr;
  std::vector<std::pair<const FamilyFunctions*, apriltag_family_t*>> families;
  cv::Mat gray;  // conversion buffer for colour input

  ~Impl() {
    if (detector) apriltag_detector_destroy(detector);
    for (auto& [fn, family] : families) fn->destroy(family);
  }
};

AprilTagDetector::AprilTagDetector(AprilTagOptions options)
    : impl_(std::make_unique<Impl>()), options_(std::move(options)) {
  if (options_.families.empty()) throw InputError("no AprilTag family given");
  if (options_.decimation < 1) throw InputError("AprilTag decimation should be 1 or more");
  if (options_.threads < 1) throw InputError("AprilTag threads should be 1 or more");
  impl_->detector = apriltag_detector_create();
  for (const std::string& name : options_.families) {
    const FamilyFunctions& fn = family_functions(name);
    apriltag_family_t* family = fn.create();
    impl_->families.emplace_back(&fn, family);
    apriltag_detector_add_family_bits(impl_->detector, family, options_.bits_corrected);
  }
  impl_->detector->quad_decimate = options_.decimation;
  impl_->detector->quad_sigma = options_.blur_sigma;
  impl_->detector->nthreads = options_.threads;
  impl_->detector->refine_edges = options_.refine_edges;
}

AprilTagDetector::~AprilTagDetector() = default;

std::vector<TagDetection> AprilTagDetector::detect(const cv::Mat& image, cv::Rect roi) {
  return detect(image, roi, options_.decimation);
}

std::vector<TagDetection> AprilTagDetector::detect(const cv::Mat& image, cv::Rect roi,
                                                   float decimation) {
  if (image.empty()) return {};
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw InputError("AprilTag detection needs an 8-bit grey or BGR image");
  const cv::Mat* gray = &image;
  if (image.channels() == 3) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGR2GRAY);
    gray = &impl_->gray;
  }
  cv::Rect full(0, 0, gray->cols, gray->rows);
  roi = roi.area() > 0 ? roi & full : full;
  if (roi.width < 8 || roi.height < 8) return {};

  // libapriltag reads the pixels in place: no copy, the region is a window on the image.
  image_u8_t view{roi.width, roi.height, static_cast<int32_t>(gray->step[0]),
                  const_cast<uint8_t*>(gray->ptr<uint8_t>(roi.y, roi.x))};
  impl_->detector->quad_decimate = decimation;
  zarray_t* found = apriltag_detector_detect(impl_->detector, &view);

  std::vector<TagDetection> out;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(found, i, &det);
    if (det->hamming > options_.max_hamming) continue;
    TagDetection t;
    t.family = det->family->name;
    t.id = det->id;
    t.hamming = det->hamming;
    t.decision_margin = det->decision_margin;
    // libapriltag puts pixel centres at +0.5; rostro (like OpenCV) puts them at integers.
    const double dx = roi.x - kApriltagPixelOffset, dy = roi.y - kApriltagPixelOffset;
    t.center = {det->c[0] + dx, det->c[1] + dy};
    for (int k = 0; k < 4; ++k) t.corners[k] = {det->p[k][0] + dx, det->p[k][1] + dy};
    out.push_back(t);
  }
  apriltag_detections_destroy(found);
  impl_->detector->quad_decimate = options_.decimation;
  return out;
}

cv::Mat apriltag_image(const std::string& family, int id) {
  ScopedFamily f(family);
  if (id < 0 || id >= static_cast<int>(f.family->ncodes))
    throw InputError("AprilTag " + family + " has ids 0.." + std::to_string(f.family->ncodes - 1) +
                     ", not " + std::to_string(id));
  image_u8_t* im = apriltag_to_image(f.family, id);
  cv::Mat out(im->height, im->width, CV_8UC1);
  for (int y = 0; y < im->height; ++y)
    for (int x = 0; x < im->width; ++x) out.at<uint8_t>(y, x) = im->buf[y * im->stride + x];
  // libapriltag 3.3 does not export image_u8_destroy(); it is these two free() calls.
  std::free(im->buf);
  std::free(im);
  return out;
}

int apriltag_black_width(const std::string& family) {
  ScopedFamily f(family);
  return f.family->width_at_border;
}

}  // namespace rostro::tracking
