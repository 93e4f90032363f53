// The libcamera source when rostro is built without libcamera (CMake did not find it or
// ROSTRO_WITH_LIBCAMERA is OFF).
#include "capture/libcamera_source.hpp"
#include "facecore/error.hpp"

namespace rostro::capture {

bool libcamera_built() {
  return false;
}

std::vector<LibcameraCameraInfo> list_libcamera_cameras() {
  return {};
}

std::unique_ptr<FrameSource> open_libcamera_source(const std::string& id_or_index,
                                                   const SourceOptions&) {
  throw InputError("libcamera:" + id_or_index +
                   ": rostro was built without libcamera (install libcamera-dev and rebuild)");
}

}  // namespace rostro::capture
