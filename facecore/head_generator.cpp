#include "facecore/head_generator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include "facecore/error.hpp"
#include "facecore/texture_bake.hpp"

namespace rostro {
namespace {

using V3 = Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

// Layout of the head in millimetres, MPEG-4 frame: x toward the face's left, y up, z out.
constexpr double kEyeX = 32.0, kEyeY = 30.0;  // left pupil centre (x, y)
constexpr double kEyeR = 12.5;                // eyeball radius
constexpr double kLidH = 5.5;                 // half the eye opening: IRISD0 = 2 x this
constexpr double kLidHW = 12.5;               // half the eye opening's width
constexpr double kLidReach = 1.6 * kLidHW;    // reach of the eyelid cosine along x
constexpr double kLidGap = 0.8;               // eyelid skin in front of the eyeball
constexpr double kUpperLidLead = 0.4;         // upper lid in front of the lower
constexpr double kLashWidth = 1.0;  // the upper lash line's width at the eye's middle (mm)
constexpr double kBrowInnerX = 15.0, kBrowMidX = 31.5, kBrowOuterX = 47.0;  // 4.1, 4.3, 4.5
constexpr double kBrowInner = 6.0, kBrowOuter = 3.0;  // the brow's height at its ends
constexpr double kMouthY = -32.0, kMouthHW = 23.5;    // mouth line, inner corners at +-kMouthHW
constexpr double kOuterCornerX = 25.5;
// Past the lips' outer corners the skin moves with the corner, wholly from kCornerSkinX either
// side and partly from kCornerShareX, as far as kCornerReach from it.
constexpr double kCornerShareX = 16, kCornerSkinX = 28, kCornerReach = 26;
constexpr double kCapY = 60.0, kCrownY = 122.0, kNeckY = -150.0;
// Below the neck's foot the skin goes on into the shoulders, down to kFootY: 416 texels of the
// skin's texture below kNeckY, so that the face's texels lie where they would without them.
constexpr double kFootY = kNeckY - 416 * (kCrownY - kNeckY) / 1024;
// The head turns (FAPs 48-50) whole above kTurnTopY; the neck below twists less and less, and
// the shoulders below kTurnFootY stay.
constexpr double kTurnTopY = -95.0, kTurnFootY = -185.0;
constexpr double kEarY = 19.0;  // the ears' centre height
// The ears' half sizes: out from the head, up, front to back.
constexpr double kEarOut = 7.0, kEarUp = 29.0, kEarBack = 15.0;

double clamp01(double t) {
  return std::clamp(t, 0.0, 1.0);
}
double smoothstep(double e0, double e1, double x) {
  const double t = clamp01((x - e0) / (e1 - e0));
  return t * t * (3 - 2 * t);
}
double gauss(double d, double s) {
  return std::exp(-(d * d) / (s * s));
}
double rc(double d, double reach) {
  return d >= reach ? 0.0 : 0.5 * (1 + std::cos(kPi * d / reach));
}

// Catmull-Rom through (y, value) knots sorted by y, clamped outside.
double curve(const std::vector<std::pair<double, double>>& k, double y) {
  if (y <= k.front().first) return k.front().second;
  if (y >= k.back().first) return k.back().second;
  std::size_t i = 0;
  while (k[i + 1].first < y) ++i;
  auto at = [&](long j) {
    return k[static_cast<std::size_t>(std::clamp(j, 0L, static_cast<long>(k.size()) - 1))].second;
  };
  const double t = (y - k[i].first) / (k[i + 1].first - k[i].first);
  const auto li = static_cast<long>(i);
  const double p0 = at(li - 1), p1 = at(li), p2 = at(li + 1), p3 = at(li + 2);
  return 0.5 * ((2 * p1) + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t +
                (-p0 + 3 * p1 - 3 * p2 + p3) * t * t * t);
}

// Cross-section of the head at height y: half width, front and back extent, centre z. Below the
// neck's foot (-150) it flares into the shoulders and the top of the chest.
const std::vector<std::pair<double, double>> kHalfWidth = {
    {kFootY, 200}, {-240, 204}, {-222, 194}, {-205, 162}, {-190, 114}, {-176, 74},
    {-163, 59},    {-150, 52},  {-100, 50},  {-86, 50},   {-75, 46},   {-60, 56},
    {-40, 64},     {-20, 70},   {0, 73},     {30, 76},    {60, 75}};
const std::vector<std::pair<double, double>> kFront = {
    {kFootY, 100}, {-240, 98}, {-220, 92}, {-200, 80}, {-182, 65}, {-165, 56},
    {-150, 52},    {-100, 50}, {-90, 58},  {-80, 74},  {-70, 86},  {-55, 91},
    {-40, 93},     {-20, 95},  {0, 96},    {30, 93},   {60, 90}};
const std::vector<std::pair<double, double>> kBack = {
    {kFootY, 95}, {-240, 95}, {-220, 93}, {-200, 88}, {-182, 81},
    {-165, 74},   {-150, 70}, {-100, 68}, {-80, 72},  {-60, 82},
    {-40, 90},    {-20, 95},  {0, 98},    {30, 100},  {60, 98}};
const std::vector<std::pair<double, double>> kCentreZ = {
    {-150, -22}, {-100, -20}, {-80, -8}, {-60, 0}, {60, 0}};

// The aperture of the left eye at |x - kEyeX| = d, 1 at the centre, 0 at the corners; it
// follows the eyelid cosine so that closing both lids (512 IRISD each) shuts the eye.
double eye_aperture(double d) {
  if (d >= kLidHW) return 0.0;
  const double corner = rc(kLidHW, kLidReach);
  return (rc(d, kLidReach) - corner) / (1 - corner);
}

double mouth_aperture(double ax) {
  return ax >= kMouthHW ? 0.0 : std::pow(1 - (ax / kMouthHW) * (ax / kMouthHW), 0.6);
}
// Heights of the outer lip contour above / below the mouth line.
double upper_lip_height(double ax) {
  if (ax >= kOuterCornerX) return 0.0;
  const double u = ax / kOuterCornerX;
  const double bow = 1.2 * gauss(ax - 5.0, 3.5) - 0.8 * gauss(ax, 2.0);  // Cupid's bow
  return (7.0 + bow) * std::pow(1 - u * u, 0.7);
}
double lower_lip_height(double ax) {
  if (ax >= kOuterCornerX) return 0.0;
  const double u = ax / kOuterCornerX;
  return 9.0 * std::pow(1 - u * u, 0.8);
}

enum class Side { None, Upper, Lower };

struct SkinShape {
  double eye_z = 0;  // z of the eyeball centres

  // Surface point at height y and angle phi (0 front, +pi/2 the face's left) with the
  // cross-section scaled by s (s < 1 in the skull cap).
  V3 base(double y, double phi, double s, double shape_y) const {
    const double a = curve(kHalfWidth, shape_y), f = curve(kFront, shape_y),
                 b = curve(kBack, shape_y), zc = curve(kCentreZ, shape_y);
    const double sp = std::sin(std::abs(phi)), cp = std::cos(phi);
    const double p = cp >= 0 ? 2.6 : 2.0;  // flatter face, rounder skull
    const double x = s * a * std::pow(sp, 2.0 / p);
    const double z = zc + s * (cp >= 0 ? f * std::pow(cp, 2.0 / p) : -b * std::pow(-cp, 2.0 / p));
    return {phi < 0 ? -x : x, y, z};
  }

  // Relief of the face, added along z (the face is the front of the head).
  static double relief(double ax, double y) {
    double dz = 0;
    // Nose: a ridge from the nasion to the tip, then the underside to the base (9.15).
    double nose = 0, width = 7.0;
    if (y >= 3 && y <= 33) {
      nose = 1.5 + 21.0 * std::pow((33 - y) / 30.0, 1.4);
      width = 6.0 + 5.0 * (33 - y) / 30.0;
    } else if (y < 3 && y > -11) {
      const double t = (3 - y) / 14.0;
      nose = 22.5 * std::pow(1 - t * t, 0.6);
      width = 11.0 - 2.0 * t;
    }
    dz += nose * gauss(ax, width);
    dz += 6.0 * gauss(std::hypot(ax - 11.5, (y + 5) * 1.1), 5.5);  // nostril wings
    dz += 3.2 * gauss(y - 46, 6.5) * smoothstep(62, 38, ax);       // brow ridge
    dz += 5.0 * gauss(std::hypot(ax - 40, (y + 2) * 0.8), 16);     // cheeks
    dz += 6.0 * gauss(std::hypot(ax * 0.8, y + 60), 12);           // chin
    // Lips: both bulge forward; a groove between the lower lip and the chin.
    const double lip_x = smoothstep(kOuterCornerX + 6, 8, ax);
    dz += 3.2 * lip_x * gauss(y - (kMouthY + 3.5), 4.5);
    dz += 3.6 * lip_x * gauss(y - (kMouthY - 4.5), 5.0);
    dz -= 1.8 * smoothstep(26, 6, ax) * gauss(y - (kMouthY - 15), 3.5);
    dz += 1.2 * smoothstep(4, 0, ax) * gauss(y - (kMouthY + 13), 4);  // philtrum
    return dz;
  }

  // The eyelid skin wraps the eyeball on a vertical cylinder just in front of it, so an
  // eyelid sliding down (a y translation) stays in front of the eye.
  double lid_wrap(double ax) const {
    const double rw = 1.25 * kEyeR, dx = std::min(std::abs(ax - kEyeX), rw);
    return eye_z + kEyeR + kLidGap - (rw - std::sqrt(rw * rw - dx * dx));
  }
  static double lid_blend(double ax, double y) {
    const double e = std::hypot((ax - kEyeX) / (kLidHW + 3.0), (y - kEyeY) / (kLidH + 6.0));
    return 1.0 - smoothstep(1.0, 1.9, e);
  }

  V3 surface(double y, double phi, double s, double shape_y) const {
    V3 p = base(y, phi, s, shape_y);
    const double front = smoothstep(0.15, 0.6, std::cos(phi));
    const double ax = std::abs(p.x());
    p.z() += front * relief(ax, y);
    const double w = lid_blend(ax, y) * front;
    if (w > 0)
      p.z() = (1 - w) * p.z() + w * std::max(lid_wrap(ax), std::min(p.z(), lid_wrap(ax) + 3));
    // The upper lid rides a little in front of the lower one, so that where a closing lid
    // passes the other (toward the corners) it covers it instead of cutting through it.
    if (w > 0 && y > kEyeY) p.z() += kUpperLidLead * w * smoothstep(0.0, 2.0, y - kEyeY);
    return p;
  }
};

constexpr float kUntextured = std::numeric_limits<float>::quiet_NaN();
// The skin's texture: u around the head from the back (phi = -pi), v up from the shoulders'
// foot to the crown, by the row a vertex was made on (a slit's two copies share theirs, so the
// lid and lip margins are lines in the texture). 2048 x 1440 texels: about 0.25 mm each.
constexpr int kTextureWidth = 2048, kTextureHeight = 1440;
Eigen::Vector2f skin_texcoord(double phi, double row_y) {
  return {static_cast<float>((phi + kPi) / (2 * kPi)),
          static_cast<float>((row_y - kFootY) / (kCrownY - kFootY))};
}
// The inverse: the angle (in -pi..pi) and row height a texture point lies at.
std::pair<double, double> skin_place(const Eigen::Vector2d& uv) {
  const double phi = (uv.x() - std::floor(uv.x())) * 2 * kPi - kPi;
  return {phi, kFootY + uv.y() * (kCrownY - kFootY)};
}

// Mesh under construction, with a tag per vertex saying which side of a slit it lies on.
struct Builder {
  FaceModel m;
  std::vector<Side> side;
  int add(const V3& p, const Eigen::Vector3f& colour, Side s = Side::None) {
    m.positions.push_back(p.cast<float>());
    m.colors.push_back(colour);
    m.texcoords.emplace_back(kUntextured, kUntextured);
    side.push_back(s);
    return static_cast<int>(m.positions.size()) - 1;
  }
  void tri(int a, int b, int c, int material) {
    m.triangles.emplace_back(a, b, c);
    m.triangle_materials.push_back(material);
  }
  void quad(int a, int b, int c, int d, int material) {  // a b c d counter-clockwise
    tri(a, b, c, material);
    tri(a, c, d, material);
  }
  V3 pos(int v) const { return m.positions[static_cast<std::size_t>(v)].cast<double>(); }
};

enum Material { kSkin, kEye, kTeeth, kTongue, kMouth };

const Eigen::Vector3f kSkinColour(0.86f, 0.66f, 0.54f);
const Eigen::Vector3f kLipColour(0.72f, 0.36f, 0.36f);
const Eigen::Vector3f kInnerLipColour(0.45f, 0.15f, 0.15f);
const Eigen::Vector3f kBrowColour(0.24f, 0.15f, 0.09f);
const Eigen::Vector3f kHairColour(0.20f, 0.13f, 0.08f);
const Eigen::Vector3f kLashColour(0.10f, 0.07f, 0.05f);
const Eigen::Vector3f kShirtColour(0.19f, 0.25f, 0.34f);

Eigen::Vector3f mix(const Eigen::Vector3f& a, const Eigen::Vector3f& b, double t) {
  return a + static_cast<float>(clamp01(t)) * (b - a);
}

// The hair's lower edge (y, mm) round the head from the front (phi, rad): the forehead, the
// temples' corners, a sideburn down in front of the ear to its middle (kEarY; the ear's front
// edge is at phi 1.52), round behind the ear and down to the nape. Without the sideburn the
// edge ran straight from the temple to behind the ear, a cap above bare sides of the head.
double hairline(double phi) {
  static const std::vector<std::pair<double, double>> k = {
      {0.0, 76},  {0.5, 72},  {0.95, 58}, {1.22, 50}, {1.42, 14},
      {1.55, 10}, {1.75, 12}, {2.05, 0},  {2.4, -30}, {3.15, -45}};
  return curve(k, std::abs(phi));
}

// Hair stands off the skull, along the way out from the head's axis (up in the cap): nothing at
// the hairline, rising behind it to kHairTop on the crown, kHairSide above the ears and kHairBack
// at the back of the head, thinning toward the nape's hairline, clear of the ears, and lying
// flat over the temples below the top of the brows (as short hair does there; standing out
// beside the eyes it moved dlib's landmarks enough to doubt the start of a turning take). Above
// the brow the first kHairFlat millimetres behind the hairline stay flat, where a capture
// headband presses the hair down (the synthetic layout's tags lie there). The skull's top under
// it is 11.4, the hair's 11.5: portraits are framed to the skull's, so hair does not shrink the
// face in the image.
constexpr double kHairTop = 10.0, kHairSide = 8.0, kHairBack = 14.0, kHairFlat = 22.0;
// The ears' centre, round the head from the front (rad), and the head's radius there (mm).
constexpr double kEarPhi = 1.72, kEarRadius = 76.0;
V3 hair_lift(const V3& p, double phi, double shape_y) {
  const double above = shape_y - hairline(phi);
  if (above <= 0) return V3::Zero();
  const V3 out =
      V3(p.x(), std::max(0.0, p.y() - 30.0), p.z() - curve(kCentreZ, std::min(shape_y, kCapY)))
          .normalized();
  const double facing = out.z() / std::max(1e-9, std::hypot(out.x(), out.z()));  // 1 front
  const double back = smoothstep(0.0, -0.8, facing);
  const double flat = kHairFlat * smoothstep(0.2, 0.8, facing) * (1 - out.y() * out.y());
  const double rise = smoothstep(flat, flat + 20 + 20 * back, above);
  const double ear = smoothstep(
      1.05, 1.35,
      std::hypot((p.y() - kEarY) / kEarUp, (std::abs(phi) - kEarPhi) * kEarRadius / kEarBack));
  const double around = kHairSide + (kHairBack - kHairSide) * back;
  const double temple = back + (1 - back) * smoothstep(40, 70, p.y());
  return rise * ear * temple * (around + (kHairTop - around) * out.y() * out.y()) * out;
}

// The eyebrow's upper edge at |x| = ax. MPEG-4's 4.1, 4.3 and 4.5 lie on it: the inner end, the
// uppermost point and the outer end of the brow, which hangs below it.
double brow_top_y(double ax) {
  return 44.0 +
         5.0 * std::pow(std::max(0.0, std::sin(kPi * std::clamp(ax - 13, 0.0, 38.0) / 38)), 0.8);
}

Eigen::Vector3f skin_colour(const V3& p, double phi, double shape_y) {
  const double ax = std::abs(p.x()), y = p.y();
  Eigen::Vector3f c = kSkinColour;
  c = mix(c, Eigen::Vector3f(0.88f, 0.58f, 0.50f), 0.35 * gauss(std::hypot(ax - 42, y + 6), 14));
  // Nostrils: dark openings with a soft shadow around them.
  const double nostril = std::hypot((ax - 6.8) / 3.4, (y + 8.8) / 2.0);
  c = mix(c, Eigen::Vector3f(0.45f, 0.25f, 0.2f), 0.7 * gauss(nostril, 1.3));
  c = mix(c, Eigen::Vector3f(0.25f, 0.12f, 0.1f), 0.9 * smoothstep(1.2, 0.5, nostril));
  // Eyebrows: a band hanging from the brow's upper edge between its inner and outer ends,
  // thick inside, thin outside, in fine strokes of hair slanting up and out.
  if (ax > kBrowInnerX - 2 && ax < kBrowOuterX + 2 && p.z() > 40) {
    const double thick =
        kBrowInner - (kBrowInner - kBrowOuter) * (ax - kBrowInnerX) / (kBrowOuterX - kBrowInnerX);
    const double d = std::abs(y - (brow_top_y(ax) - thick / 2)) / (thick / 2);
    const double hairs = 0.8 + 0.2 * std::sin(2 * kPi * (ax + 0.6 * y) / 0.9);
    c = mix(c, kBrowColour,
            hairs * (1 - smoothstep(0.6, 1.05, d)) *
                smoothstep(kBrowInnerX - 1.5, kBrowInnerX + 0.5, ax) *
                smoothstep(kBrowOuterX + 1.5, kBrowOuterX - 0.5, ax));
  }
  // Lips, from the outer contour to the mouth line.
  if (ax < kOuterCornerX + 1 && p.z() > 60) {
    double inside = 0;
    if (y >= kMouthY)
      inside = smoothstep(0.6, -0.6, y - kMouthY - upper_lip_height(ax));
    else
      inside = smoothstep(0.6, -0.6, kMouthY - y - lower_lip_height(ax));
    c = mix(c, kLipColour, inside * smoothstep(kOuterCornerX + 1, kOuterCornerX - 2, ax));
  }
  // Hair over the skull, in strands combed back from the hairline: a fine ripple across them.
  const double strands = 0.85 + 0.15 * std::sin(2 * kPi * phi * 70.0 + 0.08 * shape_y) *
                                    std::sin(2 * kPi * phi * 23.0);
  c = mix(c, kHairColour * static_cast<float>(strands),
          smoothstep(-1.5, 1.5, shape_y - hairline(phi)));
  // A crew-neck shirt over the shoulders: its collar a ribbed band, lower at the front.
  const double neckline = -176.0 - 8.0 * std::cos(phi);
  if (shape_y < neckline + 2) {
    const double collar = smoothstep(neckline - 6.5, neckline - 5.5, shape_y);
    const double rib = 0.93 + 0.07 * std::sin(2 * kPi * phi * 90.0);
    const Eigen::Vector3f shirt = mix(kShirtColour, kShirtColour * static_cast<float>(rib), collar);
    c = mix(c, shirt, smoothstep(neckline + 0.5, neckline - 0.5, shape_y));
  }
  return c;
}

// A latitude-longitude surface around `axis` (rings at the given polar angles, poles
// included), outward (or inward) facing; returns [first, end) vertex range.
struct LatLong {
  std::vector<int> vertices;
  int front_pole = -1, back_pole = -1;
};
LatLong lat_long(Builder& b, const std::vector<double>& angles, int segments,
                 const std::function<V3(double, double)>& point,
                 const std::function<Eigen::Vector3f(std::size_t ring)>& colour, int material,
                 const V3& centre, bool inward, double min_angle = 0.0) {
  LatLong out;
  std::vector<std::vector<int>> rings;
  const std::size_t first_tri = b.m.triangles.size();
  const bool open = min_angle > 0;
  if (!open) out.front_pole = b.add(point(0.0, 0.0), colour(0), Side::None);
  for (std::size_t r = 0; r < angles.size(); ++r) {
    if (angles[r] < min_angle) continue;
    std::vector<int> ring;
    for (int s = 0; s < segments; ++s)
      ring.push_back(b.add(point(angles[r], 2 * kPi * s / segments), colour(r + 1), Side::None));
    rings.push_back(ring);
  }
  out.back_pole = b.add(point(kPi, 0.0), colour(angles.size() + 1), Side::None);
  auto seg = [&](int s) { return (s + segments) % segments; };
  if (!open)
    for (int s = 0; s < segments; ++s)
      b.tri(out.front_pole, rings[0][static_cast<std::size_t>(s)],
            rings[0][static_cast<std::size_t>(seg(s + 1))], material);
  for (std::size_t r = 0; r + 1 < rings.size(); ++r)
    for (int s = 0; s < segments; ++s) {
      const auto s0 = static_cast<std::size_t>(s), s1 = static_cast<std::size_t>(seg(s + 1));
      // Rings that share an angle (colour seams) are not joined.
      b.quad(rings[r][s0], rings[r + 1][s0], rings[r + 1][s1], rings[r][s1], material);
    }
  for (int s = 0; s < segments; ++s)
    b.tri(out.back_pole, rings.back()[static_cast<std::size_t>(seg(s + 1))],
          rings.back()[static_cast<std::size_t>(s)], material);
  // Convex parts: orient every triangle by the side of the centre it faces.
  for (std::size_t t = first_tri; t < b.m.triangles.size(); ++t) {
    Eigen::Vector3i& tr = b.m.triangles[t];
    const V3 a = b.pos(tr[0]), p1 = b.pos(tr[1]), p2 = b.pos(tr[2]);
    const V3 n = (p1 - a).cross(p2 - a);
    const bool outward = n.dot((a + p1 + p2) / 3 - centre) > 0;
    if (outward == inward) std::swap(tr[1], tr[2]);
  }
  for (const auto& ring : rings) out.vertices.insert(out.vertices.end(), ring.begin(), ring.end());
  if (out.front_pole >= 0) out.vertices.push_back(out.front_pole);
  out.vertices.push_back(out.back_pole);
  return out;
}

// `count` row heights from below `top` down to `bottom` (the last), at equal steps of a measure
// summed over `samples` slices of the height: slice i (1-based) adds `increment(i, slice)`.
std::vector<double> rows_at_equal_steps(double top, double bottom, int count, int samples,
                                        const std::function<double(int, double)>& increment) {
  std::vector<double> cdf(static_cast<std::size_t>(samples) + 1, 0.0);
  const double step = (top - bottom) / samples;
  for (int i = 1; i <= samples; ++i)
    cdf[static_cast<std::size_t>(i)] = cdf[static_cast<std::size_t>(i - 1)] + increment(i, step);
  std::vector<double> ys;
  for (int r = 1; r <= count; ++r) {
    const double target = cdf.back() * r / count;
    const auto it = std::lower_bound(cdf.begin(), cdf.end(), target);
    const auto i = static_cast<double>(it - cdf.begin());
    ys.push_back(top - i * step);
  }
  return ys;
}

// Row heights of the skin below the skull cap: denser around the eyes and the mouth.
std::vector<double> body_rows(int count) {
  auto density = [](double y) {
    return 1.0 + 2.0 * gauss(y - kEyeY, 9) + 2.0 * gauss(y - kMouthY, 9) + 0.6 * gauss(y, 14) +
           (y > -85 && y < 58 ? 0.8 : 0.0);
  };
  std::vector<double> ys = rows_at_equal_steps(kCapY, kNeckY, count, 4000, [&](int i, double step) {
    return density(kCapY - (i - 0.5) * step) * step;
  });
  // Snap the nearest rows onto the eye and mouth lines (the slits lie on rows).
  for (double line : {kEyeY, kMouthY}) {
    auto best = std::min_element(ys.begin(), ys.end(), [&](double a, double c) {
      return std::abs(a - line) < std::abs(c - line);
    });
    *best = line;
  }
  return ys;
}

struct Skin {
  int rows = 0, cols = 0;
  std::vector<std::vector<int>> grid;        // [row][col] (upper copy on slit rows)
  std::map<std::pair<int, int>, int> lower;  // slit duplicates below the line
  int eye_row = -1, mouth_row = -1;
  std::vector<int> upper_flange, lower_flange;  // inner lip strips
  std::vector<int> vertices;                    // all skin vertices
};

// The eye's outline painted on the skin around it, at a point of the skin's texture: the lash
// lines along the lid margins (darkest and widest toward the outer corner of the upper lid,
// reaching 2 mm past the corners). An eye is read by its dark outline
// (dlib's landmarks put the corners of an eye without it on the iris), and a closed eye shows
// its lashes' line. `row_y` is the texture's height (the margins lie at kEyeY).
Eigen::Vector3f eye_outline(const SkinShape& shape, double phi, double row_y,
                            const Eigen::Vector3f& c) {
  if (std::cos(phi) < 0.3) return c;
  const double signed_d = std::abs(shape.base(kEyeY, phi, 1.0, kEyeY).x()) - kEyeX;  // + outward
  const double d = std::abs(signed_d);
  if (d > kLidHW + 3.0) return c;
  const double opening = kLidH * eye_aperture(d);
  // Rows near the eye line were moved apart by the opening: a row's height above the margin,
  // in mm of skin, is its height in the texture less that share.
  const double dist = std::abs(row_y - kEyeY) * (1.0 - opening / 13.0);
  const bool upper = row_y >= kEyeY;
  const double outward = smoothstep(-kLidHW, kLidHW, signed_d);
  const double width = upper ? kLashWidth * (0.7 + 0.6 * outward) : 0.6;
  const double strength = upper ? 0.9 : 0.4;
  const double along = smoothstep(kLidHW + 2.0, kLidHW, d);
  return mix(c, kLashColour, strength * along * smoothstep(width, 0.6 * width, dist));
}

// Bakes the skin's colours (skin_colour and the lash lines) into the model's texture, and gives
// each textured vertex the texture's colour at its coordinates.
void paint_skin(FaceModel& m, const SkinShape& shape) {
  std::vector<int> skin_triangles;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (m.triangle_materials[t] != kSkin) continue;
    const Eigen::Vector3i& tr = m.triangles[t];
    if (m.texcoords[static_cast<std::size_t>(tr[0])].allFinite() &&
        m.texcoords[static_cast<std::size_t>(tr[1])].allFinite() &&
        m.texcoords[static_cast<std::size_t>(tr[2])].allFinite())
      skin_triangles.push_back(static_cast<int>(t));
  }
  m.texture =
      bake_texture(m, skin_triangles, kTextureWidth, kTextureHeight, [&](const TexelPoint& t) {
        const auto [phi, row_y] = skin_place(t.uv);
        return eye_outline(shape, phi, row_y, skin_colour(t.position, phi, t.position.y()));
      });
  for (std::size_t v = 0; v < m.positions.size(); ++v)
    if (m.texcoords[v].allFinite()) m.colors[v] = sample_texture(m.texture, m.texcoords[v]);
}

}  // namespace

FaceModel generate_head(const HeadOptions& options) {
  if (options.vertices < kMinHeadVertices)
    throw InputError("head: --vertices must be at least 1500 (got " +
                     std::to_string(options.vertices) + ")");
  const double n = options.vertices;
  const int segs = 2 * std::clamp(static_cast<int>(std::lround(std::sqrt(n) / 6)), 8, 60);
  const int teeth_cols = std::clamp(static_cast<int>(std::lround(std::sqrt(n) / 4)), 12, 160) | 1;
  const double parts = 2.0 * segs * (segs / 3 + 9) + 2.0 * teeth_cols * 4 + segs * (segs / 2) * 2.0;
  const double skin_target = std::max(800.0, n - parts);
  const int cols = 2 * static_cast<int>(std::lround(std::sqrt(skin_target * 1.15) / 2));
  const int rows = std::max(20, static_cast<int>(std::lround(skin_target / cols)));
  const int cap_rows = std::max(4, rows / 6);

  Builder b;
  b.m.name = "rostro default head";
  b.m.materials = {"skin", "eye", "teeth", "tongue", "mouth"};
  SkinShape shape;
  {
    // Eyeball depth: its front 2.5 mm behind the face surface at the pupil.
    double lo = 0, hi = kPi / 2;
    for (int i = 0; i < 60; ++i) {
      const double mid = (lo + hi) / 2;
      (shape.base(kEyeY, mid, 1.0, kEyeY).x() < kEyeX ? lo : hi) = mid;
    }
    const V3 p = shape.base(kEyeY, lo, 1.0, kEyeY);
    shape.eye_z = p.z() + SkinShape::relief(kEyeX, kEyeY) - 2.5 - kEyeR;
  }

  // Skin rows: the cap (y from the crown down to kCapY), then the body rows.
  struct Row {
    double y, s;
  };
  std::vector<Row> row_list;
  for (int r = 1; r <= cap_rows; ++r) {
    const double a = (kPi / 2) * r / (cap_rows + 1);
    row_list.push_back({kCapY + (kCrownY - kCapY) * std::cos(a), std::sin(a)});
  }
  for (double y : body_rows(rows - cap_rows)) row_list.push_back({y, 1.0});
  Skin skin;
  skin.rows = static_cast<int>(row_list.size());
  skin.cols = cols;
  for (int r = 0; r < skin.rows; ++r) {
    if (row_list[static_cast<std::size_t>(r)].y == kEyeY) skin.eye_row = r;
    if (row_list[static_cast<std::size_t>(r)].y == kMouthY) skin.mouth_row = r;
  }
  auto phi_of = [&](int c) {
    // Columns are symmetric (k and -k mirror each other) and denser at the front.
    const double u = 2.0 * (c - cols / 2) / cols;
    const double au = std::abs(u);
    const double phi = kPi * (0.35 * au + 0.65 * au * au * au);
    return u < 0 ? -phi : phi;
  };

  // A skin vertex: row, column, and which side of a slit it belongs to.
  auto skin_vertex = [&](int r, int c, Side side) {
    const Row& row = row_list[static_cast<std::size_t>(r)];
    const double phi = phi_of(c);
    const bool cap = row.s < 1.0;
    double y = row.y;
    if (!cap) {
      const double ax0 = std::abs(shape.base(row.y, phi, 1.0, row.y).x());
      const bool front = std::cos(phi) > 0.3;
      // Open the eyes: rows near the eye line move away from it, the slit copies most.
      const double de = y - kEyeY;
      const double h_eye = front ? kLidH * eye_aperture(std::abs(ax0 - kEyeX)) : 0.0;
      if (h_eye > 0 && std::abs(de) < 13.0) {
        const double g = 1 - std::abs(de) / 13.0;
        const bool up = side == Side::Upper || (side == Side::None && de > 0);
        const bool down = side == Side::Lower || (side == Side::None && de < 0);
        y += up ? h_eye * g : down ? -h_eye * g : 0.0;
      }
      // The lips are not parted: MPEG-4's neutral face has the mouth closed, lips in contact
      // (a gap of a fraction of a millimetre showed the teeth as a white line between them).
    }
    V3 p = cap ? shape.base(y, phi, row.s, kCapY) : shape.surface(y, phi, 1.0, y);
    p += hair_lift(p, phi, cap ? row.y : y);
    const int v = b.add(p, skin_colour(p, phi, cap ? row.y : y), side);
    b.m.texcoords[static_cast<std::size_t>(v)] = skin_texcoord(phi, row.y);
    return v;
  };

  const V3 crown(0, kCrownY, curve(kCentreZ, kCapY));
  const int pole = b.add(crown + hair_lift(crown, 0, kCrownY), kHairColour);
  skin.vertices.push_back(pole);
  skin.grid.assign(static_cast<std::size_t>(skin.rows),
                   std::vector<int>(static_cast<std::size_t>(cols), -1));
  auto in_eye_slit = [&](int c) {
    const double x = shape.base(kEyeY, phi_of(c), 1.0, kEyeY).x();
    return std::cos(phi_of(c)) > 0.3 && std::abs(std::abs(x) - kEyeX) < kLidHW;
  };
  auto in_mouth_slit = [&](int c) {
    const double x = shape.base(kMouthY, phi_of(c), 1.0, kMouthY).x();
    return std::cos(phi_of(c)) > 0.3 && std::abs(x) < kMouthHW;
  };
  for (int r = 0; r < skin.rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const bool slit =
          (r == skin.eye_row && in_eye_slit(c)) || (r == skin.mouth_row && in_mouth_slit(c));
      const int v = skin_vertex(r, c, slit ? Side::Upper : Side::None);
      skin.grid[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = v;
      skin.vertices.push_back(v);
      if (slit) {
        const int lower = skin_vertex(r, c, Side::Lower);
        skin.lower[{r, c}] = lower;
        skin.vertices.push_back(lower);
      }
    }
  auto at = [&](int r, int c, bool below) {
    c = (c % cols + cols) % cols;
    if (below) {
      auto it = skin.lower.find({r, c});
      if (it != skin.lower.end()) return it->second;
    }
    return skin.grid[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
  };
  // Column c+1 lies toward +x at the front, rows go down: a(r,c) d(r+1,c) c(r+1,c+1) b(r,c+1)
  // is counter-clockwise seen from outside.
  for (int c = 0; c < cols; ++c) b.tri(pole, at(0, c, false), at(0, c + 1, false), kSkin);
  for (int r = 0; r + 1 < skin.rows; ++r)
    for (int c = 0; c < cols; ++c)
      b.quad(at(r, c, true), at(r + 1, c, false), at(r + 1, c + 1, false), at(r, c + 1, true),
             kSkin);

  // Inner lip strips: from each lip edge back into the mouth, so an open mouth shows lips
  // with thickness rather than a paper edge.
  {
    std::vector<int> cols_in;
    for (int c = 0; c < cols; ++c)
      if (skin.lower.count({skin.mouth_row, c})) cols_in.push_back(c);
    std::sort(cols_in.begin(), cols_in.end(), [&](int a, int c) { return phi_of(a) < phi_of(c); });
    const int left_corner = at(skin.mouth_row, cols_in.back() + 1, false);
    const int right_corner = at(skin.mouth_row, cols_in.front() - 1, false);
    for (int sign : {+1, -1}) {
      std::vector<int> edge, f1, f2;
      for (int c : cols_in) {
        const int e = sign > 0 ? at(skin.mouth_row, c, false) : at(skin.mouth_row, c, true);
        const V3 p = b.pos(e);
        const double t = mouth_aperture(std::abs(p.x()));
        const Side side = sign > 0 ? Side::Upper : Side::Lower;
        edge.push_back(e);
        f1.push_back(b.add(p + V3(0, sign * 1.0 * t, -3.0 * t), kInnerLipColour, side));
        f2.push_back(b.add(p + V3(0, sign * 2.0 * t, -6.0 * t), kInnerLipColour * 0.7f, side));
      }
      auto& flange = sign > 0 ? skin.upper_flange : skin.lower_flange;
      flange.insert(flange.end(), f1.begin(), f1.end());
      flange.insert(flange.end(), f2.begin(), f2.end());
      const std::size_t k = edge.size();
      // Strip along the lip: edge -> f1 -> f2; upper faces down, lower faces up.
      for (std::size_t i = 0; i + 1 < k; ++i) {
        if (sign > 0) {
          b.quad(edge[i], edge[i + 1], f1[i + 1], f1[i], kMouth);
          b.quad(f1[i], f1[i + 1], f2[i + 1], f2[i], kMouth);
        } else {
          b.quad(edge[i], f1[i], f1[i + 1], edge[i + 1], kMouth);
          b.quad(f1[i], f2[i], f2[i + 1], f1[i + 1], kMouth);
        }
      }
      if (sign > 0) {
        b.tri(right_corner, edge[0], f1[0], kMouth);
        b.tri(right_corner, f1[0], f2[0], kMouth);
        b.tri(left_corner, f1[k - 1], edge[k - 1], kMouth);
        b.tri(left_corner, f2[k - 1], f1[k - 1], kMouth);
      } else {
        b.tri(right_corner, f1[0], edge[0], kMouth);
        b.tri(right_corner, f2[0], f1[0], kMouth);
        b.tri(left_corner, edge[k - 1], f1[k - 1], kMouth);
        b.tri(left_corner, f1[k - 1], f2[k - 1], kMouth);
      }
    }
  }

  // Inner lip strips face into the mouth opening: the upper one down, the lower one up.
  for (std::size_t t = 0; t < b.m.triangles.size(); ++t) {
    if (b.m.triangle_materials[t] != kMouth) continue;
    Eigen::Vector3i& tr = b.m.triangles[t];
    const V3 a = b.pos(tr[0]), p1 = b.pos(tr[1]), p2 = b.pos(tr[2]);
    const bool upper = (a + p1 + p2).y() / 3 > kMouthY;
    if (((p1 - a).cross(p2 - a).y() > 0) == upper) std::swap(tr[1], tr[2]);
  }
  FaceModel& m = b.m;
  // IRISD0 as the FAPU will measure it: the opening at the lid column nearest the pupil.
  double irisd0 = 0, lid_dx = 1e9;
  for (const auto& [rc_key, lower] : skin.lower) {
    if (rc_key.first != skin.eye_row) continue;
    const V3 up = b.pos(at(rc_key.first, rc_key.second, false)), low = b.pos(lower);
    if (up.x() > 0 && std::abs(up.x() - kEyeX) < lid_dx)
      lid_dx = std::abs(up.x() - kEyeX), irisd0 = up.y() - low.y();
  }

  // --- Eyeballs: rings around the gaze axis, sharp pupil and iris edges (duplicated rings).
  auto eyeball = [&](double sign) {
    const V3 c(sign * kEyeX, kEyeY, shape.eye_z);
    const double iris_r = irisd0 / 2, pupil_r = iris_r / 3;
    const double ap = std::asin(pupil_r / kEyeR), ai = std::asin(iris_r / kEyeR);
    std::vector<double> angles = {ap * 0.5,  ap, ap,       ap + (ai - ap) * 0.45,
                                  ai * 0.97, ai, ai * 1.08};
    const int sclera = std::max(5, segs / 3);
    for (int i = 1; i <= sclera; ++i)
      angles.push_back(ai * 1.08 + (kPi - 0.15 - ai * 1.08) * i / sclera);
    const Eigen::Vector3f pupil(0.02f, 0.02f, 0.02f), iris_in(0.42f, 0.28f, 0.16f),
        iris_out(0.25f, 0.15f, 0.08f), limbus(0.12f, 0.08f, 0.05f), white(0.93f, 0.91f, 0.88f);
    auto colour = [&](std::size_t ring) -> Eigen::Vector3f {
      if (ring <= 2) return pupil;
      if (ring == 3) return iris_in;
      if (ring == 4) return mix(iris_in, iris_out, 0.5);
      if (ring <= 6) return ring == 6 ? limbus : iris_out;
      if (ring == 7) return mix(white, Eigen::Vector3f(0.8f, 0.78f, 0.75f), 0.5);
      // The white darkens away from the iris, shaded by the lids toward the corners.
      const double toward_lids = std::min(1.0, (static_cast<double>(ring) - 7.0) / 3.0);
      return mix(white, Eigen::Vector3f(0.62f, 0.52f, 0.50f), toward_lids);
    };
    auto point = [&](double a, double t) {
      return V3(c.x() + kEyeR * std::sin(a) * std::cos(t),
                c.y() + kEyeR * std::sin(a) * std::sin(t), c.z() + kEyeR * std::cos(a));
    };
    LatLong ll = lat_long(b, angles, segs, point, colour, kEye, c, false);
    RigidPart part;
    part.vertices = ll.vertices;
    part.pivot = c;
    return std::make_pair(part, ll.front_pole);
  };
  auto [left_eye, left_pupil] = eyeball(+1);
  auto [right_eye, right_pupil] = eyeball(-1);
  m.parts.left_eyeball = left_eye;
  m.parts.right_eyeball = right_eye;

  // --- Eye sockets: an inward-facing bowl behind each eyeball, open toward the face. The lids'
  // slit reaches past the eyeball's edge at the corners, where it would show the head's inside
  // as a dark wedge; the bowl shows the white in the lids' shade there instead, and the pink of
  // the caruncle toward the nose.
  const Eigen::Vector3f shaded_white(0.55f, 0.46f, 0.44f), caruncle(0.78f, 0.50f, 0.48f);
  for (double sign : {+1.0, -1.0}) {
    const V3 c(sign * kEyeX, kEyeY, shape.eye_z);
    const V3 r(kEyeR + 4.0, kEyeR + 1.0, kEyeR + 1.0);
    std::vector<double> angles;
    for (int i = 0; i < 5; ++i) angles.push_back(kPi / 3 + (2 * kPi / 3 - 0.2) * i / 5);
    const LatLong bowl = lat_long(
        b, angles, segs / 2,
        [&](double a, double t) {
          // The rim comes forward toward the nose, where a turned head looks in past the
          // eyeball; on the outer side it stays behind the skin.
          const double rim = kPi / 2 - kPi / 6 * smoothstep(0.0, -0.7, sign * std::cos(t));
          a = rim + (a - kPi / 3) * (kPi - rim) / (2 * kPi / 3);
          return V3(c.x() + r.x() * std::sin(a) * std::cos(t),
                    c.y() + r.y() * std::sin(a) * std::sin(t), c.z() + r.z() * std::cos(a));
        },
        [&](std::size_t) { return shaded_white; }, kEye, c, true, kPi / 3);
    for (int v : bowl.vertices) {
      const double toward_nose = (kEyeX - std::abs(b.pos(v).x())) / kEyeR;
      b.m.colors[static_cast<std::size_t>(v)] =
          mix(shaded_white, caruncle, smoothstep(0.3, 0.9, toward_nose));
    }
  }

  // --- Ears: a shell on each side of the head, its outer face dished into a bowl (the concha)
  // inside a rim (the helix), tilted back, flaring out toward the back; the inner face lies in
  // the head. The top of the left ear is 10.1, its back 10.3, its lobe 10.5.
  const V3 ear_r(kEarOut, kEarUp, kEarBack);
  auto ear = [&](double side) {
    const V3 c(side * (curve(kHalfWidth, kEarY) + 3.0), kEarY, curve(kCentreZ, kEarY) - 12.0);
    const double tilt = 12.0 * kPi / 180;  // the top leans back
    std::vector<double> angles;
    // Coarser than the eyeballs: the ears are seen small and from the side.
    const int rings = std::max(6, segs / 3), segments = std::max(12, 2 * segs / 3);
    for (int i = 1; i <= rings; ++i) angles.push_back(kPi * i / (rings + 1));
    auto point = [&, c, side](double a, double t) {
      const double uy = std::sin(a) * std::sin(t), uz = std::sin(a) * std::cos(t);
      double out = ear_r.x() * std::cos(a);
      if (a < kPi / 2) out -= 0.75 * ear_r.x() * std::exp(-(a / 0.8) * (a / 0.8));  // the bowl
      const double y = ear_r.y() * uy, z = ear_r.z() * uz;
      out += 0.25 * std::max(0.0, -z);  // flares out toward the back
      return V3(c.x() + side * out, c.y() + y * std::cos(tilt) + z * std::sin(tilt),
                c.z() + z * std::cos(tilt) - y * std::sin(tilt));
    };
    const Eigen::Vector3f ear_colour = mix(kSkinColour, Eigen::Vector3f(0.88f, 0.56f, 0.48f), 0.35);
    LatLong ll = lat_long(
        b, angles, segments, point, [&](std::size_t) { return ear_colour; }, kSkin, c, false);
    return std::make_pair(ll.vertices, c);
  };
  const auto [left_ear, left_ear_c] = ear(+1);
  ear(-1);

  // --- Mouth interior: an inward-facing bag behind the lips, open toward them.
  const V3 cavity_c(0, kMouthY, shape.eye_z - 10);
  const V3 cavity_r(32, 22, 28);
  std::vector<double> cav_angles;
  const int cav_rings = std::max(6, segs / 2);
  for (int i = 1; i <= cav_rings; ++i) cav_angles.push_back(kPi * i / (cav_rings + 1));
  LatLong cavity = lat_long(
      b, cav_angles, segs,
      [&](double a, double t) {
        return V3(cavity_c.x() + cavity_r.x() * std::sin(a) * std::cos(t),
                  cavity_c.y() + cavity_r.y() * std::sin(a) * std::sin(t),
                  cavity_c.z() + cavity_r.z() * std::cos(a));
      },
      [](std::size_t) { return Eigen::Vector3f(0.20f, 0.06f, 0.07f); }, kMouth, cavity_c, true,
      0.95);

  // --- Teeth: two arched bands meeting at the mouth line (teeth touch at rest).
  const double teeth_front = shape.eye_z + 17.0, arch_w = 22.0;
  auto teeth = [&](double top, double bottom) {
    std::vector<std::array<int, 4>> cols_v;
    RigidPart part;
    for (int k = 0; k < teeth_cols; ++k) {
      const double x = -arch_w + 2 * arch_w * k / (teeth_cols - 1);
      const double z = teeth_front - x * x / 40.0;
      // Inward normal of the arch, for the back face 2.5 mm behind.
      const V3 in = V3(x / 20.0, 0, 1).normalized() * -2.5;
      const bool gap = k % 3 == 0 && k != 0 && k != teeth_cols - 1;
      const Eigen::Vector3f col =
          gap ? Eigen::Vector3f(0.70f, 0.67f, 0.58f) : Eigen::Vector3f(0.93f, 0.91f, 0.84f);
      std::array<int, 4> v = {b.add(V3(x, top, z), col), b.add(V3(x, bottom, z), col),
                              b.add(V3(x, bottom, z) + in, col), b.add(V3(x, top, z) + in, col)};
      for (int i : v) part.vertices.push_back(i);
      cols_v.push_back(v);
    }
    const std::size_t first = m.triangles.size();
    for (std::size_t k = 0; k + 1 < cols_v.size(); ++k)
      for (int f = 0; f < 4; ++f)
        b.quad(cols_v[k][static_cast<std::size_t>(f)],
               cols_v[k][static_cast<std::size_t>((f + 1) % 4)],
               cols_v[k + 1][static_cast<std::size_t>((f + 1) % 4)],
               cols_v[k + 1][static_cast<std::size_t>(f)], kTeeth);
    b.quad(cols_v.front()[0], cols_v.front()[3], cols_v.front()[2], cols_v.front()[1], kTeeth);
    b.quad(cols_v.back()[0], cols_v.back()[1], cols_v.back()[2], cols_v.back()[3], kTeeth);
    // Orient outward from the band's own centre line.
    for (std::size_t t = first; t < m.triangles.size(); ++t) {
      Eigen::Vector3i& tr = m.triangles[t];
      const V3 a = b.pos(tr[0]), p1 = b.pos(tr[1]), p2 = b.pos(tr[2]);
      const V3 cen = (a + p1 + p2) / 3;
      const double x = std::clamp(cen.x(), -arch_w, arch_w);
      const V3 mid(x, (top + bottom) / 2, teeth_front - x * x / 40.0 - 1.25);
      if ((p1 - a).cross(p2 - a).dot(cen - mid) < 0) std::swap(tr[1], tr[2]);
    }
    return part;
  };
  m.parts.upper_teeth = teeth(kMouthY + 9.0, kMouthY);
  m.parts.lower_teeth = teeth(kMouthY, kMouthY - 9.0);
  m.parts.lower_teeth.jaw_gain = 1.0;

  // --- Tongue: a flattened ellipsoid on the mouth floor, tip behind the teeth.
  const V3 tongue_c(0, kMouthY - 5.5, teeth_front - 21.0);
  const V3 tongue_r(17, 4.5, 18.5);
  std::vector<double> tongue_angles;
  for (int i = 1; i <= cav_rings; ++i) tongue_angles.push_back(kPi * i / (cav_rings + 1));
  LatLong tongue = lat_long(
      b, tongue_angles, segs,
      [&](double a, double t) {
        return V3(tongue_c.x() + tongue_r.x() * std::sin(a) * std::cos(t),
                  tongue_c.y() + tongue_r.y() * std::sin(a) * std::sin(t),
                  tongue_c.z() + tongue_r.z() * std::cos(a));
      },
      [](std::size_t) { return Eigen::Vector3f(0.78f, 0.38f, 0.38f); }, kTongue, tongue_c, false);
  m.parts.tongue.vertices = tongue.vertices;
  m.parts.tongue.pivot = tongue_c;
  m.parts.tongue.jaw_gain = 0.8;

  // --- Shoulders: below the neck's foot (the skin grid's last row) the skin goes on into the
  // shoulders and the top of the chest, on every other column (they are seen from afar), its
  // rows at equal steps along the shoulder's slope. No region moves them.
  std::vector<int> shoulders;
  {
    // Equal steps along the side's outline (half width against height).
    const std::vector<double> heights = rows_at_equal_steps(
        kNeckY, kFootY, std::clamp(skin.rows / 6, 8, 40), 2000, [](int i, double step) {
          const double y = kNeckY - static_cast<double>(i) * step;
          return std::hypot(step, curve(kHalfWidth, y) - curve(kHalfWidth, y + step));
        });
    std::vector<int> above;  // the row above, column by column
    for (int c = 0; c < cols; ++c) above.push_back(at(skin.rows - 1, c, false));
    for (const double y : heights) {
      std::vector<int> row;
      for (int c = 0; c < cols; c += 2) {
        const double phi = phi_of(c);
        const V3 p = shape.surface(y, phi, 1.0, y);
        const int v = b.add(p, skin_colour(p, phi, y));
        b.m.texcoords[static_cast<std::size_t>(v)] = skin_texcoord(phi, y);
        row.push_back(v);
        shoulders.push_back(v);
      }
      const auto width = static_cast<int>(row.size());
      auto low = [&](int k) { return row[static_cast<std::size_t>((k + width) % width)]; };
      if (above.size() == row.size()) {
        for (int k = 0; k < width; ++k)
          b.quad(above[static_cast<std::size_t>(k)], low(k), low(k + 1),
                 above[static_cast<std::size_t>((k + 1) % width)], kSkin);
      } else {  // the neck's foot: two columns above each one below
        auto high = [&](int c) { return above[static_cast<std::size_t>((c + cols) % cols)]; };
        for (int k = 0; k < width; ++k) {
          b.tri(high(2 * k), low(k), high(2 * k + 1), kSkin);
          b.tri(high(2 * k + 1), low(k), low(k + 1), kSkin);
          b.tri(high(2 * k + 1), low(k + 1), high(2 * k + 2), kSkin);
        }
      }
      above = row;
    }
  }

  // --- The top of the skull (11.4), under the hair, an isolated vertex; the pole above it, the
  // hair's top, is 11.5 (MPEG-4's "hair thickness over 11.4").
  const int skull_top = b.add(crown, kHairColour);

  // --- Head rotation centre (7.1): top of the spine, an isolated vertex.
  const int spine = b.add(V3(0, -35, -25), kSkinColour);
  m.head_pivot = V3(0, -35, -25);

  // --- Feature points.
  auto nearest = [&](const std::vector<int>& set, const V3& target, const V3& metric,
                     const std::function<bool(int)>& ok = nullptr) {
    int best = -1;
    double best_d = 1e30;
    for (int v : set) {
      if (ok && !ok(v)) continue;
      const double d = (b.pos(v) - target).cwiseProduct(metric).squaredNorm();
      if (d < best_d) best_d = d, best = v;
    }
    if (best < 0) throw std::logic_error("head generator: no vertex for a feature point");
    return best;
  };
  const V3 xy(1, 1, 0);
  std::vector<int> front_skin;
  for (int v : skin.vertices)
    if (b.pos(v).z() > 20) front_skin.push_back(v);
  auto is_upper = [&](int v) { return b.side[static_cast<std::size_t>(v)] == Side::Upper; };
  auto is_lower = [&](int v) { return b.side[static_cast<std::size_t>(v)] == Side::Lower; };
  auto on_row = [&](int row) {
    std::vector<int> out;
    for (int c = 0; c < cols; ++c) {
      out.push_back(at(row, c, false));
      if (skin.lower.count({row, c})) out.push_back(at(row, c, true));
    }
    return out;
  };
  const std::vector<int> mouth_row = on_row(skin.mouth_row), eye_row = on_row(skin.eye_row);
  auto slit_end = [&](const std::vector<int>& row_vertices, bool max_x, double lo, double hi) {
    // The last shared vertex beyond the duplicated run: the slit's corner.
    int best = -1;
    for (int v : row_vertices) {
      const double x = b.pos(v).x();
      if (b.side[static_cast<std::size_t>(v)] != Side::None || x < lo || x > hi ||
          b.pos(v).z() < 20)
        continue;
      if (best < 0 || (max_x ? x < b.pos(best).x() : x > b.pos(best).x())) best = v;
    }
    return best;
  };
  std::map<FeaturePointId, int>& fp = m.feature_points;
  const double my = kMouthY;
  fp[{2, 2}] = nearest(mouth_row, V3(0, my, 0), xy, is_upper);
  fp[{2, 3}] = nearest(mouth_row, V3(0, my, 0), xy, is_lower);
  fp[{2, 4}] = slit_end(mouth_row, true, kMouthHW - 0.01, 60);
  fp[{2, 6}] = nearest(mouth_row, V3(kMouthHW / 2, my, 0), xy, is_upper);
  fp[{2, 8}] = nearest(mouth_row, V3(kMouthHW / 2, my, 0), xy, is_lower);
  fp[{8, 1}] = nearest(front_skin, V3(0, my + upper_lip_height(0), 0), xy,
                       [&](int v) { return b.pos(v).x() == 0 && !is_lower(v); });
  fp[{8, 2}] = nearest(front_skin, V3(0, my - lower_lip_height(0), 0), xy,
                       [&](int v) { return b.pos(v).x() == 0 && !is_upper(v); });
  // (The mouth's row runs round the head: a vertex of the nape can lie as near in x and y.)
  fp[{8, 3}] = nearest(mouth_row, V3(kOuterCornerX + 0.8, my, 0), xy, [&](int v) {
    return b.side[static_cast<std::size_t>(v)] == Side::None && b.pos(v).z() > 20 &&
           b.pos(v).x() > b.pos(fp[{2, 4}]).x() + 0.5;
  });
  fp[{8, 5}] = nearest(front_skin, V3(12, my + upper_lip_height(12), 0), xy,
                       [&](int v) { return b.pos(v).y() > my + 1; });
  fp[{8, 7}] = nearest(front_skin, V3(12, my - lower_lip_height(12), 0), xy,
                       [&](int v) { return b.pos(v).y() < my - 1; });
  fp[{8, 10}] = nearest(front_skin, V3(5, my + upper_lip_height(5), 0), xy,
                        [&](int v) { return b.pos(v).y() > my + 1; });
  fp[{2, 1}] = nearest(front_skin, V3(0, -75, 0), xy, [&](int v) { return b.pos(v).x() == 0; });
  fp[{2, 10}] = nearest(front_skin, V3(0, -60, 0), xy, [&](int v) { return b.pos(v).x() == 0; });
  fp[{2, 11}] = nearest(front_skin, V3(14, -68, 0), xy);
  fp[{2, 13}] = nearest(front_skin, V3(56, -50, 0), xy, [&](int v) { return b.pos(v).z() > 25; });
  const double eye_col_x = b.pos(nearest(eye_row, V3(kEyeX, kEyeY, 0), xy, is_upper)).x();
  fp[{3, 1}] = nearest(eye_row, V3(eye_col_x, kEyeY, 0), xy, is_upper);
  fp[{3, 3}] = nearest(eye_row, V3(eye_col_x, kEyeY, 0), xy, is_lower);
  fp[{3, 5}] = left_pupil;
  fp[{3, 7}] = slit_end(eye_row, true, kEyeX + kLidHW - 0.01, 80);
  fp[{3, 11}] = slit_end(eye_row, false, 0, kEyeX - kLidHW + 0.01);
  fp[{3, 9}] = nearest(front_skin, V3(eye_col_x, kEyeY - kLidH - 3, 0), xy,
                       [&](int v) { return b.pos(v).y() < kEyeY - kLidH - 1; });
  fp[{3, 13}] = nearest(front_skin, V3(eye_col_x, kEyeY + kLidH + 3, 0), xy,
                        [&](int v) { return b.pos(v).y() > kEyeY + kLidH + 1; });
  fp[{4, 1}] = nearest(front_skin, V3(kBrowInnerX, brow_top_y(kBrowInnerX), 0), xy);
  fp[{4, 3}] = nearest(front_skin, V3(kBrowMidX, brow_top_y(kBrowMidX), 0), xy);
  fp[{4, 5}] = nearest(front_skin, V3(kBrowOuterX, brow_top_y(kBrowOuterX), 0), xy);
  fp[{5, 1}] = nearest(front_skin, V3(44, -14, 0), xy);
  fp[{5, 3}] = nearest(front_skin, V3(41, 8, 0), xy);
  fp[{9, 1}] = nearest(front_skin, V3(12.5, -5, 0), xy);
  fp[{9, 3}] =
      nearest(front_skin, V3(0, 2, 200), V3(0.3, 0.3, 1), [&](int v) { return b.pos(v).x() == 0; });
  fp[{9, 15}] = nearest(front_skin, V3(0, -11, 0), xy, [&](int v) { return b.pos(v).x() == 0; });
  fp[{9, 5}] = nearest(front_skin, V3(8, -9, 0), xy);
  fp[{9, 7}] = nearest(front_skin, V3(6, 24, 0), xy);
  fp[{9, 12}] = nearest(front_skin, V3(0, 14, 0), xy, [&](int v) { return b.pos(v).x() == 0; });
  fp[{9, 13}] = nearest(front_skin, V3(7, 12, 0), xy);
  fp[{11, 1}] =
      nearest(front_skin, V3(0, hairline(0), 0), xy, [&](int v) { return b.pos(v).x() == 0; });
  fp[{11, 3}] = nearest(front_skin, V3(42, hairline(0.7), 0), xy);
  fp[{11, 4}] = skull_top;
  fp[{11, 5}] = pole;
  fp[{11, 6}] = nearest(skin.vertices, V3(0, 30, -200), V3(1, 1, 0.2),
                        [&](int v) { return b.pos(v).x() == 0; });
  {  // The left ear: its top, back and lobe; where it meets the head above and below.
    auto extreme = [&](const std::function<double(const V3&)>& score, bool inner_only) {
      int best = -1;
      for (int v : left_ear)
        if ((!inner_only || b.pos(v).x() < left_ear_c.x()) &&
            (best < 0 || score(b.pos(v)) > score(b.pos(best))))
          best = v;
      return best;
    };
    fp[{10, 1}] = extreme([](const V3& p) { return p.y(); }, false);
    fp[{10, 3}] = extreme([](const V3& p) { return -p.z(); }, false);
    fp[{10, 5}] = extreme([](const V3& p) { return -p.y(); }, false);
    fp[{10, 9}] = extreme([](const V3& p) { return p.y() + 0.5 * p.z(); }, true);
    fp[{10, 7}] = extreme([](const V3& p) { return -p.y() + 0.5 * p.z(); }, true);
  }
  fp[{6, 1}] = tongue.front_pole;
  fp[{6, 2}] = nearest(tongue.vertices, tongue_c + V3(0, tongue_r.y(), 0), V3::Ones());
  fp[{6, 3}] = nearest(tongue.vertices, tongue_c + V3(tongue_r.x(), 0, 0), V3::Ones());
  fp[{7, 1}] = spine;
  auto centre_of = [&](const std::vector<int>& part, double y) {
    return nearest(part, V3(0, y, teeth_front + 10), V3(1, 1, 1));
  };
  fp[{9, 8}] = centre_of(m.parts.upper_teeth.vertices, kMouthY + 9.0);
  fp[{9, 10}] = centre_of(m.parts.upper_teeth.vertices, kMouthY);
  fp[{9, 11}] = centre_of(m.parts.lower_teeth.vertices, kMouthY);
  fp[{9, 9}] = centre_of(m.parts.lower_teeth.vertices, kMouthY - 9.0);

  // Mirror the left points to the right by position (the mesh is exactly symmetric).
  std::map<std::array<long, 4>, int> by_position;
  auto key = [](const Eigen::Vector3f& p, Side side) {
    return std::array<long, 4>{std::lround(p.x() * 1e4), std::lround(p.y() * 1e4),
                               std::lround(p.z() * 1e4), static_cast<long>(side)};
  };
  for (std::size_t v = 0; v < m.positions.size(); ++v)
    by_position.emplace(key(m.positions[v], b.side[v]), static_cast<int>(v));
  // The vertex at the mirrored position on the same side of a slit (copies share corners).
  auto mirror_vertex = [&](int v) {
    Eigen::Vector3f p = m.positions[static_cast<std::size_t>(v)];
    p.x() = -p.x();
    auto it = by_position.find(key(p, b.side[static_cast<std::size_t>(v)]));
    if (it == by_position.end()) throw std::logic_error("head generator: mesh is not symmetric");
    return it->second;
  };
  std::map<FeaturePointId, int> right;
  for (const auto& [id, v] : fp) {
    const FeaturePointId twin = mirror(id);
    if (twin == id) continue;
    right[twin] = mirror_vertex(v);
  }
  right[{3, 6}] = right_pupil;
  for (const auto& [id, v] : right) fp[id] = v;

  // --- Regions. Helpers select skin vertices by position and side.
  auto select = [&](const std::vector<int>& set, const std::function<bool(const V3&, Side)>& keep) {
    std::vector<int> out;
    for (int v : set)
      if (keep(b.pos(v), b.side[static_cast<std::size_t>(v)])) out.push_back(v);
    return out;
  };
  std::vector<int> skin_all = skin.vertices;
  skin_all.insert(skin_all.end(), skin.upper_flange.begin(), skin.upper_flange.end());
  skin_all.insert(skin_all.end(), skin.lower_flange.begin(), skin.lower_flange.end());
  auto region = [&](std::string name, InfluenceKind kind, std::vector<FeaturePointId> points,
                    std::vector<int> vertices) {
    InfluenceRegion r;
    r.name = std::move(name);
    r.kind = kind;
    r.feature_points = std::move(points);
    r.vertices = std::move(vertices);
    return r;
  };
  auto anchors_near = [&](const std::vector<int>& set, const std::vector<V3>& targets) {
    std::vector<int> out;
    for (const V3& t : targets) {
      const int v = nearest(set, t, xy);
      bool used = std::find(out.begin(), out.end(), v) != out.end();
      for (const auto& [id, u] : fp) used = used || u == v;
      if (!used) out.push_back(v);
    }
    return out;
  };
  // Side labels the two edges of the eye slits as well as of the mouth; only the mouth's count
  // here, or the lower eyelids would join the lower lip and the jaw.
  auto upper_of_mouth = [&](const V3& p, Side s) {
    const bool mouth_edge = s != Side::None && std::abs(p.y() - kMouthY) < 15;
    return mouth_edge ? s == Side::Upper : p.y() >= kMouthY - 1e-6;
  };
  // Past the lips' outer corners the skin follows the corner itself (below), whichever side
  // of the mouth line it lies, so that a corner stretched or raised by a full smile, or drawn
  // in by a rounded "oo", carries the cheek beside it. The lips' regions hand the skin over
  // between kCornerShareX and kCornerSkinX: a narrower band, or lips' regions that kept it
  // to their anchors, left a fold from each corner toward the nose and the chin. On the
  // mouth line itself the band starts past the inner corners, which the lips move exactly.
  auto corner_share = [&](int v) {
    const V3 p = b.pos(v);
    const double on_line = 1 - smoothstep(0, 6, std::abs(p.y() - my));
    const double start = kCornerShareX + (kMouthHW + 1 - kCornerShareX) * on_line;
    return smoothstep(start, kCornerSkinX, std::abs(p.x()));
  };
  auto hand_over_to_the_corners = [&](InfluenceRegion& r) {
    r.vertex_weights.clear();
    for (int v : r.vertices) r.vertex_weights.push_back(1 - corner_share(v));
  };
  std::vector<InfluenceRegion> regions;
  std::vector<InfluenceRegion> sided;  // defined on the left, mirrored below
  // A lip stretched or drawn in moves as a whole: no FAP moves its intermediate points (2.6-2.9,
  // 8.5-8.8) along the mouth, so an RBF holding them would pin them there while the corners
  // passed them (an "oo" with square ends). Each corner's stretch gets its own RBF over its
  // half of the lip, between the corner and the still middle (a half, so that a vertex carries
  // two more weights rather than four); the lip's other FAPs keep all points.
  auto push_lip = [&](InfluenceRegion r) {
    const std::vector<int> stretch = {6, 7, 53, 54};
    InfluenceRegion half = r;
    half.name += "_stretch_l";
    half.faps = stretch;
    const std::set<FeaturePointId> middles_and_left_corners = {{2, 2}, {2, 3}, {8, 1},
                                                               {8, 2}, {2, 4}, {8, 3}};
    half.vertices.clear();
    half.vertex_weights.clear();
    for (std::size_t i = 0; i < r.vertices.size(); ++i)
      if (b.pos(r.vertices[i]).x() > 1e-6) {
        half.vertices.push_back(r.vertices[i]);
        half.vertex_weights.push_back(r.vertex_weights[i]);
      }
    std::erase_if(half.feature_points,
                  [&](FeaturePointId id) { return !middles_and_left_corners.count(id); });
    std::erase_if(half.anchors, [&](int v) { return b.pos(v).x() < -1e-6; });
    for (int f = 3; f <= 68; ++f)
      if (std::find(stretch.begin(), stretch.end(), f) == stretch.end()) r.faps.push_back(f);
    regions.push_back(std::move(r));
    sided.push_back(std::move(half));
  };

  {  // Upper lip: RBF bounded by the inner and outer lip points, anchored at its border.
    auto v = select(skin_all, [&](const V3& p, Side s) {
      return upper_of_mouth(p, s) && std::abs(p.x()) < 36 && p.y() < -13.5 && p.z() > 50;
    });
    InfluenceRegion r =
        region("upper_lip", InfluenceKind::Rbf,
               {{2, 2}, {2, 6}, {2, 7}, {2, 4}, {2, 5}, {8, 1}, {8, 5}, {8, 6}, {8, 3}, {8, 4}}, v);
    r.anchors = anchors_near(v, {{0, -14, 0},
                                 {12, -14, 0},
                                 {-12, -14, 0},
                                 {24, -16, 0},
                                 {-24, -16, 0},
                                 {35, -22, 0},
                                 {-35, -22, 0},
                                 {35.5, my + 0.5, 0},
                                 {-35.5, my + 0.5, 0}});
    hand_over_to_the_corners(r);
    push_lip(r);
  }
  {  // Lower lip, anchored along the chin groove.
    auto v = select(skin_all, [&](const V3& p, Side s) {
      return !upper_of_mouth(p, s) && std::abs(p.x()) < 36 && p.y() > my - 21 && p.z() > 50;
    });
    InfluenceRegion r =
        region("lower_lip", InfluenceKind::Rbf,
               {{2, 3}, {2, 8}, {2, 9}, {8, 2}, {8, 7}, {8, 8}, {2, 4}, {2, 5}, {8, 3}, {8, 4}}, v);
    r.anchors = anchors_near(v, {{0, my - 20.5, 0},
                                 {14, my - 19.5, 0},
                                 {-14, my - 19.5, 0},
                                 {28, my - 15, 0},
                                 {-28, my - 15, 0},
                                 {35, my - 4, 0},
                                 {-35, my - 4, 0}});
    hand_over_to_the_corners(r);
    push_lip(r);
  }
  {  // Jaw: everything below the mouth follows 2.1 (open, thrust, shift), fading out at the
     // neck, toward the ears, and above the mouth line beside the corners.
    InfluenceRegion r = region("jaw", InfluenceKind::RaisedCosine, {{2, 1}}, {});
    r.faps = {3, 14, 15};
    r.metric = V3(1, 0.5, 0.3);
    r.d_max = 95;
    for (int v : skin_all) {
      const V3 p = b.pos(v);
      const Side s = b.side[static_cast<std::size_t>(v)];
      if (p.z() < 0 || p.y() < -104) continue;
      const double ax = std::abs(p.x()), dy = p.y() - my;
      const bool upper = upper_of_mouth(p, s);
      // Away from the mouth line the lower face follows the jaw and the upper lip does not,
      // save beside the corners. At the line the lips part by the mouth's aperture there:
      // wholly at the middle, not at all at the corners, which go down half as far as the
      // jaw, so that an open mouth is rounded at its ends. Past the corners, where no slit
      // divides the skin, both sides of the line agree, and farther out go with the jaw.
      const double away = upper ? smoothstep(24, 42, ax) * (1 - smoothstep(0, 22, dy)) : 1.0;
      const double aperture = mouth_aperture(ax);
      const double corner = 1 - smoothstep(kMouthHW, kMouthHW + 18, ax);
      const double below_line = 1 - 0.5 * corner * (1 - aperture);
      const double at_line = upper ? below_line - aperture : below_line;
      const double near = 1 - smoothstep(0, 10, std::abs(dy));
      double w = smoothstep(-102, -84, p.y()) * smoothstep(0, 35, p.z()) *
                 (near * at_line + (1 - near) * away);
      if (w <= 1e-3) continue;
      r.vertices.push_back(v);
      r.vertex_weights.push_back(w);
    }
    regions.push_back(r);
  }
  {  // Chin boss.
    const V3 c = b.pos(fp[{2, 10}]);
    InfluenceRegion r =
        region("chin", InfluenceKind::RaisedCosine, {{2, 10}},
               select(front_skin, [&](const V3& p, Side) { return (p - c).norm() < 18; }));
    r.d_max = 18;
    regions.push_back(r);
  }
  {  // Mouth floor follows the jaw, more the lower it is.
    InfluenceRegion r = region("mouth_floor", InfluenceKind::Rigid, {{2, 1}}, {});
    r.faps = {3, 14, 15};
    for (int v : cavity.vertices) {
      const double w = smoothstep(kMouthY + 4, kMouthY - 8, b.pos(v).y());
      if (w <= 0) continue;
      r.vertices.push_back(v);
      r.vertex_weights.push_back(w);
    }
    regions.push_back(r);
  }
  {  // Nose tip.
    const V3 c = b.pos(fp[{9, 3}]);
    InfluenceRegion r =
        region("nose_tip", InfluenceKind::RaisedCosine, {{9, 3}},
               select(front_skin, [&](const V3& p, Side) { return (p - c).norm() < 16; }));
    r.d_max = 16;
    regions.push_back(r);
  }
  {  // Tongue: tip and body.
    InfluenceRegion tip =
        region("tongue_tip", InfluenceKind::RaisedCosine, {{6, 1}}, tongue.vertices);
    tip.d_max = 34;
    regions.push_back(tip);
    InfluenceRegion body =
        region("tongue_body", InfluenceKind::RaisedCosine, {{6, 2}}, tongue.vertices);
    body.d_max = 26;
    regions.push_back(body);
  }
  {  // Left eyelids: cosine along x from the lid's centre, fading above / below the margin.
    for (bool upper : {true, false}) {
      InfluenceRegion r =
          region(upper ? "upper_eyelid_l" : "lower_eyelid_l", InfluenceKind::RaisedCosine,
                 {upper ? FeaturePointId{3, 1} : FeaturePointId{3, 3}}, {});
      r.metric = V3(1, 0, 0);
      r.d_max = kLidReach;
      const double cx = b.pos(fp[{3, 1}]).x();
      for (int v : skin_all) {
        const V3 p = b.pos(v);
        const Side s = b.side[static_cast<std::size_t>(v)];
        if (p.x() < 5 || std::abs(p.x() - cx) >= kLidReach || p.z() < 40) continue;
        const bool above = s == Side::Upper || (s == Side::None && p.y() >= kEyeY);
        if (above != upper) continue;
        const double margin =
            kEyeY + (upper ? 1 : -1) * kLidH * eye_aperture(std::abs(p.x() - kEyeX));
        const double d = upper ? p.y() - margin : margin - p.y();
        const double w = 1 - smoothstep(2.0, upper ? 12.0 : 9.0, d);
        if (w <= 1e-3) continue;
        r.vertices.push_back(v);
        r.vertex_weights.push_back(w);
      }
      sided.push_back(r);
    }
  }
  {  // Left eyebrow: RBF through its three points, anchored around it.
    auto v = select(front_skin, [&](const V3& p, Side) {
      return p.x() > 4 && p.x() < 58 && p.y() > kEyeY + 9 && p.y() < kEyeY + 35;
    });
    InfluenceRegion r = region("eyebrow_l", InfluenceKind::Rbf, {{4, 1}, {4, 3}, {4, 5}}, v);
    r.anchors = anchors_near(v, {{5, 44, 0},
                                 {8, 60, 0},
                                 {31, 64, 0},
                                 {54, 60, 0},
                                 {57, 44, 0},
                                 {50, 39.5, 0},
                                 {31, 39.5, 0},
                                 {14, 39.5, 0}});
    sided.push_back(r);
  }
  {  // Left cheek: averaged cosines of the cheek centre and the cheek bone.
    const V3 a = b.pos(fp[{5, 1}]), c = b.pos(fp[{5, 3}]);
    InfluenceRegion r = region("cheek_l", InfluenceKind::AveragedCosine, {{5, 1}, {5, 3}},
                               select(front_skin, [&](const V3& p, Side) {
                                 return p.x() > 8 && std::min((p - a).norm(), (p - c).norm()) < 24;
                               }));
    r.d_max = 24;
    sided.push_back(r);
  }
  {  // Skin beside the left mouth corner: a cosine around it, taken over from the lips.
    const V3 c = b.pos(fp[{8, 3}]);
    InfluenceRegion r = region("mouth_corner_l", InfluenceKind::RaisedCosine, {{8, 3}}, {});
    r.d_max = kCornerReach;
    for (int v : skin_all) {
      const V3 p = b.pos(v);
      const double w = corner_share(v);
      if (p.x() <= 0 || p.z() <= 50 || w <= 1e-3 || (p - c).norm() >= kCornerReach) continue;
      r.vertices.push_back(v);
      r.vertex_weights.push_back(w);
    }
    sided.push_back(r);
  }
  {  // Left nostril.
    const V3 c = b.pos(fp[{9, 1}]);
    InfluenceRegion r =
        region("nostril_l", InfluenceKind::RaisedCosine, {{9, 1}},
               select(front_skin, [&](const V3& p, Side) { return (p - c).norm() < 9; }));
    r.d_max = 9;
    sided.push_back(r);
  }
  {  // Left ear: raised (FAP 65) from its top, pulled out (FAP 67) from its back, the part
     // nearest the head moving least.
    InfluenceRegion top = region("ear_top_l", InfluenceKind::RaisedCosine, {{10, 1}}, left_ear);
    top.d_max = 2.2 * ear_r.y();
    sided.push_back(top);
    InfluenceRegion back = region("ear_back_l", InfluenceKind::RaisedCosine, {{10, 3}}, left_ear);
    back.d_max = 2.2 * ear_r.z();
    sided.push_back(back);
  }
  for (const InfluenceRegion& r : sided) {
    regions.push_back(r);
    InfluenceRegion t = r;
    t.name.back() = 'r';
    for (FeaturePointId& p : t.feature_points) p = mirror(p);
    for (int& v : t.vertices) v = mirror_vertex(v);
    for (int& v : t.anchors) v = mirror_vertex(v);
    regions.push_back(t);
  }
  m.regions = std::move(regions);
  // The neck twists between the turning head and the shoulders, which stay.
  std::vector<int> neck = shoulders;
  for (int v : skin.vertices)
    if (b.pos(v).y() < kTurnTopY) neck.push_back(v);
  std::sort(neck.begin(), neck.end());
  for (int v : neck) {
    m.turn_weights.vertices.push_back(v);
    m.turn_weights.weights.push_back(smoothstep(kTurnFootY, kTurnTopY, b.pos(v).y()));
  }
  paint_skin(m, shape);
  m.fapu = fapu_from_feature_points(m.feature_point_positions());
  m.validate("generated head");
  return std::move(b.m);
}

}  // namespace rostro
