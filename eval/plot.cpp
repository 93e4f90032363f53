#include "eval/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "facecore/atomic_file.hpp"
#include "facecore/error.hpp"

namespace rostro::eval {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kBlack(0, 0, 0);
const cv::Scalar kGrey(110, 110, 110);
const cv::Scalar kGrid(225, 225, 225);

std::string tick_text(double v, double step) {
  // Enough decimals to tell neighbouring ticks apart, no more.
  int decimals = 0;
  while (decimals < 6) {
    const double scaled = step * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
    ++decimals;
  }
  if (std::abs(v) < step * 1e-6) v = 0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

void put_text(cv::Mat& img, const std::string& text, cv::Point anchor, double scale, int thickness,
              const cv::Scalar& colour, double align_x = 0, double align_y = 1) {
  int baseline = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, thickness, &baseline);
  // align_y: 1 puts the top of the text at anchor.y, 0.5 its middle, 0 its baseline.
  const cv::Point origin(anchor.x - static_cast<int>(align_x * s.width),
                         anchor.y + static_cast<int>(align_y * s.height));
  cv::putText(img, text, origin, kFont, scale, colour, thickness, cv::LINE_AA);
}

// Text turned 90 degrees counter-clockwise, centred on `centre` (for the y-axis label).
void put_vertical_text(cv::Mat& img, const std::string& text, cv::Point centre, double scale) {
  int baseline = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::Mat strip(s.height + baseline + 4, s.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(strip, text, {2, s.height + 2}, kFont, scale, kBlack, 1, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(strip, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect roi(centre.x - turned.cols / 2, centre.y - turned.rows / 2, turned.cols, turned.rows);
  roi &= cv::Rect(0, 0, img.cols, img.rows);
  turned(cv::Rect(0, 0, roi.width, roi.height)).copyTo(img(roi));
}

void dashed_line(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour,
                 int thickness, double dash = 9, double gap = 6, double* phase = nullptr) {
  const double len = cv::norm(b - a);
  if (len <= 0) return;
  const cv::Point2d dir = (b - a) / len;
  double t = phase ? -*phase : 0;
  while (t < len) {
    const double s0 = std::max(t, 0.0), s1 = std::min(t + dash, len);
    if (s1 > s0) cv::line(img, a + dir * s0, a + dir * s1, colour, thickness, cv::LINE_AA);
    t += dash + gap;
  }
  if (phase) *phase = std::fmod(len + *phase, dash + gap);
}

}  // namespace

cv::Scalar palette_colour(std::size_t i) {
  // Okabe-Ito palette (BGR): blue, vermilion, bluish green, reddish purple, orange, sky blue.
  static const cv::Scalar colours[] = {{178, 114, 0},   {0, 94, 213},  {115, 158, 0},
                                       {167, 121, 204}, {0, 159, 230}, {233, 180, 86},
                                       {0, 0, 0}};
  return colours[i % (sizeof colours / sizeof colours[0])];
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / std::max(target, 1);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    step = m * power;
    if (step >= raw) break;
  }
  std::vector<double> ticks;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step)
    ticks.push_back(v);
  return ticks;
}

cv::Mat draw_chart(const Chart& chart, cv::Size size) {
  cv::Mat img(size, CV_8UC3, cv::Scalar(255, 255, 255));

  // Data ranges.
  double x0 = chart.x_min, x1 = chart.x_max, y0 = chart.y_min, y1 = chart.y_max;
  if (x0 == x1 || y0 == y1) {
    double dx0 = 1e300, dx1 = -1e300, dy0 = 1e300, dy1 = -1e300;
    for (const Series& s : chart.series)
      for (const CurvePoint& p : s.points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
        dx0 = std::min(dx0, p.x), dx1 = std::max(dx1, p.x);
        dy0 = std::min(dy0, p.y), dy1 = std::max(dy1, p.y);
      }
    if (dx0 > dx1) dx0 = 0, dx1 = 1, dy0 = 0, dy1 = 1;
    if (x0 == x1) x0 = dx0, x1 = dx1 > dx0 ? dx1 : dx0 + 1;
    if (y0 == y1) {
      const double pad = dy1 > dy0 ? 0.08 * (dy1 - dy0) : 1.0;
      y0 = dy0 - pad, y1 = dy1 + pad;
    }
  }
  const auto x_ticks = nice_ticks(x0, x1, 8);
  const auto y_ticks = nice_ticks(y0, y1, 5);
  const double x_step = x_ticks.size() > 1 ? x_ticks[1] - x_ticks[0] : 1;
  const double y_step = y_ticks.size() > 1 ? y_ticks[1] - y_ticks[0] : 1;

  // Plot area: room on the left for the y label and ticks, below for the x label.
  int widest_y_tick = 0;
  for (double v : y_ticks) {
    int baseline = 0;
    widest_y_tick = std::max(widest_y_tick,
                             cv::getTextSize(tick_text(v, y_step), kFont, 0.5, 1, &baseline).width);
  }
  const int left = 40 + widest_y_tick + 10, right = 25, top = chart.title.empty() ? 20 : 50,
            bottom = 70;
  const cv::Rect area(left, top, size.width - left - right, size.height - top - bottom);
  auto to_px = [&](double x, double y) {
    return cv::Point2d(area.x + (x - x0) / (x1 - x0) * area.width,
                       area.y + area.height - (y - y0) / (y1 - y0) * area.height);
  };

  // Grid and ticks.
  for (double v : x_ticks) {
    const cv::Point2d p = to_px(v, y0);
    cv::line(img, {static_cast<int>(p.x), area.y}, {static_cast<int>(p.x), area.br().y}, kGrid, 1);
    cv::line(img, {static_cast<int>(p.x), area.br().y}, {static_cast<int>(p.x), area.br().y + 5},
             kBlack, 1);
    put_text(img, tick_text(v, x_step), {static_cast<int>(p.x), area.br().y + 10}, 0.5, 1, kBlack,
             0.5, 1);
  }
  for (double v : y_ticks) {
    const cv::Point2d p = to_px(x0, v);
    cv::line(img, {area.x, static_cast<int>(p.y)}, {area.br().x, static_cast<int>(p.y)}, kGrid, 1);
    cv::line(img, {area.x - 5, static_cast<int>(p.y)}, {area.x, static_cast<int>(p.y)}, kBlack, 1);
    put_text(img, tick_text(v, y_step), {area.x - 9, static_cast<int>(p.y)}, 0.5, 1, kBlack, 1,
             0.5);
  }

  // Vertical markers (thresholds), drawn under the data.
  for (const VerticalMarker& m : chart.markers) {
    if (m.x < x0 || m.x > x1) continue;
    const cv::Point2d p = to_px(m.x, y0);
    dashed_line(img, {p.x, static_cast<double>(area.br().y)}, {p.x, static_cast<double>(area.y)},
                kGrey, 1, 5, 5);
    // Above the plot area, where no curve can run through it.
    put_text(img, m.label, {static_cast<int>(p.x), area.y - 5}, 0.5, 1, kGrey, 0.5, 0);
  }

  // Data, clipped to the plot area.
  cv::Mat plot = img(area);
  const cv::Point2d offset(area.x, area.y);
  for (std::size_t i = 0; i < chart.series.size(); ++i) {
    const Series& s = chart.series[i];
    const cv::Scalar colour = s.has_colour ? s.colour : palette_colour(i);
    double phase = 0;
    for (std::size_t k = 1; k < s.points.size(); ++k) {
      const CurvePoint& a = s.points[k - 1];
      const CurvePoint& b = s.points[k];
      if (!std::isfinite(a.y) || !std::isfinite(b.y)) continue;
      const cv::Point2d pa = to_px(a.x, a.y) - offset, pb = to_px(b.x, b.y) - offset;
      if (s.dashed)
        dashed_line(plot, pa, pb, colour, 2, 9, 6, &phase);
      else
        cv::line(plot, pa, pb, colour, 2, cv::LINE_AA);
    }
  }
  cv::rectangle(img, area, kBlack, 1);

  // Labels and title.
  put_text(img, chart.x_label, {area.x + area.width / 2, size.height - 14}, 0.6, 1, kBlack, 0.5, 0);
  put_vertical_text(img, chart.y_label, {16, area.y + area.height / 2}, 0.6);
  const bool legend_above = chart.legend == LegendPlace::Above;
  if (!chart.title.empty()) {
    // Centred, or flush left when the legend takes the right of the top margin.
    const cv::Point anchor = legend_above ? cv::Point(area.x, 14) : cv::Point(size.width / 2, 14);
    put_text(img, chart.title, anchor, 0.7, 2, kBlack, legend_above ? 0 : 0.5, 1);
  }

  // Legend: a framed white box with a line sample per series.
  if (!chart.series.empty()) {
    int widest = 0, baseline = 0;
    for (const Series& s : chart.series)
      widest = std::max(widest, cv::getTextSize(s.label, kFont, 0.5, 1, &baseline).width);
    const int row = 22, n = static_cast<int>(chart.series.size());
    const int entry_w = widest + 60;
    // Inside the plot area in a corner, or one row in the top margin, right-aligned.
    const cv::Size box_size =
        legend_above ? cv::Size(entry_w * n, row + 4) : cv::Size(entry_w, row * n + 10);
    const cv::Point corner =
        legend_above ? cv::Point(area.br().x - box_size.width, std::max(area.y - row - 12, 2))
        : chart.legend == LegendPlace::BottomRight
            ? cv::Point(area.br().x - box_size.width - 10, area.br().y - box_size.height - 10)
            : cv::Point(area.x + 10, area.y + 10);
    const cv::Rect box(corner, box_size);
    cv::rectangle(img, box, cv::Scalar(255, 255, 255), cv::FILLED);
    if (!legend_above) cv::rectangle(img, box, kGrey, 1);
    for (std::size_t i = 0; i < chart.series.size(); ++i) {
      const Series& s = chart.series[i];
      const cv::Scalar colour = s.has_colour ? s.colour : palette_colour(i);
      const int k = static_cast<int>(i);
      const int x = legend_above ? box.x + entry_w * k : box.x;
      const int y = legend_above ? box.y + box.height / 2 : box.y + 5 + row * k + row / 2;
      const cv::Point2d a(x + 8, y), b(x + 43, y);
      if (s.dashed)
        dashed_line(img, a, b, colour, 2, 9, 6);
      else
        cv::line(img, a, b, colour, 2, cv::LINE_AA);
      put_text(img, s.label, {x + 51, y}, 0.5, 1, kBlack, 0, 0.5);
    }
  }
  return img;
}

cv::Mat draw_charts(const std::vector<Chart>& charts, cv::Size panel) {
  std::vector<cv::Mat> panels;
  for (const Chart& c : charts) panels.push_back(draw_chart(c, panel));
  if (panels.empty()) return cv::Mat(panel, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat out;
  cv::vconcat(panels, out);
  return out;
}

void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes))
    throw InputError(path.string() + ": could not encode the PNG");
  AtomicFile file(path);
  file.write(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  file.commit();
}

}  // namespace rostro::eval
