#pragma once
// Drawing a layout's AprilTag into a scene (eval/synth.cpp's rendered head, eval/photo_scene's
// photographs): the printed pattern, black square and white quiet zone, paper 235 and ink 30.

#include <array>
#include <opencv2/core.hpp>

#include "tracking/layout.hpp"

namespace rostro::eval {

// Draws the tag of `spec` into the 8-bit BGR `image` with its black square's corners at
// `corners` (pixel-centre coordinates; libapriltag's order: bottom-left, bottom-right,
// top-right, top-left as the tag is read). Only the tag's sheet is drawn over.
void draw_tag(cv::Mat& image, const tracking::MarkerSpec& spec,
              const std::array<cv::Point2d, 4>& corners);

}  // namespace rostro::eval
