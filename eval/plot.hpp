#pragma once
// Simple, readable line charts drawn with OpenCV: title, axis labels, tick values, grid and a
// legend. Debian's plotting libraries were considered (PLplot pulls in Fortran, Qt and
// wxWidgets development packages and loads its PNG driver at run time); eval already has
// OpenCV, and these charts need little more than lines and text.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "eval/error_stats.hpp"

namespace rostro::eval {

struct Series {
  std::string label;
  std::vector<CurvePoint> points;
  cv::Scalar colour;  // BGR; leave default to take the next colour of the palette
  bool dashed = false;
  bool has_colour = false;
};

struct VerticalMarker {
  double x = 0;
  std::string label;
};

enum class LegendPlace { TopLeft, BottomRight, Above };

struct Chart {
  std::string title;
  std::string x_label;
  std::string y_label;
  // Axis ranges; when min == max the range is taken from the data.
  double x_min = 0, x_max = 0;
  double y_min = 0, y_max = 0;
  std::vector<Series> series;
  std::vector<VerticalMarker> markers;
  LegendPlace legend = LegendPlace::TopLeft;
};

// The next colour of a palette that stays distinguishable for colour-blind readers.
cv::Scalar palette_colour(std::size_t i);

// Draws one chart into a white image of `size`.
cv::Mat draw_chart(const Chart& chart, cv::Size size);

// Charts stacked top to bottom, each `panel` in size.
cv::Mat draw_charts(const std::vector<Chart>& charts, cv::Size panel);

// Writes `image` as PNG through AtomicFile. Throws InputError on failure.
void write_png(const std::filesystem::path& path, const cv::Mat& image);

// Tick positions for [lo, hi]: steps of 1, 2 or 5 times a power of ten, about `target` ticks.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

}  // namespace rostro::eval
