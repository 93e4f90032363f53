#include "eval/photo_scene.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>

#include "eval/draw_tag.hpp"
#include "facecore/error.hpp"
#include "tracking/ibug_mapping.hpp"
#include "tracking/landmark_model.hpp"

namespace rostro::eval {
namespace {

constexpr double kPi = std::numbers::pi;
// The canvas is this many times finer than the output frame.
constexpr int kSupersample = 2;
// Where a Gaussian bump is cut off, in sigmas: exp(-12.5) of its amplitude is below 1e-4 px.
constexpr double kBumpReach = 5;

double norm(cv::Point2d p) {
  return std::hypot(p.x, p.y);
}

cv::Point2d unit(cv::Point2d p) {
  const double n = norm(p);
  return n > 0 ? p / n : cv::Point2d(1, 0);
}

// An affine map x -> a * x + b.
struct Affine {
  cv::Matx22d a = cv::Matx22d::eye();
  cv::Point2d b;
  cv::Point2d operator()(cv::Point2d p) const {
    return {a(0, 0) * p.x + a(0, 1) * p.y + b.x, a(1, 0) * p.x + a(1, 1) * p.y + b.y};
  }
  Affine inverse() const {
    Affine inv;
    inv.a = a.inv();
    inv.b = -(
        cv::Point2d(inv.a(0, 0) * b.x + inv.a(0, 1) * b.y, inv.a(1, 0) * b.x + inv.a(1, 1) * b.y));
    return inv;
  }
};

// One Gaussian displacement: v * exp(-|p - centre|^2 / (2 sigma^2)).
struct Bump {
  cv::Point2d centre;
  double sigma = 1;
  cv::Point2d v;
};

// F(p) = G(p + D(p)), D the sum of the bumps.
struct Warp {
  Affine g;
  std::vector<Bump> bumps;

  cv::Point2d displacement(cv::Point2d p) const {
    cv::Point2d d(0, 0);
    for (const Bump& b : bumps) {
      const cv::Point2d r = p - b.centre;
      d += b.v * std::exp(-(r.x * r.x + r.y * r.y) / (2 * b.sigma * b.sigma));
    }
    return d;
  }
  cv::Point2d forward(cv::Point2d p) const { return g(p + displacement(p)); }
};

// Solves p + D(p) = z by Newton's method, over the bumps that reach z.
cv::Point2d undo_bumps(const std::vector<const Bump*>& near, cv::Point2d z) {
  cv::Point2d p = z;
  for (int it = 0; it < 8; ++it) {
    cv::Point2d d(0, 0);
    double j00 = 1, j01 = 0, j10 = 0, j11 = 1;
    for (const Bump* b : near) {
      const cv::Point2d r = p - b->centre;
      const double is2 = 1 / (b->sigma * b->sigma);
      const double g = std::exp(-0.5 * (r.x * r.x + r.y * r.y) * is2);
      d += b->v * g;
      // d(v g)/dp = v (-g r / sigma^2)^T
      j00 -= b->v.x * g * r.x * is2;
      j01 -= b->v.x * g * r.y * is2;
      j10 -= b->v.y * g * r.x * is2;
      j11 -= b->v.y * g * r.y * is2;
    }
    const cv::Point2d res = p + d - z;
    if (res.x * res.x + res.y * res.y < 1e-16) break;
    const double det = j00 * j11 - j01 * j10;
    p -= cv::Point2d((j11 * res.x - j01 * res.y) / det, (-j10 * res.x + j00 * res.y) / det);
  }
  return p;
}

// The landmarks of the chosen face, in photo pixels.
struct FittedFace {
  std::vector<cv::Point2d> landmarks;
  cv::Rect2d box;
};

FittedFace fit_face(const cv::Mat& photo, int index, const std::string& name) {
  tracking::LandmarkModel model(tracking::default_landmark_model());
  cv::Mat gray;
  cv::cvtColor(photo, gray, cv::COLOR_BGR2GRAY);
  auto faces = model.detect(gray, {0, 0, gray.cols, gray.rows}, 36, 0.0);
  if (faces.empty()) throw InputError(name + ": no face found in the photo");
  std::sort(faces.begin(), faces.end(),
            [](const auto& a, const auto& b) { return a.box.area() > b.box.area(); });
  if (index < 0 || index >= static_cast<int>(faces.size()))
    throw InputError(name + ": face " + std::to_string(index) + " asked for, the photo has " +
                     std::to_string(faces.size()) + " (0 is the largest)");
  FittedFace f;
  f.box = faces[static_cast<std::size_t>(index)].box;
  f.landmarks = model.fit(gray, f.box);
  return f;
}

// Least-squares affine from `from` to `to` (at least three points, not all on a line).
Affine fit_affine(const std::vector<cv::Point2d>& from, const std::vector<cv::Point2d>& to) {
  const int n = static_cast<int>(from.size());
  cv::Mat a(2 * n, 6, CV_64F, cv::Scalar(0)), y(2 * n, 1, CV_64F);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    a.at<double>(2 * i, 0) = from[k].x;
    a.at<double>(2 * i, 1) = from[k].y;
    a.at<double>(2 * i, 2) = 1;
    a.at<double>(2 * i + 1, 3) = from[k].x;
    a.at<double>(2 * i + 1, 4) = from[k].y;
    a.at<double>(2 * i + 1, 5) = 1;
    y.at<double>(2 * i) = to[k].x;
    y.at<double>(2 * i + 1) = to[k].y;
  }
  cv::Mat x;
  cv::solve(a, y, x, cv::DECOMP_SVD);
  Affine m;
  m.a = {x.at<double>(0), x.at<double>(1), x.at<double>(3), x.at<double>(4)};
  m.b = {x.at<double>(2), x.at<double>(5)};
  return m;
}

// The layout's frontal millimetres -> photo pixels: an affine fitted to the control points
// plus their residuals spread by normalised Gaussian weights (Nadaraya-Watson): smooth, equal
// to a control point's residual at an isolated control point, and never beyond the residuals'
// range (an interpolating Gaussian RBF through 22 uneven points overshoots by tens of pixels
// between them).
struct SmoothMap {
  Affine affine;
  std::vector<cv::Point2d> centres, residuals;
  double sigma_mm = 16;

  cv::Point2d operator()(cv::Point2d mm) const {
    cv::Point2d sum(0, 0);
    double weight = 0;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      const cv::Point2d r = mm - centres[i];
      const double w = std::exp(-(r.x * r.x + r.y * r.y) / (2 * sigma_mm * sigma_mm));
      sum += residuals[i] * w;
      weight += w;
    }
    return affine(mm) + (weight > 1e-12 ? sum / weight : cv::Point2d(0, 0));
  }
};

SmoothMap fit_smooth_map(const std::vector<cv::Point2d>& mm, const std::vector<cv::Point2d>& px) {
  SmoothMap m;
  m.affine = fit_affine(mm, px);
  m.centres = mm;
  for (std::size_t i = 0; i < mm.size(); ++i) m.residuals.push_back(px[i] - m.affine(mm[i]));
  return m;
}

// Face geometry at rest, in output pixels.
struct FaceFrame {
  std::vector<cv::Point2d> lm;  // the 68 landmarks
  cv::Point2d right;            // unit, from the image-left eye to the image-right eye
  cv::Point2d up;               // unit, from the mouth toward the eyes
  double eye = 0;               // mean eye width (corner to corner)
  double mouth = 0;             // mouth width

  cv::Point2d mean(int from, int to) const {  // 0-based, inclusive
    cv::Point2d s(0, 0);
    for (int i = from; i <= to; ++i) s += lm[static_cast<std::size_t>(i)];
    return s / (to - from + 1);
  }
  cv::Point2d at(int i) const { return lm[static_cast<std::size_t>(i)]; }
};

FaceFrame face_frame(std::vector<cv::Point2d> lm) {
  FaceFrame f;
  f.lm = std::move(lm);
  f.right = unit(f.at(45) - f.at(36));
  f.up = {f.right.y, -f.right.x};
  if ((f.mean(36, 47) - f.mean(48, 59)).dot(f.up) < 0) f.up = -f.up;
  f.eye = (norm(f.at(39) - f.at(36)) + norm(f.at(45) - f.at(42))) / 2;
  f.mouth = norm(f.at(54) - f.at(48));
  return f;
}

// Where a make-up artist puts the dot of `fp`, starting from `p` (the landmark's place): on
// skin beside the feature, not on the brow hair, the lid line or a corner of the eye or mouth.
cv::Point2d nudge(const std::string& fp, cv::Point2d p, const FaceFrame& f, double radius) {
  const double e = f.eye;
  if (fp.rfind("4.", 0) == 0) return p + f.up * (0.04 * e + radius);      // brows
  if (fp == "3.1" || fp == "3.2") return p + f.up * (0.14 * e + radius);  // upper lids
  if (fp == "3.3" || fp == "3.4") return p - f.up * (0.10 * e + radius);  // lower lids
  if (fp == "3.7") return p + f.right * (0.10 * e + radius);              // outer corners
  if (fp == "3.12") return p - f.right * (0.10 * e + radius);
  if (fp == "3.11") return p - f.right * (0.05 * e + radius);  // inner corners
  if (fp == "3.8") return p + f.right * (0.05 * e + radius);
  if (fp == "8.3") return p + f.right * (0.04 * f.mouth + radius);  // mouth corners
  if (fp == "8.4") return p - f.right * (0.04 * f.mouth + radius);
  if (fp == "8.1") return p + f.up * (0.5 * radius);  // lip borders
  if (fp == "8.2" || fp == "8.7" || fp == "8.8") return p - f.up * (0.5 * radius);
  if (fp == "2.1") return p + (f.at(57) - p) * 0.15;  // chin
  if (fp == "8.5" || fp == "8.6") {                   // on the upper lip's outer contour, like 8.1
    cv::Point2d best = p;
    double best_d = 1e300;
    for (int i = 48; i < 54; ++i)
      for (int k = 0; k <= 16; ++k) {
        const cv::Point2d q = f.at(i) + (f.at(i + 1) - f.at(i)) * (k / 16.0);
        if (const double d = norm(q - p); d < best_d) best_d = d, best = q;
      }
    return best + f.up * (0.5 * radius);
  }
  return p;
}

// Pushes `p` out of the disc (`centre`, `clear`).
cv::Point2d keep_clear(cv::Point2d p, cv::Point2d centre, double clear) {
  const cv::Point2d d = p - centre;
  const double n = norm(d);
  if (n >= clear) return p;
  return centre + unit(d) * clear;
}

struct Painted {
  const tracking::MarkerSpec* spec = nullptr;
  cv::Point2d at;                      // output pixels at rest
  std::array<cv::Point2d, 4> corners;  // tags
};

// Canvas coordinates of output pixels at rest: canvas pixel i's centre is output x =
// origin + (i + 0.5) / kSupersample - 0.5.
struct CanvasFrame {
  cv::Point2d origin;
  cv::Point2d to_canvas(cv::Point2d p) const {
    return (p - origin + cv::Point2d(0.5, 0.5)) * kSupersample - cv::Point2d(0.5, 0.5);
  }
};

cv::Scalar ring_mean(const cv::Mat& image, cv::Point2d c, double r_in, double r_out) {
  const cv::Rect box = cv::Rect(cvFloor(c.x - r_out), cvFloor(c.y - r_out), cvCeil(2 * r_out) + 2,
                                cvCeil(2 * r_out) + 2) &
                       cv::Rect(0, 0, image.cols, image.rows);
  if (box.area() <= 0) return cv::Scalar(128, 128, 128);
  cv::Mat mask(box.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < box.height; ++y)
    for (int x = 0; x < box.width; ++x) {
      const double d = std::hypot(box.x + x - c.x, box.y + y - c.y);
      if (d >= r_in && d <= r_out) mask.at<uchar>(y, x) = 255;
    }
  if (cv::countNonZero(mask) == 0) return cv::Scalar(128, 128, 128);
  return cv::mean(image(box), mask);
}

// A disc of radius `r` (canvas pixels) at `c`, with a linear edge `edge` wide centred on r:
// exactly symmetric about c.
void paint_dot(cv::Mat& canvas, cv::Point2d c, double r, double edge, cv::Scalar ink) {
  const double reach = r + edge;
  const cv::Rect box = cv::Rect(cvFloor(c.x - reach), cvFloor(c.y - reach), cvCeil(2 * reach) + 2,
                                cvCeil(2 * reach) + 2) &
                       cv::Rect(0, 0, canvas.cols, canvas.rows);
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      const double alpha = std::clamp((r - std::hypot(x - c.x, y - c.y)) / edge + 0.5, 0.0, 1.0);
      if (alpha <= 0) continue;
      cv::Vec3b& px = canvas.at<cv::Vec3b>(y, x);
      for (int ch = 0; ch < 3; ++ch)
        px[ch] = cv::saturate_cast<uchar>((1 - alpha) * px[ch] + alpha * ink[ch]);
    }
}

// The light headband the tags sit on: a band across the forehead (layout millimetres through
// `affine`), slightly shaded top to bottom.
void paint_headband(cv::Mat& canvas, const Affine& mm_to_canvas) {
  const double x0 = -76, x1 = 76, y0 = -104, y1 = -66;  // frontal axes, y down
  std::vector<cv::Point> poly;
  for (const cv::Point2d mm :
       {cv::Point2d(x0, y0), cv::Point2d(x1, y0), cv::Point2d(x1, y1), cv::Point2d(x0, y1)}) {
    const cv::Point2d c = mm_to_canvas(mm);
    poly.emplace_back(cvRound(c.x * 16), cvRound(c.y * 16));
  }
  cv::fillConvexPoly(canvas, poly, cv::Scalar(206, 212, 218), cv::LINE_AA, 4);
}

// The expression bumps at full activation, each with the channel that drives it.
enum Channel { kJaw, kSmile, kBrows };
struct ChannelBump {
  Bump bump;
  Channel channel;
};

std::vector<ChannelBump> expression_bumps(const FaceFrame& f, double w) {
  const cv::Point2d down = -f.up;
  std::vector<ChannelBump> out;
  // Jaw and lower lip down: centred between the lower lip and the chin.
  out.push_back({{(f.at(57) + f.at(8)) / 2, 0.16 * w, down * (0.05 * w)}, kJaw});
  // Mouth corners out and up.
  out.push_back({{f.at(48), 0.11 * w, -f.right * (0.025 * w) + f.up * (0.012 * w)}, kSmile});
  out.push_back({{f.at(54), 0.11 * w, f.right * (0.025 * w) + f.up * (0.012 * w)}, kSmile});
  // Brows up.
  out.push_back({{f.mean(17, 21), 0.10 * w, f.up * (0.02 * w)}, kBrows});
  out.push_back({{f.mean(22, 26), 0.10 * w, f.up * (0.02 * w)}, kBrows});
  return out;
}

double raised_cosine(double t, double hz, double phase = 0) {
  return 0.5 * (1 - std::cos(2 * kPi * hz * t + phase));
}

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// The length of the first-frame blur on frame k (fading to none by frame 5).
double blur_length(const PhotoSceneOptions& o, long k) {
  return k < 5 ? o.first_blur_px * (1 - static_cast<double>(k) / 5) : 0.0;
}

// The warp of frame k.
Warp frame_warp(const PhotoSceneOptions& o, const std::vector<ChannelBump>& bumps,
                cv::Point2d centre, long k) {
  const double t = static_cast<double>(k) / o.fps, w = o.face_px;
  Warp warp;
  double roll = 0, squeeze = 1, scale = 1;
  cv::Point2d shift(0, 0);
  const bool turns = o.motion == "turns" || o.motion == "talk";
  const bool mouth = o.motion == "mouth" || o.motion == "talk";
  if (turns) {
    roll = 8 * kPi / 180 * std::sin(2 * kPi * t / 4);
    squeeze = 0.925 + 0.075 * std::cos(2 * kPi * t / 3);
    scale = 1 + 0.05 * std::sin(2 * kPi * t / 5);
    shift = {0.06 * w * std::sin(2 * kPi * t / 4.5), 0.03 * w * std::sin(2 * kPi * t / 3.3)};
  }
  if (mouth) {
    const double gain = o.motion == "talk" ? 0.5 : 1.0;
    for (const ChannelBump& cb : bumps) {
      double a = 0;
      switch (cb.channel) {
        case kJaw:
          a = gain * raised_cosine(t, 2.5);
          break;
        case kSmile:
          a = gain * raised_cosine(t, 0.9, 1.0);
          break;
        case kBrows:
          a = gain * raised_cosine(t, 0.6);
          break;
      }
      if (a <= 1e-12) continue;
      Bump b = cb.bump;
      b.v *= a;
      warp.bumps.push_back(b);
    }
  }
  // A late start: the face slides in from beyond the right edge.
  if (o.enter_seconds > 0)
    shift.x += (1 - smoothstep(t / o.enter_seconds)) * (o.size.width - centre.x + 0.8 * w);
  // The first frames' horizontal motion, as long a step each frame as that frame's blur.
  double lead = 0;
  for (long j = k + 1; j < 5; ++j) lead += blur_length(o, j);
  shift.x -= lead;

  const double c = std::cos(roll), s = std::sin(roll);
  const cv::Matx22d a = cv::Matx22d(c, -s, s, c) * cv::Matx22d(squeeze * scale, 0, 0, scale);
  warp.g.a = a;
  warp.g.b =
      centre + shift -
      cv::Point2d(a(0, 0) * centre.x + a(0, 1) * centre.y, a(1, 0) * centre.x + a(1, 1) * centre.y);
  return warp;
}

// The inverse map of `warp` for remap: each output pixel's place on the canvas. It is solved
// exactly at even rows and columns and interpolated halfway between them: the affine part is
// linear, and the bumps' curvature (A / sigma^2, under 0.015 px per px^2 for a face 180 px
// wide) leaves a midpoint within h^2 / 8 of it (h = 2): 0.01 px, about what remap's rounding of
// its coordinates to 1/32 canvas pixel costs.
void inverse_map(const Warp& warp, const CanvasFrame& cf, cv::Size size, cv::Mat& map) {
  map.create(size, CV_32FC2);
  const Affine ginv = warp.g.inverse();
  struct Box {
    const Bump* bump;
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  for (const Bump& b : warp.bumps) {
    const double r = kBumpReach * b.sigma + norm(b.v);
    boxes.push_back({&b, b.centre.x - r, b.centre.y - r, b.centre.x + r, b.centre.y + r});
  }
  std::vector<const Bump*> near;
  const auto exact = [&](int x, int y) {
    cv::Point2d p = ginv(cv::Point2d(x, y));
    near.clear();
    for (const Box& b : boxes)
      if (p.x >= b.x0 && p.x <= b.x1 && p.y >= b.y0 && p.y <= b.y1) near.push_back(b.bump);
    if (!near.empty()) p = undo_bumps(near, p);
    const cv::Point2d c = cf.to_canvas(p);
    return cv::Vec2f(static_cast<float>(c.x), static_cast<float>(c.y));
  };
  for (int y = 0; y < size.height; y += 2) {
    auto* row = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < size.width; x += 2) row[x] = exact(x, y);
    for (int x = 1; x < size.width; x += 2)
      row[x] = x + 1 < size.width ? (row[x - 1] + row[x + 1]) * 0.5f : exact(x, y);
  }
  for (int y = 1; y < size.height; y += 2) {
    auto* row = map.ptr<cv::Vec2f>(y);
    if (y + 1 < size.height) {
      const auto* above = map.ptr<cv::Vec2f>(y - 1);
      const auto* below = map.ptr<cv::Vec2f>(y + 1);
      for (int x = 0; x < size.width; ++x) row[x] = (above[x] + below[x]) * 0.5f;
    } else {
      for (int x = 0; x < size.width; ++x) row[x] = exact(x, y);
    }
  }
}

// A horizontal line of `length` pixels, centred: the taps at the ends are weighted by how much
// of them the line covers, so a non-integer length blurs by exactly that much.
cv::Mat line_kernel(double length) {
  const int half = static_cast<int>(std::ceil(length / 2 + 0.5));
  cv::Mat k(1, 2 * half + 1, CV_32F);
  double sum = 0;
  for (int i = -half; i <= half; ++i) {
    const double lo = std::max(i - 0.5, -length / 2), hi = std::min(i + 0.5, length / 2);
    const double w = std::max(0.0, hi - lo);
    k.at<float>(0, i + half) = static_cast<float>(w);
    sum += w;
  }
  return k / sum;
}

// A skin-coloured hand: an ellipse crossing the frame at the mouth's height.
struct Hand {
  bool active = false;
  cv::Point2d centre;
  cv::Size2d axes;
  bool covers(cv::Point2d p, double margin) const {
    if (!active) return false;
    const double dx = (p.x - centre.x) / (axes.width + margin);
    const double dy = (p.y - centre.y) / (axes.height + margin);
    return dx * dx + dy * dy <= 1;
  }
};

void paint_hand(cv::Mat& frame, const Hand& hand, cv::Scalar skin) {
  const cv::Rect box = cv::Rect(cvFloor(hand.centre.x - hand.axes.width - 2),
                                cvFloor(hand.centre.y - hand.axes.height - 2),
                                cvCeil(2 * hand.axes.width) + 5, cvCeil(2 * hand.axes.height) + 5) &
                       cv::Rect(0, 0, frame.cols, frame.rows);
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      const double dx = (x - hand.centre.x) / hand.axes.width;
      const double dy = (y - hand.centre.y) / hand.axes.height;
      const double r = std::sqrt(dx * dx + dy * dy);
      // A soft edge about two pixels wide.
      const double alpha =
          std::clamp((1 - r) * std::min(hand.axes.width, hand.axes.height) / 2 + 0.5, 0.0, 1.0);
      if (alpha <= 0) continue;
      const double shade = 1.08 - 0.2 * dx;  // lit from the left
      cv::Vec3b& px = frame.at<cv::Vec3b>(y, x);
      for (int ch = 0; ch < 3; ++ch)
        px[ch] = cv::saturate_cast<uchar>((1 - alpha) * px[ch] + alpha * shade * skin[ch]);
    }
}

void validate(const PhotoSceneOptions& o) {
  auto bad = [&](const std::string& what) { throw InputError(o.photo.string() + ": " + what); };
  if (o.size.width < 64 || o.size.height < 64) bad("the frame size should be at least 64x64");
  if (!(o.face_px >= 40)) bad("face_px should be at least 40");
  if (!(o.dot_px >= 2 && o.dot_px <= 40)) bad("dot_px should be 2 to 40");
  if (!(o.fps > 0) || !(o.seconds > 0)) bad("fps and seconds should be positive");
  if (o.motion != "still" && o.motion != "turns" && o.motion != "mouth" && o.motion != "talk")
    bad("unknown motion '" + o.motion + "' (still, turns, mouth, talk)");
  if (!(o.first_blur_px >= 0) || !(o.enter_seconds >= 0) || !(o.noise >= 0) ||
      !(o.brightness > 0) || !(o.gradient >= 0 && o.gradient < 1))
    bad("first_blur_px, enter_seconds and noise should be at least 0, brightness above 0, "
        "gradient 0 to below 1");
}

// Each layout marker's place in the output frame at rest (see the header): dots from their
// landmark or the smooth map, nudged onto skin and kept apart; tags through the map's affine.
std::vector<Painted> place_markers(const tracking::MarkerLayout& layout, const FaceFrame& face,
                                   const SmoothMap& map, double dot_px, double jitter,
                                   unsigned seed) {
  // A make-up artist's hand: each dot up to `jitter` eye widths off its place, uniformly over
  // a disc (the scene's own placement stream, apart from its noise).
  std::mt19937 hand(seed * 2654435761u + 17);
  std::uniform_real_distribution<double> unit_interval(0, 1);
  const tracking::IbugMapping mapping = tracking::default_ibug_mapping();
  std::map<std::string, const tracking::IbugMarker*> by_fp;
  for (const tracking::IbugMarker& m : mapping.markers) by_fp[m.feature_point.str()] = &m;
  const double radius = dot_px / 2;
  std::vector<Painted> painted;
  for (const tracking::MarkerSpec& spec : layout.markers) {
    Painted p;
    p.spec = &spec;
    if (spec.is_tag()) {
      const auto mm = spec.tag_corners_frontal();
      for (std::size_t q = 0; q < 4; ++q) p.corners[q] = map.affine(mm[q]);
      p.at = map.affine(spec.frontal());
    } else {
      const std::string fp = spec.feature_point.str();
      cv::Point2d at =
          by_fp.count(fp) ? tracking::mapped_position(*by_fp[fp], face.lm) : map(spec.frontal());
      at = nudge(fp, at, face, radius);
      // Clear of the pupils and the nostrils.
      at = keep_clear(at, face.mean(36, 41), 0.3 * face.eye + radius);
      at = keep_clear(at, face.mean(42, 47), 0.3 * face.eye + radius);
      at = keep_clear(at, (face.at(31) + face.at(32)) / 2, 0.12 * face.eye + radius);
      at = keep_clear(at, (face.at(34) + face.at(35)) / 2, 0.12 * face.eye + radius);
      const double r = jitter * face.eye * std::sqrt(unit_interval(hand));
      const double a = 2 * std::numbers::pi * unit_interval(hand);
      p.at = at + cv::Point2d(r * std::cos(a), r * std::sin(a));
    }
    painted.push_back(p);
  }
  // Dots an artist would not paint into one another (landmarks of a turned face crowd the far
  // side): pairs nearer than 1.8 diameters are pushed apart along their line.
  const double spacing = 1.8 * dot_px;
  for (int round = 0; round < 20; ++round)
    for (Painted& a : painted)
      for (Painted& b : painted)
        if (&a < &b && !a.spec->is_tag() && !b.spec->is_tag()) {
          const cv::Point2d d = b.at - a.at;
          if (const double n = norm(d); n < spacing) {
            const cv::Point2d push = unit(d) * ((spacing - n) / 2);
            a.at -= push;
            b.at += push;
          }
        }
  return painted;
}

// The smooth map from layout millimetres to the output frame, fitted to the layout's dots that
// have an iBUG counterpart.
SmoothMap layout_map(const tracking::MarkerLayout& layout, const FaceFrame& face) {
  const tracking::IbugMapping mapping = tracking::default_ibug_mapping();
  std::vector<cv::Point2d> control_mm, control_px;
  for (const tracking::MarkerSpec& spec : layout.markers)
    for (const tracking::IbugMarker& m : mapping.markers)
      if (!spec.is_tag() && m.feature_point == spec.feature_point) {
        control_mm.push_back(spec.frontal());
        control_px.push_back(tracking::mapped_position(m, face.lm));
      }
  if (control_mm.size() < 4)
    throw InputError("layout " + layout.name + ": fewer than four dots have an iBUG counterpart");
  return fit_smooth_map(control_mm, control_px);
}

// The canvas placement that covers every output pixel's source in every frame.
std::pair<CanvasFrame, cv::Size> cover(const std::vector<Warp>& warps, cv::Size size,
                                       double margin) {
  cv::Point2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Warp& w : warps) {
    const Affine ginv = w.g.inverse();
    for (const cv::Point2d corner :
         {cv::Point2d(0, 0), cv::Point2d(size.width - 1, 0), cv::Point2d(0, size.height - 1),
          cv::Point2d(size.width - 1, size.height - 1)}) {
      const cv::Point2d p = ginv(corner);
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
  }
  CanvasFrame cf;
  cf.origin = {std::floor(lo.x - margin), std::floor(lo.y - margin)};
  return {cf,
          cv::Size(static_cast<int>(std::ceil(hi.x - cf.origin.x + margin + 1)) * kSupersample,
                   static_cast<int>(std::ceil(hi.y - cf.origin.y + margin + 1)) * kSupersample)};
}

// The headband and tags, then the dots, each a quarter of the skin around it (from `bare`).
void paint_markers(cv::Mat& canvas, const cv::Mat& bare, const std::vector<Painted>& painted,
                   const tracking::MarkerLayout& layout, const SmoothMap& map,
                   const CanvasFrame& cf, double radius) {
  Affine mm_to_canvas = map.affine;
  mm_to_canvas.a *= kSupersample;
  mm_to_canvas.b = cf.to_canvas(map.affine.b);
  if (layout.tag_count() > 0) paint_headband(canvas, mm_to_canvas);
  for (const Painted& p : painted)
    if (p.spec->is_tag()) {
      std::array<cv::Point2d, 4> c;
      for (std::size_t q = 0; q < 4; ++q) c[q] = cf.to_canvas(p.corners[q]);
      draw_tag(canvas, *p.spec, c);
    }
  const double r = radius * kSupersample;
  for (const Painted& p : painted)
    if (!p.spec->is_tag()) {
      const cv::Point2d c = cf.to_canvas(p.at);
      const cv::Scalar skin = ring_mean(bare, c, 1.6 * r, 3 * r);
      const bool dark = layout.polarity == tracking::DotPolarity::Dark;
      paint_dot(canvas, c, r, kSupersample, dark ? skin * 0.25 : cv::Scalar(245, 245, 245));
    }
}

// The hand at time t: crossing the frame from 30 % to 70 % of the take at the mouth's height.
Hand hand_at(const PhotoSceneOptions& o, const Warp& warp, const FaceFrame& face, double t,
             double seconds) {
  Hand hand;
  const double s = (t / seconds - 0.3) / 0.4;
  if (!o.hand || s <= 0 || s >= 1) return hand;
  hand.active = true;
  hand.axes = {0.28 * o.face_px, 0.4 * o.face_px};
  const cv::Point2d mouth = warp.forward((face.at(48) + face.at(54)) / 2);
  hand.centre = {-hand.axes.width + s * (o.size.width + 2 * hand.axes.width),
                 mouth.y + 0.1 * o.face_px};
  return hand;
}

// Every marker at F(painted position), visible as the header says.
tracking::TrackedFrame frame_truth(const std::vector<Painted>& painted, const Warp& warp,
                                   const Hand& hand, cv::Size size, double radius,
                                   std::vector<TagCorners>& corners) {
  const auto inside = [&](cv::Point2d p) {
    return p.x >= 0 && p.y >= 0 && p.x <= size.width - 1 && p.y <= size.height - 1;
  };
  tracking::TrackedFrame truth;
  for (const Painted& p : painted) {
    tracking::MarkerObservation obs;
    obs.marker = p.spec->id;
    obs.feature_point = p.spec->feature_point;
    obs.quality = 1;
    obs.position = warp.forward(p.at);
    if (p.spec->is_tag()) {
      TagCorners tc{p.spec->id, {}};
      bool visible = inside(obs.position) && !hand.covers(obs.position, 0);
      for (std::size_t q = 0; q < 4; ++q) {
        tc.corners[q] = warp.forward(p.corners[q]);
        visible = visible && inside(tc.corners[q]) && !hand.covers(tc.corners[q], 0);
      }
      obs.valid = visible;
      corners.push_back(tc);
    } else {
      obs.valid = inside(obs.position) && !hand.covers(obs.position, radius);
    }
    truth.markers.push_back(std::move(obs));
  }
  return truth;
}

// The camera: light (gain and falloff, `gain`), the first frames' blur, noise; 8-bit out.
void expose(const cv::Mat& frame, const cv::Mat& gain, double blur, double noise_sigma,
            std::mt19937& rng, cv::Mat& out) {
  cv::Mat lit;
  frame.convertTo(lit, CV_32FC3);
  cv::multiply(lit, gain, lit);
  if (blur > 0) cv::filter2D(lit, lit, -1, line_kernel(blur), {-1, -1}, 0, cv::BORDER_REFLECT_101);
  if (noise_sigma > 0) {
    cv::Mat noise(lit.size(), CV_32FC3);
    cv::RNG cvrng(static_cast<std::uint64_t>(rng()) << 32 | rng());
    cvrng.fill(noise, cv::RNG::NORMAL, 0.0, noise_sigma);
    lit += noise;
  }
  lit.convertTo(out, CV_8UC3);
}

}  // namespace

PhotoSceneResult render_photo_scene(const PhotoSceneOptions& o,
                                    const tracking::MarkerLayout& layout,
                                    const PhotoFrameSink& sink,
                                    const std::function<void(long)>& progress) {
  const std::string name = o.photo.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(o.photo, ec)) throw InputError(name + ": no photo there");
  validate(o);
  const cv::Mat photo = cv::imread(o.photo.string(), cv::IMREAD_COLOR);
  if (photo.empty()) throw InputError(name + ": not an image OpenCV can read");
  const FittedFace fitted = fit_face(photo, o.face, name);

  // Photo -> output pixels at rest: the face jaw-wide face_px, centred, a little low so the
  // headband above it stays in the frame.
  const double scale = o.face_px / norm(fitted.landmarks[16] - fitted.landmarks[0]);
  cv::Point2d anchor(0, 0);
  for (int i = 17; i <= 26; ++i) anchor += fitted.landmarks[static_cast<std::size_t>(i)] / 20.0;
  anchor += fitted.landmarks[8] / 2.0;
  const cv::Point2d centre(o.size.width / 2.0 - 0.5, o.size.height / 2.0 - 0.5 + 0.16 * o.face_px);
  const auto to_out = [&](cv::Point2d ph) { return (ph - anchor) * scale + centre; };
  std::vector<cv::Point2d> lm;
  for (const cv::Point2d& p : fitted.landmarks) lm.push_back(to_out(p));
  const FaceFrame face = face_frame(lm);

  const SmoothMap map = layout_map(layout, face);
  const std::vector<Painted> painted =
      place_markers(layout, face, map, o.dot_px, o.placement_jitter, o.seed);

  // Every frame's warp, and the canvas that covers every output pixel's source.
  const long frames = std::max(1L, std::lround(o.seconds * o.fps));
  const auto bumps = expression_bumps(face, o.face_px);
  double max_bump = 0;
  for (const ChannelBump& b : bumps) max_bump = std::max(max_bump, norm(b.bump.v));
  std::vector<Warp> warps;
  for (long k = 0; k < frames; ++k) warps.push_back(frame_warp(o, bumps, centre, k));
  const auto [cf, canvas_size] = cover(warps, o.size, max_bump + 4);

  // Photo -> canvas, resampled; then the markers painted on.
  const double k = scale * kSupersample;
  const cv::Point2d t0 = cf.to_canvas(to_out(cv::Point2d(0, 0)));
  cv::Mat canvas;
  cv::warpAffine(photo, canvas, cv::Matx23d(k, 0, t0.x, 0, k, t0.y), canvas_size, cv::INTER_CUBIC,
                 cv::BORDER_REFLECT_101);
  const cv::Mat bare = canvas.clone();
  paint_markers(canvas, bare, painted, layout, map, cf, o.dot_px / 2);
  const cv::Scalar skin =
      ring_mean(bare, cf.to_canvas(face.at(30)), 0, 0.25 * o.face_px * kSupersample);

  PhotoSceneResult result;
  result.face_box = fitted.box;
  for (const Painted& p : painted) result.painted.push_back(p.at);

  // Light: gain and a left-right falloff, fixed in the camera's frame.
  cv::Mat gain(o.size, CV_32FC3);
  for (int x = 0; x < o.size.width; ++x) {
    const float g =
        static_cast<float>(o.brightness * (1 - o.gradient * x / std::max(1, o.size.width - 1)));
    gain.col(x).setTo(cv::Scalar(g, g, g));
  }
  std::mt19937 rng(o.seed);
  cv::Mat inverse, frame, out;
  const double seconds = static_cast<double>(frames) / o.fps;
  for (long f = 0; f < frames; ++f) {
    const Warp& warp = warps[static_cast<std::size_t>(f)];
    const double t = static_cast<double>(f) / o.fps;
    inverse_map(warp, cf, o.size, inverse);
    cv::remap(canvas, frame, inverse, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
    const Hand hand = hand_at(o, warp, face, t, seconds);
    if (hand.active) paint_hand(frame, hand, skin);
    std::vector<TagCorners> corners;
    tracking::TrackedFrame truth = frame_truth(painted, warp, hand, o.size, o.dot_px / 2, corners);
    truth.frame = f;
    truth.time_s = t;
    expose(frame, gain, blur_length(o, f), o.noise, rng, out);
    sink(out);
    result.truth.push_back(std::move(truth));
    result.tag_corners.push_back(std::move(corners));
    if (progress) progress(f + 1);
  }
  return result;
}

}  // namespace rostro::eval
