// Each relationship rule of the seed, mirror fallbacks, unit conversion and the rule that a
// measured FAP is never overwritten.
#include "mapping/hierarchy.hpp"

#include <gtest/gtest.h>

#include "facecore/error.hpp"

namespace rostro::mapping {
namespace {

Fapu test_fapu() {
  Fapu f;
  f.es0 = 60;
  f.ens0 = 45;
  f.mns0 = 20;
  f.mw0 = 50;
  f.irisd0 = 11;
  return f;
}

int id(const char* name) {
  return *find_fap(name);
}

Hierarchy bundled() {
  return read_hierarchy(std::filesystem::path(ROSTRO_DATA_DIR) / "hierarchy.json");
}

TEST(Hierarchy, MirrorTwinsByName) {
  EXPECT_EQ(mirror_fap(id("raise_l_i_eyebrow")), id("raise_r_i_eyebrow"));
  EXPECT_EQ(mirror_fap(id("stretch_r_cornerlip_o")), id("stretch_l_cornerlip_o"));
  EXPECT_EQ(mirror_fap(id("lower_t_lip_lm_o")), id("lower_t_lip_rm_o"));
  EXPECT_EQ(mirror_fap(id("close_t_l_eyelid")), id("close_t_r_eyelid"));
  EXPECT_EQ(mirror_fap(id("open_jaw")), std::nullopt);
  EXPECT_EQ(mirror_fap(id("bend_nose")), std::nullopt);
  for (int f = 3; f <= kFapCount; ++f) {
    if (auto twin = mirror_fap(f)) {
      EXPECT_EQ(mirror_fap(*twin), f) << fap_info(f).name;
    }
  }
}

TEST(Hierarchy, CheeksFollowMouthCornersHalfOnXQuarterOnY) {
  const Fapu fapu = test_fapu();
  FapFrame f;
  f.set(id("stretch_l_cornerlip_o"), 100);
  f.set(id("stretch_r_cornerlip_o"), 80);
  f.set(id("raise_l_cornerlip_o"), 120);
  f.set(id("raise_r_cornerlip_o"), 40);
  apply_hierarchy(bundled(), fapu, f);
  // Units differ (MW -> ES, MNS -> ENS): the physical displacement ratio is the factor.
  EXPECT_NEAR(f.get(id("puff_l_cheek")), 0.5 * 100 * 50.0 / 60.0, 1e-9);
  EXPECT_NEAR(f.get(id("puff_r_cheek")), 0.5 * 80 * 50.0 / 60.0, 1e-9);
  EXPECT_NEAR(f.get(id("lift_l_cheek")), 0.25 * 120 * 20.0 / 45.0, 1e-9);
  EXPECT_NEAR(f.get(id("lift_r_cheek")), 0.25 * 40 * 20.0 / 45.0, 1e-9);
  EXPECT_NEAR(f.get(id("puff_l_cheek")) * fapu.unit_size(FapUnit::ES),
              0.5 * 100 * fapu.unit_size(FapUnit::MW), 1e-12);
}

TEST(Hierarchy, InnerLipsEqualOuterLips) {
  const std::pair<const char*, const char*> pairs[] = {
      {"lower_t_midlip", "lower_t_midlip_o"},
      {"raise_b_midlip", "raise_b_midlip_o"},
      {"stretch_l_cornerlip", "stretch_l_cornerlip_o"},
      {"stretch_r_cornerlip", "stretch_r_cornerlip_o"},
      {"lower_t_lip_lm", "lower_t_lip_lm_o"},
      {"lower_t_lip_rm", "lower_t_lip_rm_o"},
      {"raise_b_lip_lm", "raise_b_lip_lm_o"},
      {"raise_b_lip_rm", "raise_b_lip_rm_o"},
      {"raise_l_cornerlip", "raise_l_cornerlip_o"},
      {"raise_r_cornerlip", "raise_r_cornerlip_o"}};
  FapFrame f;
  double v = 10;
  for (const auto& [inner, outer] : pairs) f.set(id(outer), v += 7);
  const auto derived = apply_hierarchy(bundled(), test_fapu(), f);
  for (const auto& [inner, outer] : pairs) {
    EXPECT_TRUE(f.has(id(inner))) << inner;
    EXPECT_DOUBLE_EQ(f.get(id(inner)), f.get(id(outer))) << inner;
    EXPECT_TRUE(derived.test(static_cast<std::size_t>(id(inner) - 1)));
  }
}

TEST(Hierarchy, ThrustJawIsHalfOpenJaw) {
  FapFrame f;
  f.set(id("open_jaw"), 400);
  apply_hierarchy(bundled(), test_fapu(), f);
  EXPECT_DOUBLE_EQ(f.get(id("thrust_jaw")), 200);
}

TEST(Hierarchy, MeasuredFapsAreNeverOverwritten) {
  FapFrame f;
  f.set(id("lower_t_midlip_o"), 30);
  f.set(id("lower_t_midlip"), 7);
  f.set(id("stretch_l_cornerlip_o"), 100);
  f.set(id("puff_l_cheek"), -12);
  f.set(id("stretch_r_cornerlip"), 5);  // measured inner, no outer
  f.set(id("stretch_l_cornerlip"), 9);  // its mirror twin is not used over the rule either
  const FapFrame before = f;
  const auto derived = apply_hierarchy(bundled(), test_fapu(), f);
  for (int fap = 1; fap <= kFapCount; ++fap)
    if (before.has(fap)) {
      EXPECT_EQ(f.get(fap), before.get(fap)) << fap_info(fap).name;
      EXPECT_FALSE(derived.test(static_cast<std::size_t>(fap - 1)));
    }
}

TEST(Hierarchy, MirrorFillsTheMissingSide) {
  FapFrame f;
  f.set(id("raise_l_i_eyebrow"), 80);
  f.set(id("stretch_l_cornerlip_o"), 100);
  f.set(id("raise_r_i_eyebrow"), 50);  // both measured: left alone
  f.set(id("raise_l_m_eyebrow"), 70);
  apply_hierarchy(bundled(), test_fapu(), f);
  EXPECT_DOUBLE_EQ(f.get(id("stretch_r_cornerlip_o")), 100);
  EXPECT_DOUBLE_EQ(f.get(id("raise_r_m_eyebrow")), 70);
  EXPECT_DOUBLE_EQ(f.get(id("raise_r_i_eyebrow")), 50);
  // The mirrored corner feeds the right cheek and inner corner in turn.
  EXPECT_NEAR(f.get(id("puff_r_cheek")), 0.5 * 100 * 50.0 / 60.0, 1e-9);
  EXPECT_DOUBLE_EQ(f.get(id("stretch_r_cornerlip")), 100);
}

TEST(Hierarchy, RuleFallsBackToTheMirroredSource) {
  Hierarchy h = hierarchy_from_json(R"({"mirror_missing": false, "rules": [
      {"target": "lift_r_cheek", "source": "raise_r_cornerlip_o", "factor": 0.25},
      {"target": "thrust_jaw", "source": "open_jaw", "factor": 0.5, "mirror_fallback": false}]})",
                                    "test");
  FapFrame f;
  f.set(id("raise_l_cornerlip_o"), 90);
  apply_hierarchy(h, test_fapu(), f);
  EXPECT_FALSE(f.has(id("raise_r_cornerlip_o"))) << "mirror_missing is off";
  EXPECT_NEAR(f.get(id("lift_r_cheek")), 0.25 * 90 * 20.0 / 45.0, 1e-9);
  EXPECT_FALSE(f.has(id("thrust_jaw")));
}

TEST(Hierarchy, UnidirectionalTargetsAreClamped) {
  FapFrame f;
  f.set(id("raise_l_cornerlip_o"), -80);
  f.set(id("raise_r_cornerlip_o"), -80);
  apply_hierarchy(bundled(), test_fapu(), f);
  ASSERT_TRUE(f.has(id("lift_l_cheek")));
  EXPECT_EQ(f.get(id("lift_l_cheek")), 0.0);
}

TEST(Hierarchy, NothingMeasuredNothingDerived) {
  FapFrame f;
  EXPECT_TRUE(apply_hierarchy(bundled(), test_fapu(), f).none());
  EXPECT_TRUE(f.mask.none());
}

TEST(Hierarchy, BundledRulesAreTheSeeds) {
  const Hierarchy h = bundled();
  EXPECT_TRUE(h.mirror_missing);
  auto factor = [&](const char* target) {
    for (const auto& r : h.rules)
      if (r.target == id(target)) return r.factor;
    return -1.0;
  };
  EXPECT_EQ(factor("puff_l_cheek"), 0.5);
  EXPECT_EQ(factor("lift_r_cheek"), 0.25);
  EXPECT_EQ(factor("lower_t_midlip"), 1.0);
  EXPECT_EQ(factor("thrust_jaw"), 0.5);
  EXPECT_EQ(h.rules.size(), 15u);
}

TEST(Hierarchy, MalformedRulesAreReportedClearly) {
  auto message = [](const std::string& text) {
    try {
      hierarchy_from_json(text, "rules.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(message(R"({"rules": 3})").find("'rules' array"), std::string::npos);
  const std::string unknown = message(
      R"({"rules": [{"target": "open_jaw", "source": "open_jaw", "factor": 1},
                    {"target": "smile", "source": "open_jaw", "factor": 1}]})");
  EXPECT_NE(unknown.find("rule 1"), std::string::npos) << unknown;
  EXPECT_NE(
      message(R"({"rules": [{"target": "thrust_jaw", "source": "open_jaw"}]})").find("factor"),
      std::string::npos);
  EXPECT_NE(message(R"({"rules": [{"target": "thrust_jaw", "source": "shout", "factor": 1}]})")
                .find("'shout' is not an MPEG-4 FAP name"),
            std::string::npos);
  EXPECT_NE(message(R"({"rules": [{"target": "viseme", "source": "open_jaw", "factor": 1}]})")
                .find("high-level"),
            std::string::npos);
  EXPECT_THROW(read_hierarchy("/nonexistent/hierarchy.json"), InputError);
}

}  // namespace
}  // namespace rostro::mapping
