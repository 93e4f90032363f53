// Dark features that are no markers, and markers the layout misplaces: the pupil (a dark
// disc in the darker iris) is not taken for a dot, a lost lid dot is found beside it, a pair
// of dots both shifted from the layout's places (the chin under a nod) keep their names, and a
// long dark blob where the layout puts a dot (the lip corner beside a mouth-corner dot worn
// on the skin) is not named in its place, nor a faint one nearer a dot's place than the dot,
// nor the feature a dot is worn beside (the brow's end below a brow dot); the lower lip of an
// open mouth keeps its names.

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "tracking/dot_detector.hpp"
#include "tracking/ibug_mapping.hpp"
#include "tracking/identify.hpp"
#include "tracking/layout.hpp"

namespace {

using namespace rostro::tracking;

void disc(cv::Mat& image, cv::Point2d centre, double radius, int grey) {
  constexpr int kShift = 4;  // sub-pixel centres and radii
  const double k = 1 << kShift;
  cv::circle(image, cv::Point(static_cast<int>(centre.x * k), static_cast<int>(centre.y * k)),
             static_cast<int>(radius * k), cv::Scalar(grey), cv::FILLED, cv::LINE_AA, kShift);
}

// Skin, an iris with its pupil, and a lid dot just below the iris.
struct EyeScene {
  cv::Mat image = cv::Mat(120, 120, CV_8UC1, cv::Scalar(200));
  cv::Point2d pupil{60.0, 50.0}, lid_dot{60.4, 66.6};
  EyeScene() {
    disc(image, pupil, 11, 80);   // iris, darker than skin, lighter than a dot
    disc(image, pupil, 4.2, 25);  // pupil
    disc(image, lid_dot, 4.0, 25);
    cv::GaussianBlur(image, image, {0, 0}, 0.7);
  }
};

TEST(DarkFeatures, PupilIsNotADot) {
  EyeScene eye;
  DotOptions options;
  EXPECT_FALSE(refine_dot(eye.image, eye.pupil, 2, options).has_value());
  auto dot = refine_dot(eye.image, eye.lid_dot, 2, options);
  ASSERT_TRUE(dot.has_value());
  EXPECT_LT(cv::norm(dot->center - eye.lid_dot), 0.25);
  EXPECT_LT(dot->surround, 0.2);
  // Without the ring check the pupil passes every other test: the check is what rejects it.
  options.max_surround = 10;
  auto pupil = refine_dot(eye.image, eye.pupil, 2, options);
  ASSERT_TRUE(pupil.has_value());
  EXPECT_GT(pupil->surround, 0.55);
}

TEST(DarkFeatures, LostDotIsFoundBesideThePupil) {
  EyeScene eye;
  // Looking between the two, the pupil is as near as the dot: every candidate comes back,
  // nearest first, and only the dot passes.
  const cv::Point2d guess(60, 59);
  auto found = dots_near(eye.image, guess, 9, DotOptions{});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_LT(cv::norm(found[0].center - eye.lid_dot), 0.25);
}

TEST(DarkFeatures, DotCentreIsNotPulledByAnAdjacentDarkFeature) {
  // A dot touching a darker band (a lip, an eyebrow) without merging at half contrast.
  cv::Mat image(80, 80, CV_8UC1, cv::Scalar(200));
  cv::rectangle(image, cv::Rect(10, 45, 60, 6), cv::Scalar(150), cv::FILLED);
  const cv::Point2d centre(40.3, 39.6);
  disc(image, centre, 4.0, 30);
  cv::GaussianBlur(image, image, {0, 0}, 0.7);
  auto dot = refine_dot(image, centre, 2, DotOptions{});
  ASSERT_TRUE(dot.has_value());
  EXPECT_LT(cv::norm(dot->center - centre), 0.15);
}

// The layout's dots at their frontal places, 3 pixels a millimetre, those in `moved` shifted.
std::vector<Dot> layout_dots(const MarkerLayout& layout,
                             const std::map<std::string, cv::Point2d>& moved,
                             std::map<std::string, cv::Point2d>& truth) {
  std::vector<Dot> dots;
  for (const MarkerSpec& m : layout.markers) {
    if (m.is_tag()) continue;
    cv::Point2d p = cv::Point2d(320, 240) + 3 * m.frontal();
    if (auto it = moved.find(m.id); it != moved.end()) p += it->second;
    truth[m.id] = p;
    dots.push_back({p, 8, 100, 0});
  }
  return dots;
}

TEST(Identify, TwoDotsShiftedTheSameWayKeepTheirNames) {
  const MarkerLayout layout =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  const MarkerSpec* chin = layout.find("chin");
  const MarkerSpec* chin_boss = layout.find("chin_boss");
  ASSERT_TRUE(chin && chin_boss);
  const double spacing = cv::norm(chin->frontal() - chin_boss->frontal());
  // Both 0.6 of their spacing further down than the layout says: the chin boss's dot is then
  // nearer the chin's place than its own.
  const cv::Point2d down(0, 0.6 * spacing * 3);
  std::map<std::string, cv::Point2d> truth;
  const std::vector<Dot> dots = layout_dots(layout, {{"chin", down}, {"chin_boss", down}}, truth);
  const Identification id = identify_markers(layout, dots, {});
  for (const auto& [name, at] : truth) {
    auto it = id.dots.find(name);
    ASSERT_NE(it, id.dots.end()) << name;
    EXPECT_LT(cv::norm(it->second.center - at), 1e-9) << name;
  }
}

// The layout's default arrangement and the distance from `marker` to its nearest other dot.
struct LayoutAt {
  MarkerLayout layout =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  double spacing_of(const MarkerSpec& marker) const {
    double spacing = 1e9;
    for (const MarkerSpec& m : layout.markers)
      if (!m.is_tag() && &m != &marker)
        spacing = std::min(spacing, cv::norm(m.frontal() - marker.frontal()));
    return spacing;
  }
};

TEST(Identify, ALongBlobAtADotsPlaceIsNotNamedForIt) {
  const LayoutAt at;
  const MarkerLayout& layout = at.layout;
  const MarkerSpec* corner = layout.find("mouth_l");
  ASSERT_TRUE(corner);
  const double spacing = at.spacing_of(*corner);
  // The dot is worn on the skin 0.6 of its spacing out from where the layout puts it; the lip
  // corner, as dark, lies exactly there, twice as long as wide, and stood apart from the lips
  // only measured high up its contrast.
  std::map<std::string, cv::Point2d> truth;
  std::vector<Dot> dots =
      layout_dots(layout, {{"mouth_l", cv::Point2d(0.6 * spacing * 3, 0)}}, truth);
  Dot lip_corner{cv::Point2d(320, 240) + 3 * corner->frontal(), 8, 100, 0.3, 2.2, 0.9};
  dots.push_back(lip_corner);

  const Identification id = identify_markers(layout, dots, {});
  for (const auto& [name, where] : truth) {
    auto it = id.dots.find(name);
    ASSERT_NE(it, id.dots.end()) << name;
    EXPECT_LT(cv::norm(it->second.center - where), 1e-9) << name;
  }
  // The shape is what tells them apart: judged by place alone, the blob takes the name.
  IdentificationOptions any_shape;
  any_shape.shape_factor = 100;
  const Identification by_place = identify_markers(layout, dots, {}, any_shape);
  ASSERT_TRUE(by_place.dots.count("mouth_l"));
  EXPECT_LT(cv::norm(by_place.dots.at("mouth_l").center - lip_corner.center), 1e-9);
}

TEST(Identify, ADotForeshortenedOnSkinThatTurnsAwayIsStillNamed) {
  const MarkerLayout layout =
      load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
  // The chin's dot seen from the front lies on skin turned away from the camera: twice as long
  // as wide, but standing alone on the skin (measured at half its contrast).
  std::map<std::string, cv::Point2d> truth;
  std::vector<Dot> dots = layout_dots(layout, {}, truth);
  for (Dot& d : dots)
    if (cv::norm(d.center - truth.at("chin")) < 1e-9) d.elongation = 2.2, d.share = 0.5;
  const Identification id = identify_markers(layout, dots, {});
  ASSERT_TRUE(id.dots.count("chin"));
  EXPECT_LT(cv::norm(id.dots.at("chin").center - truth.at("chin")), 1e-9);
  // Judged by its shape alone, it would be no dot.
  IdentificationOptions shape_alone;
  shape_alone.alone_share = 0;
  EXPECT_FALSE(identify_markers(layout, dots, {}, shape_alone).dots.count("chin"));
}

TEST(Identify, AFaintBlobNearerADotsPlaceThanTheDotDoesNotTakeItsName) {
  const LayoutAt at;
  const MarkerLayout& layout = at.layout;
  const MarkerSpec* lid = layout.find("lid_r_up");
  ASSERT_TRUE(lid);
  const double spacing = at.spacing_of(*lid);
  // The upper-lid dot worn 0.4 of its spacing above the layout's place, and a shadow in the
  // eye a third as dark, of the same size and shape, 0.25 below it (the photo scene at
  // 640x480: the dot 6.4 px from its predicted place, the shadow 4.6).
  std::map<std::string, cv::Point2d> truth;
  std::vector<Dot> dots =
      layout_dots(layout, {{"lid_r_up", cv::Point2d(0, -0.4 * spacing * 3)}}, truth);
  const cv::Point2d place = cv::Point2d(320, 240) + 3 * lid->frontal();
  const Dot shadow{place + cv::Point2d(0, 0.25 * spacing * 3), 8, 33, 0};
  dots.push_back(shadow);
  const Identification id = identify_markers(layout, dots, {});
  ASSERT_TRUE(id.dots.count("lid_r_up"));
  EXPECT_LT(cv::norm(id.dots.at("lid_r_up").center - truth.at("lid_r_up")), 1e-9);
  // Judged by place alone, the shadow takes the name.
  IdentificationOptions by_place;
  by_place.ink_weight = 0;
  const Identification placed = identify_markers(layout, dots, {}, by_place);
  ASSERT_TRUE(placed.dots.count("lid_r_up"));
  EXPECT_LT(cv::norm(placed.dots.at("lid_r_up").center - shadow.center), 1e-9);
  // A dot as faint alone near its place (in a corner's shadow) is still named.
  for (Dot& d : dots)
    if (cv::norm(d.center - truth.at("lid_r_up")) < 1e-9) d.center = shadow.center;
  dots.pop_back();
  for (Dot& d : dots)
    if (cv::norm(d.center - shadow.center) < 1e-9) d.contrast = 33;
  const Identification alone = identify_markers(layout, dots, {});
  ASSERT_TRUE(alone.dots.count("lid_r_up"));
  EXPECT_LT(cv::norm(alone.dots.at("lid_r_up").center - shadow.center), 1e-9);
}

// The mid-brow dot unseen (in the brow hair) and the upper-lid dot raised halfway to the brow's
// place: the one detection is about as near either place, and naming it is a coin toss LK
// would follow to the end. It is left out; by nearness alone one of the two names takes it.
TEST(Identify, ADotAboutAsNearAnUnnamedDotsPlaceIsLeftOut) {
  const LayoutAt at;
  const MarkerLayout& layout = at.layout;
  const MarkerSpec* brow = layout.find("brow_r_mid");
  const MarkerSpec* lid = layout.find("lid_r_up");
  ASSERT_TRUE(brow && lid);
  const cv::Point2d up = 0.5 * 3 * (brow->frontal() - lid->frontal());
  std::map<std::string, cv::Point2d> truth;
  std::vector<Dot> dots = layout_dots(layout, {{"lid_r_up", up}}, truth);
  const cv::Point2d brow_at = truth.at("brow_r_mid");
  std::erase_if(dots, [&](const Dot& d) { return cv::norm(d.center - brow_at) < 1e-9; });
  truth.erase("brow_r_mid");

  const Identification id = identify_markers(layout, dots, {});
  EXPECT_FALSE(id.dots.count("brow_r_mid"));
  EXPECT_FALSE(id.dots.count("lid_r_up"));
  for (const auto& [name, where] : truth) {
    if (name == "lid_r_up") continue;
    auto it = id.dots.find(name);
    ASSERT_NE(it, id.dots.end()) << name;
    EXPECT_LT(cv::norm(it->second.center - where), 1e-9) << name;
  }
  IdentificationOptions by_nearness;
  by_nearness.unnamed_rival = 0;
  const Identification coin = identify_markers(layout, dots, {}, by_nearness);
  EXPECT_TRUE(coin.dots.count("lid_r_up") || coin.dots.count("brow_r_mid"));
}

// Where a face model (dlib's landmarks) puts the dots' feature points, given the dots' own
// places: each dot less the `beside` it is worn at (x toward the face's left, y up), `mm`
// pixels a millimetre.
std::map<std::string, cv::Point2d> points_of(const MarkerLayout& layout,
                                             const std::map<std::string, cv::Point2d>& dots,
                                             double mm) {
  std::map<std::string, cv::Point2d> points;
  for (const IbugMarker& i : default_ibug_mapping().markers)
    for (const MarkerSpec& m : layout.markers) {
      if (m.is_tag() || m.feature_point != i.feature_point) continue;
      points[m.id] = dots.at(m.id);
      if (m.beside_mm) points[m.id] -= cv::Point2d(m.beside_mm->x, -m.beside_mm->y) * mm;
    }
  return points;
}

TEST(Identify, ADotWornBesideItsPointIsLookedForThere) {
  const LayoutAt at;
  const MarkerLayout& layout = at.layout;
  const double mm = 3;  // pixels a millimetre (layout_dots)
  std::map<std::string, cv::Point2d> truth;
  std::vector<Dot> dots = layout_dots(layout, {}, truth);
  // The face model marks the brows' points (the brow's inner end, 4.1, among them), the dots
  // worn 3.5 mm above them, and the points of the nose and mouth dots, worn on them; the eye
  // dots it is not asked for. The brow's inner end is a dark blob of a dot's size right at
  // its point.
  std::map<std::string, cv::Point2d> points = points_of(layout, truth, mm);
  std::erase_if(points, [&](const auto& p) {
    const MarkerSpec* m = layout.find(p.first);
    return m->feature_point.group == 3 || m->feature_point.group == 5;
  });
  const cv::Point2d brow_end = points.at("brow_l_in");
  ASSERT_GT(cv::norm(brow_end - truth.at("brow_l_in")), 10);
  dots.push_back({brow_end, 8, 100, 0});

  const Identification id = identify_markers(layout, dots, {}, {}, points);
  for (const auto& [name, where] : truth) {
    ASSERT_TRUE(id.dots.count(name)) << name;
    EXPECT_LT(cv::norm(id.dots.at(name).center - where), 1e-9) << name;
  }
  EXPECT_LT(cv::norm(id.places.at("brow_l_in") - truth.at("brow_l_in")), 0.5);
  // Looked for at the points themselves, the brows' places lie below their dots, toward the
  // brow's end (the naming's fit through the other places takes up part of the offset).
  IdentificationOptions at_points;
  at_points.dots_beside_points = false;
  const Identification by_points = identify_markers(layout, dots, {}, at_points, points);
  EXPECT_GT(cv::norm(by_points.places.at("brow_l_in") - truth.at("brow_l_in")), 1.0);
}

TEST(Identify, AnOpenMouthsLowerLipKeepsItsNames) {
  const LayoutAt at;
  const MarkerLayout& layout = at.layout;
  // A wide open smile: the lower lip's dots 14 mm lower than the layout's places and spread, the
  // chin's lower with them, the corners out and up, the upper lip up; the face model (dlib's
  // landmarks) puts the dots it knows exactly where they are. The middle lower-lip dot, in the
  // lower lip's shadow, is not detected.
  const double mm = 3;  // pixels a millimetre (layout_dots)
  const double dl = 14, du = 3, dc = 6,
               ds = 3;  // millimetres: lower lip, upper lip, corners, spread
  std::map<std::string, cv::Point2d> truth;
  std::vector<Dot> dots = layout_dots(layout,
                                      {{"lip_bot", cv::Point2d(0, dl) * mm},
                                       {"lip_bot_l", cv::Point2d(ds, dl) * mm},
                                       {"lip_bot_r", cv::Point2d(-ds, dl) * mm},
                                       {"chin_boss", cv::Point2d(0, dl) * mm},
                                       {"chin", cv::Point2d(0, dl) * mm},
                                       {"mouth_l", cv::Point2d(dc, -dc / 2) * mm},
                                       {"mouth_r", cv::Point2d(-dc, -dc / 2) * mm},
                                       {"lip_top", cv::Point2d(0, -du) * mm},
                                       {"lip_top_l", cv::Point2d(0, -du) * mm},
                                       {"lip_top_r", cv::Point2d(0, -du) * mm}},
                                      truth);
  const std::map<std::string, cv::Point2d> expected = points_of(layout, truth, mm);
  std::erase_if(dots,
                [&](const Dot& d) { return cv::norm(d.center - truth.at("lip_bot")) < 1e-9; });

  const Identification id = identify_markers(layout, dots, {}, {}, expected);
  for (const auto& [name, where] : truth) {
    if (name == "lip_bot") continue;
    ASSERT_TRUE(id.dots.count(name)) << name;
    EXPECT_LT(cv::norm(id.dots.at(name).center - where), 1e-9) << name;
  }
  EXPECT_FALSE(id.dots.count("lip_bot"));
  // With the lower lip's places moved by the upper lip's and the corners' offsets as well,
  // they stay near the lip line, and the lower lip's dots are left unnamed.
  IdentificationOptions together;
  together.lower_lip_apart = false;
  const Identification pulled = identify_markers(layout, dots, {}, together, expected);
  EXPECT_FALSE(pulled.dots.count("lip_bot_l"));
  EXPECT_FALSE(pulled.dots.count("lip_bot_r"));
}

}  // namespace
