#include "render/contact_sheet.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace rostro::render {

cv::Mat contact_sheet(const std::vector<SheetTile>& tiles, int columns) {
  if (tiles.empty() || tiles.front().image.empty()) {
    throw std::invalid_argument("contact sheet: no images");
  }
  columns = std::clamp(columns, 1, static_cast<int>(tiles.size()));
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  const cv::Size tile = tiles.front().image.size();
  const int caption_height = std::max(24, tile.height / 12);
  const int gap = 4;
  const cv::Size cell(tile.width + gap, tile.height + caption_height + gap);
  cv::Mat sheet(rows * cell.height + gap, columns * cell.width + gap, CV_8UC3,
                cv::Scalar(32, 32, 32));
  const double font_scale = caption_height / 36.0;
  const int thickness = std::max(1, caption_height / 18);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const int col = static_cast<int>(i) % columns;
    const int row = static_cast<int>(i) / columns;
    const cv::Point origin(gap + col * cell.width, gap + row * cell.height);
    cv::Mat image = tiles[i].image;
    if (image.empty()) continue;
    if (image.size() != tile) cv::resize(image, image, tile, 0, 0, cv::INTER_AREA);
    image.copyTo(sheet(cv::Rect(origin, tile)));
    int baseline = 0;
    const cv::Size text = cv::getTextSize(tiles[i].caption, cv::FONT_HERSHEY_SIMPLEX, font_scale,
                                          thickness, &baseline);
    const cv::Point at(origin.x + (tile.width - text.width) / 2,
                       origin.y + tile.height + (caption_height + text.height) / 2);
    cv::putText(sheet, tiles[i].caption, at, cv::FONT_HERSHEY_SIMPLEX, font_scale,
                cv::Scalar(235, 235, 235), thickness, cv::LINE_AA);
  }
  return sheet;
}

}  // namespace rostro::render
