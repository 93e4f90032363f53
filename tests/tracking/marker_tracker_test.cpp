// MarkerTracker's options check themselves: a value out of range is one line naming it.
#include "tracking/marker_tracker.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "facecore/error.hpp"

namespace rostro::tracking {
namespace {

MarkerLayout default_layout() {
  return load_layout(std::filesystem::path(ROSTRO_DATA_DIR) / "layouts" / "default.json");
}

// The message validate() throws for `o`, or "" when it passes.
template <typename Options>
std::string complaint(const Options& o) {
  try {
    o.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TrackerOptions, DefaultsPass) {
  EXPECT_EQ(complaint(TrackerOptions{}), "");
  EXPECT_EQ(complaint(DotOptions{}), "");
}

TEST(TrackerOptions, BadValueIsNamedInOneLine) {
  TrackerOptions o;
  o.lk_window = 0;
  EXPECT_EQ(complaint(o), "TrackerOptions::lk_window = 0: should be > 0");
  EXPECT_THROW(MarkerTracker tracker(default_layout(), o), InputError);
  o = {};
  o.eyes.max_dot_growth_found = 0.9;
  EXPECT_EQ(complaint(o), "EyeOptions::max_dot_growth_found = 0.9: should be >= 1");
  o = {};
  o.lower_lip.shape = 0;
  EXPECT_EQ(complaint(o), "LowerLipOptions::shape = 0: should be > 0");
}

TEST(DotOptions, BadValueIsNamedInOneLine) {
  DotOptions d;
  d.max_diameter_px = 3;  // below min_diameter_px (4)
  EXPECT_EQ(complaint(d), "DotOptions::max_diameter_px = 3: should be >= 4");
  d = {};
  d.min_roundness = 1.5;
  EXPECT_EQ(complaint(d), "DotOptions::min_roundness = 1.5: should be in 0..1");
  // Checked with the tracker's options, as the tracker's constructor does.
  TrackerOptions o;
  o.dots.max_elongation = 0.5;
  EXPECT_EQ(complaint(o), "DotOptions::max_elongation = 0.5: should be >= 1");
  EXPECT_THROW(MarkerTracker tracker(default_layout(), o), InputError);
}

TEST(TrackerOptions, SetByName) {
  TrackerOptions o;
  set_tracker_option(o, "eyes.max_dot_growth_found=1.3");
  set_tracker_option(o, "lower_lip.together=false");
  set_tracker_option(o, "dots.max_elongation=4");
  set_tracker_option(o, "lk_window=15");
  EXPECT_EQ(o.eyes.max_dot_growth_found, 1.3);
  EXPECT_FALSE(o.lower_lip.together);
  EXPECT_EQ(o.dots.max_elongation, 4);
  EXPECT_EQ(o.lk_window, 15);
}

TEST(TrackerOptions, BadNameOrValueIsOneLine) {
  TrackerOptions o;
  try {
    set_tracker_option(o, "eyes.max_dot_grwth_found=1.3");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("TrackerOptions has no option 'eyes.max_dot_grwth_found' (known: ", 0), 0u)
        << what;
    EXPECT_NE(what.find("eyes.max_dot_growth_found"), std::string::npos) << what;
  }
  EXPECT_THROW(set_tracker_option(o, "lk_window=13.5"), InputError);
  EXPECT_THROW(set_tracker_option(o, "lower_lip.together=maybe"), InputError);
  EXPECT_THROW(set_tracker_option(o, "max_snap"), InputError);
  EXPECT_EQ(o.lk_window, TrackerOptions{}.lk_window);
}

}  // namespace
}  // namespace rostro::tracking
