#include "eval/head_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>

#include "facecore/error.hpp"
#include "facecore/fap_frame.hpp"
#include "render/camera.hpp"
#include "render/face_renderer.hpp"
#include "render/frame_sink.hpp"
#include "tracking/ibug_mapping.hpp"
#include "tracking/landmark_model.hpp"

namespace rostro::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const FeaturePointId kRightOuterEye{3, 12}, kLeftOuterEye{3, 7};
constexpr int kExpressions = 6;  // ExpressionLibrary's 1..6; 0 is neutral

FapFrame expression_frame(int select, int intensity) {
  FapFrame frame;
  if (select == 0) return frame;
  ExpressionParams e;
  e.select1 = select;
  e.intensity1 = intensity;
  frame.set_expression(e);
  return frame;
}

std::string share_text(double share) {
  return std::isfinite(share) ? fmt::format("{:.1f} %", 100 * share) : std::string("-");
}

std::string signed_share_text(double share) {
  return fmt::format("{:+.1f} %", 100 * share);
}

std::string view_text(double yaw) {
  return yaw == 0 ? std::string("front") : fmt::format("yaw {:+.0f}", yaw);
}

// A table as Markdown or as aligned text; the first `left` columns are left-aligned.
std::string table_text(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows, std::size_t left,
                       bool markdown) {
  std::string out;
  if (markdown) {
    auto line = [](const std::vector<std::string>& cells) {
      std::string s = "|";
      for (const std::string& c : cells) s += " " + c + " |";
      return s + "\n";
    };
    out += line(header);
    std::string rule = "|";
    for (std::size_t i = 0; i < header.size(); ++i) rule += i < left ? "---|" : "---:|";
    out += rule + "\n";
    for (const auto& cells : rows) out += line(cells);
    return out;
  }
  std::vector<std::size_t> width(header.size());
  for (std::size_t i = 0; i < header.size(); ++i) {
    width[i] = header[i].size();
    for (const auto& cells : rows) width[i] = std::max(width[i], cells[i].size());
  }
  auto line = [&](const std::vector<std::string>& cells) {
    std::string s;
    for (std::size_t i = 0; i < cells.size(); ++i)
      s += i < left ? fmt::format("{:<{}}  ", cells[i], width[i])
                    : fmt::format("{:>{}}  ", cells[i], width[i]);
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s + "\n";
  };
  out += line(header);
  for (const auto& cells : rows) out += line(cells);
  return out;
}

// The scored row's offsets: a row per checked point.
std::string offsets_table(const HeadCheckRow& row, bool markdown) {
  std::vector<std::vector<std::string>> rows;
  std::size_t i = 0;
  for (const HeadFeature& f : head_check_features())
    for (const FeaturePointId& p : f.points) {
      const LandmarkOffset& o = row.offsets.at(i++);
      rows.push_back({p.str(), f.name, signed_share_text(o.outward), signed_share_text(o.up),
                      share_text(std::hypot(o.outward, o.up))});
    }
  return table_text({"point", "feature", "outward", "up", "distance"}, rows, 2, markdown);
}

// The tables, text or Markdown: a row per render, then the scored view's offsets.
std::string table(const HeadCheckResult& r, bool markdown) {
  std::vector<std::string> header{"view", "expression", "face", "IOD px"};
  for (const HeadFeature& f : head_check_features()) header.push_back(f.name);
  header.push_back("worst point");
  std::vector<std::vector<std::string>> rows;
  for (const HeadCheckRow& row : r.rows) {
    std::vector<std::string> cells{
        view_text(row.yaw_deg), row.expression,
        row.found ? fmt::format("found ({:.2f})", row.confidence) : std::string("not found"),
        fmt::format("{:.0f}", row.iod_px)};
    for (double e : row.feature_error) cells.push_back(share_text(e));
    cells.push_back(row.found ? fmt::format("{} {}", row.worst_point, share_text(row.worst_error))
                              : std::string("-"));
    if (row.scored && markdown) cells[1] = "**" + cells[1] + "** (aim)";
    rows.push_back(cells);
  }
  std::string out = table_text(header, rows, 2, markdown);
  out += fmt::format(
      "\nFaces found: {} of {} renders (aim: all). Neutral front view, every checked landmark "
      "within {:.0f} % of the inter-ocular distance: {}.\n",
      r.found, r.renders, 100 * r.options.aim_share, r.landmarks_met ? "met" : "not met");
  const auto scored = std::find_if(r.rows.begin(), r.rows.end(),
                                   [](const HeadCheckRow& row) { return row.scored; });
  if (scored != r.rows.end() && scored->found) {
    out += fmt::format(
        "\nNeutral front view, where each landmark lies from the head's point (shares of the "
        "IOD; outward: + away from the face's midline, toward the image's right for the nose "
        "tip and the chin; up: + up):\n\n");
    out += offsets_table(*scored, markdown);
  }
  return out;
}

}  // namespace

LandmarkOffset landmark_offset(const FeaturePointId& point, double landmark_x, double landmark_y,
                               double point_x, double point_y, double midline_x, double iod_px) {
  // Within a hundredth of the IOD of the midline a point is on it: its side is the image's right.
  const double side = point_x < midline_x - 0.01 * iod_px ? -1.0 : 1.0;
  return {point, side * (landmark_x - point_x) / iod_px, (point_y - landmark_y) / iod_px};
}

const std::vector<HeadFeature>& head_check_features() {
  static const std::vector<HeadFeature> features{
      {"eye corners", {{3, 7}, {3, 11}, {3, 8}, {3, 12}}},
      {"mouth corners", {{8, 3}, {8, 4}}},
      {"nose tip", {{9, 3}}},
      {"chin", {{2, 1}}},
      {"brows", {{4, 1}, {4, 2}, {4, 3}, {4, 4}, {4, 5}, {4, 6}}},
  };
  return features;
}

long head_check_renders(const HeadCheckOptions& options) {
  return static_cast<long>(options.yaws_deg.size()) * (kExpressions + 1);
}

HeadCheckResult check_head(const FaceModel& model, const ExpressionLibrary& library,
                           const HeadCheckOptions& options,
                           const std::function<void(long, long)>& progress) {
  if (options.width < 64 || options.height < 64 || options.yaws_deg.empty())
    throw InputError("head check: the renders need a size of at least 64x64 and one view");
  for (const HeadFeature& f : head_check_features())
    for (const FeaturePointId& p : f.points)
      if (!model.has_feature_point(p))
        throw InputError(fmt::format("head check: face model '{}' has no feature point {}",
                                     model.name, p.str()));
  // Which landmarks name each checked point (means of iBUG points, as the tracker reads them).
  const tracking::IbugMapping mapping = tracking::default_ibug_mapping();
  std::map<FeaturePointId, const tracking::IbugMarker*> landmark_of;
  for (const tracking::IbugMarker& m : mapping.markers) landmark_of[m.feature_point] = &m;
  for (const HeadFeature& f : head_check_features())
    for (const FeaturePointId& p : f.points)
      if (!landmark_of.count(p))
        throw InputError("head check: the iBUG mapping does not name " + p.str());

  tracking::LandmarkModel detector(
      options.landmark_model.empty() ? tracking::default_landmark_model() : options.landmark_model);
  render::RenderOptions ro;
  ro.width = options.width;
  ro.height = options.height;
  render::FaceRenderer face(model, &library, ro);
  const double aspect = static_cast<double>(options.width) / options.height;

  HeadCheckResult result;
  result.options = options;
  const long total = head_check_renders(options);
  cv::Mat bgr, gray;
  for (double yaw : options.yaws_deg) {
    render::CameraPose pose = render::CameraPose::front();
    pose.yaw_deg = yaw;
    const render::PixelProjector projector{render::frame_camera(pose, face.framing(), aspect),
                                           options.width, options.height};
    for (int select = 0; select <= kExpressions; ++select) {
      HeadCheckRow row;
      row.expression = select == 0 ? std::string("neutral")
                                   : std::string(ExpressionLibrary::expression_name(select));
      row.yaw_deg = yaw;
      row.scored = select == 0 && yaw == 0;
      face.render_into(expression_frame(select, options.expression_intensity), pose, bgr);
      auto projected = [&](const FeaturePointId& p) {
        cv::Point2d px(kNaN, kNaN);
        projector.project(face.positions()[static_cast<std::size_t>(model.feature_points.at(p))],
                          px);
        return px;
      };
      row.iod_px = cv::norm(projected(kRightOuterEye) - projected(kLeftOuterEye));
      const double midline_x = (projected(kRightOuterEye).x + projected(kLeftOuterEye).x) / 2;

      cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
      auto faces =
          detector.detect(gray, cv::Rect(0, 0, gray.cols, gray.rows), options.min_face_px, 0.0);
      row.found = !faces.empty();
      row.feature_error.assign(head_check_features().size(), kNaN);
      std::vector<cv::Point2d> landmarks;
      cv::Rect2d box;
      if (row.found) {
        const auto best = std::max_element(faces.begin(), faces.end(), [](auto& a, auto& b) {
          return a.box.area() < b.box.area();
        });
        row.confidence = best->confidence;
        box = best->box;
        landmarks = detector.fit(gray, box);
        for (std::size_t f = 0; f < head_check_features().size(); ++f) {
          double worst = 0;
          for (const FeaturePointId& p : head_check_features()[f].points) {
            const cv::Point2d l = tracking::mapped_position(*landmark_of.at(p), landmarks),
                              q = projected(p);
            row.offsets.push_back(landmark_offset(p, l.x, l.y, q.x, q.y, midline_x, row.iod_px));
            const double e = cv::norm(l - q) / row.iod_px;
            worst = std::max(worst, e);
            if (e > row.worst_error) {
              row.worst_error = e;
              row.worst_point = p.str();
            }
          }
          row.feature_error[f] = worst;
        }
      }
      if (!options.image_dir.empty()) {
        cv::Mat shown = bgr.clone();
        if (row.found) cv::rectangle(shown, box, {230, 0, 0}, 1);
        for (const cv::Point2d& l : landmarks)
          cv::circle(shown, l, 2, {0, 200, 0}, cv::FILLED, cv::LINE_AA);
        for (const HeadFeature& f : head_check_features())
          for (const FeaturePointId& p : f.points)
            cv::circle(shown, projected(p), 3, {0, 0, 230}, 1, cv::LINE_AA);
        const std::string name = fmt::format(
            "{}_{}.png", yaw == 0 ? std::string("front") : fmt::format("yaw{:+.0f}", yaw),
            row.expression);
        render::write_image(options.image_dir / name, shown);
      }
      ++result.renders;
      if (row.found) ++result.found;
      result.rows.push_back(row);
      if (progress) progress(result.renders, total);
    }
  }
  // Met when the neutral front view was rendered and each of its landmarks is within the aim.
  const auto scored = std::find_if(result.rows.begin(), result.rows.end(),
                                   [](const HeadCheckRow& r) { return r.scored; });
  result.landmarks_met =
      scored != result.rows.end() && scored->found && scored->worst_error <= options.aim_share;
  return result;
}

std::string head_check_table_text(const HeadCheckResult& result) {
  return table(result, false);
}
std::string head_check_table_markdown(const HeadCheckResult& result) {
  return table(result, true);
}

}  // namespace rostro::eval
