// Listing cameras without any camera: libcamera gives an empty list, the text says so.
#include "capture/camera_list.hpp"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include "capture/open_source.hpp"
#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

TEST(CameraList, EmptyListSaysSo) {
  CameraList list;
  list.libcamera_built = true;
  const std::string text = format_camera_list(list);
  EXPECT_NE(text.find("No cameras found"), std::string::npos) << text;
  EXPECT_NE(text.find("libcamera: no cameras found"), std::string::npos) << text;
}

TEST(CameraList, ModesAreGroupedByFormatAndSize) {
  CameraList list;
  V4l2DeviceInfo device;
  device.path = "/dev/video0";
  device.card = "Test Cam";
  device.driver = "uvcvideo";
  device.bus_info = "usb-1";
  device.modes = {{V4L2_PIX_FMT_MJPEG, 1280, 720, 1, 30},
                  {V4L2_PIX_FMT_MJPEG, 1280, 720, 1, 60},
                  {V4L2_PIX_FMT_YUYV, 640, 480, 1, 30}};
  device.other_formats = {"H264"};
  list.v4l2.push_back(device);
  const std::string text = format_camera_list(list);
  EXPECT_NE(text.find("/dev/video0  Test Cam"), std::string::npos) << text;
  EXPECT_NE(text.find("MJPG:\n      1280x720 @ 30, 60 fps"), std::string::npos) << text;
  EXPECT_NE(text.find("YUYV:\n      640x480 @ 30 fps"), std::string::npos) << text;
  EXPECT_NE(text.find("H264"), std::string::npos) << text;
  EXPECT_EQ(text.find("No cameras found"), std::string::npos) << text;
}

#ifdef ROSTRO_HAVE_LIBCAMERA
TEST(Libcamera, BuiltAndEnumeratesWithoutCameras) {
  EXPECT_TRUE(libcamera_built());
  // No camera on the build machine: the list is empty but enumeration works. With a
  // camera attached, each entry must at least have an id.
  const auto cameras = list_libcamera_cameras();
  for (const auto& camera : cameras) EXPECT_FALSE(camera.id.empty());
  if (cameras.empty()) {
    EXPECT_THROW(open_frame_source("libcamera:0"), InputError);
    EXPECT_THROW(open_frame_source("libcamera:no-such-camera"), InputError);
  }
}
#else
TEST(Libcamera, ReportsBuildWithoutIt) {
  EXPECT_FALSE(libcamera_built());
  EXPECT_TRUE(list_libcamera_cameras().empty());
  EXPECT_THROW(open_frame_source("libcamera:0"), InputError);
}
#endif

}  // namespace
}  // namespace rostro::capture
