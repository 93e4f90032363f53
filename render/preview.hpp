#pragma once
// One frame of a capture preview: the camera image (markers already drawn on it) on the
// left, scaled to the head's height, the animated head on the right, and text lines below.
// Shared by `rostro capture --preview` and the `rostro live` window.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rostro::render {

cv::Mat compose_preview(const cv::Mat& camera, const cv::Mat& head,
                        const std::vector<std::string>& lines = {});

}  // namespace rostro::render
