#pragma once
// Lays images out in a grid with a caption under each: a contact sheet of expressions,
// visemes or camera views for the documentation and for eyeballing a head at a glance.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace rostro::render {

struct SheetTile {
  cv::Mat image;  // 8-bit BGR; tiles of other sizes are scaled to the first one's
  std::string caption;
};

cv::Mat contact_sheet(const std::vector<SheetTile>& tiles, int columns);

}  // namespace rostro::render
