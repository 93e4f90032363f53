#include "render/frame_sink.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro::render {
namespace fs = std::filesystem;
namespace {

std::atomic<int> staging_counter{0};

void check_frame(const cv::Mat& bgr, cv::Size& expected) {
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw std::invalid_argument("frame sink: frames must be 8-bit BGR images");
  }
  if (expected.area() == 0) expected = bgr.size();
  if (bgr.size() != expected) {
    throw std::invalid_argument("frame sink: frame of " + std::to_string(bgr.cols) + "x" +
                                std::to_string(bgr.rows) + " after frames of " +
                                std::to_string(expected.width) + "x" +
                                std::to_string(expected.height));
  }
}

}  // namespace

FrameFolderWriter::FrameFolderWriter(fs::path folder) : folder_(std::move(folder)) {
  if (folder_.filename().empty()) folder_ = folder_.parent_path();  // "dir/" -> "dir"
  std::error_code ec;
  if (fs::exists(folder_, ec) && !fs::is_directory(folder_, ec)) {
    throw InputError(folder_.string() + ": exists and is not a folder");
  }
  fs::path parent = folder_.has_parent_path() ? folder_.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) {
    throw InputError(folder_.string() + ": the folder " + parent.string() + " does not exist");
  }
  std::string name = ".";  // hidden, and built by appends (GCC 12 misreports "." + string)
  name.append(folder_.filename().string())
      .append(".partial-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(staging_counter++));
  staging_ = parent / name;
  if (!fs::create_directory(staging_, ec) || ec) {
    throw InputError(staging_.string() + ": cannot create a folder (" + ec.message() + ")");
  }
}

FrameFolderWriter::~FrameFolderWriter() {
  if (!finished_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

std::string FrameFolderWriter::frame_name(long index) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06ld.png", index);
  return name;
}

void FrameFolderWriter::write(const cv::Mat& bgr) {
  check_frame(bgr, size_);
  const fs::path path = staging_ / frame_name(count_);
  if (!cv::imwrite(path.string(), bgr)) {
    throw InputError(path.string() + ": cannot write the PNG frame");
  }
  ++count_;
}

void FrameFolderWriter::finish() {
  if (finished_) return;
  std::error_code ec;
  if (!fs::exists(folder_, ec)) {
    fs::rename(staging_, folder_, ec);
    if (ec)
      throw InputError(folder_.string() + ": cannot move the frames in (" + ec.message() + ")");
  } else {
    for (long i = 0; i < count_; ++i) {
      fs::rename(staging_ / frame_name(i), folder_ / frame_name(i), ec);
      if (ec) {
        throw InputError((folder_ / frame_name(i)).string() + ": cannot move the frame in (" +
                         ec.message() + ")");
      }
    }
    fs::remove_all(staging_, ec);
  }
  finished_ = true;
}

void write_image(const fs::path& path, const cv::Mat& bgr) {
  std::vector<uchar> encoded;
  std::string extension = path.extension().string();
  if (extension.empty()) extension = ".png";
  bool ok = false;
  try {
    ok = cv::imencode(extension, bgr, encoded);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) {
    throw InputError(path.string() + ": cannot encode an image as '" + extension +
                     "' (use .png or .jpg)");
  }
  AtomicFile file(path);
  file.write(std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
  file.commit();
}

}  // namespace rostro::render
