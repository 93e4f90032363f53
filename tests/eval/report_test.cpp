#include "eval/report.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace rostro::eval {
namespace {

using tracking::MarkerObservation;
using tracking::TrackedFrame;

std::vector<TrackedFrame> frames(int n, double dx) {
  std::vector<TrackedFrame> out;
  for (int i = 0; i < n; ++i) {
    TrackedFrame f;
    f.frame = i;
    for (auto [fp, x] : {std::pair{"3.12", 100.0}, std::pair{"3.7", 300.0}}) {
      MarkerObservation m;
      m.marker = fp;
      m.feature_point = *parse_feature_point(fp);
      m.position = {x + dx, 50};
      m.valid = true;
      f.markers.push_back(m);
    }
    out.push_back(f);
  }
  return out;
}

TEST(Report, TrackJsonHoldsTheFigures) {
  const auto truth = frames(4, 0);
  auto est = frames(4, 4);  // 4 px off, d = 200 px -> NME 0.02
  est.pop_back();           // frame 3 missing -> NME null, a failure
  const TrackEvalResult r = evaluate_tracks(truth, est);
  const auto j = nlohmann::json::parse(track_report_json(r, {"t.csv", "e.csv"}));
  EXPECT_EQ(j["kind"], "rostro.eval.tracks");
  EXPECT_EQ(j["truth"], "t.csv");
  EXPECT_EQ(j["estimate"], "e.csv");
  EXPECT_EQ(j["options"]["norm"][0], "3.7");
  EXPECT_EQ(j["options"]["norm"][1], "3.12");
  EXPECT_EQ(j["frames"]["scored"], 4);
  EXPECT_EQ(j["frames"]["missing"], 1);
  EXPECT_NEAR(j["nme"]["mean"].get<double>(), 0.02, 1e-12);
  EXPECT_NEAR(j["auc"].get<double>(), 0.75 * (1 - 0.02 / 0.08), 1e-12);
  EXPECT_NEAR(j["failure_rate"].get<double>(), 0.25, 1e-12);
  EXPECT_EQ(j["lost"]["observations"], 2);
  EXPECT_EQ(j["lost"]["frames"], 1);
  EXPECT_EQ(j["swaps"]["events"], 0);
  EXPECT_EQ(j["astray"], 0);
  ASSERT_EQ(j["markers"].size(), 2u);
  EXPECT_EQ(j["markers"][0]["fp"], "3.12");
  EXPECT_NEAR(j["markers"][0]["error_px"]["median"].get<double>(), 4.0, 1e-12);
  ASSERT_EQ(j["per_frame"].size(), 4u);
  EXPECT_TRUE(j["per_frame"][3]["nme"].is_null());
  EXPECT_NEAR(j["norm_px_median"].get<double>(), 200.0, 1e-12);

  const std::string md = track_summary_markdown(r, {"t.csv", "e.csv"});
  EXPECT_NE(md.find("| 3.7 | 3.7 | 3 |"), std::string::npos) << md;
  EXPECT_NE(md.find("AUC@0.08"), std::string::npos);
}

TEST(Report, FapJsonHoldsTheFigures) {
  FapStream truth, est;
  for (int i = 0; i < 3; ++i) {
    FapFrame f;
    f.index = i;
    f.set(3, 100.0 * i);
    truth.frames.push_back(f);
    f.set(3, 100.0 * i + 30);
    est.frames.push_back(f);
  }
  const FapEvalResult r = evaluate_faps(truth, est);
  const auto j = nlohmann::json::parse(fap_report_json(r, {"a.fap", "b.fap"}));
  EXPECT_EQ(j["kind"], "rostro.eval.faps");
  EXPECT_EQ(j["frames"]["matched"], 3);
  ASSERT_EQ(j["faps"].size(), 1u);
  EXPECT_EQ(j["faps"][0]["fap"], 3);
  EXPECT_EQ(j["faps"][0]["name"], "open_jaw");
  EXPECT_NEAR(j["faps"][0]["rms"].get<double>(), 30.0, 1e-12);
  EXPECT_NEAR(j["faps"][0]["rms_share_of_range"].get<double>(), 0.15, 1e-12);
  EXPECT_NEAR(j["faps"][0]["correlation"].get<double>(), 1.0, 1e-12);
  EXPECT_NE(fap_summary_markdown(r, {"a.fap", "b.fap"}).find("open_jaw"), std::string::npos);
}

TEST(Report, WriteTextFileReplacesAtomically) {
  const auto path = std::filesystem::path(ROSTRO_BINARY_DIR) / "test_eval_tmp" / "report.md";
  std::filesystem::create_directories(path.parent_path());
  write_text_file(path, "first\n");
  write_text_file(path, "second\n");
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "second\n");
}

}  // namespace
}  // namespace rostro::eval
