#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "facecore/fap_io.hpp"
#include "fap_test_util.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

FapStream two_frames() {
  FapStream s;
  s.header.name = "conv";
  FapFrame a;
  a.set(3, 100);
  a.set(31, -20);
  FapFrame b = a;
  b.index = 1;
  b.time_s = 0.04;
  b.set(3, 200);
  s.frames = {a, b};
  return s;
}

TEST(FapConvert, CsvHasNamedColumnsAndEmptyCellsForUnsetFaps) {
  const auto dir = test::scratch_dir("fap-csv");
  write_fap_stream(dir / "c.csv", two_frames());
  std::ifstream in(dir / "c.csv");
  std::string meta, header, row;
  std::getline(in, meta);
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_EQ(meta.rfind("# rostro-fap", 0), 0u);
  EXPECT_EQ(header.rfind("frame,time_s,viseme_select1", 0), 0u);
  EXPECT_NE(header.find(",open_jaw,lower_t_midlip,"), std::string::npos);
  EXPECT_EQ(header.substr(header.size() - 10), "pull_r_ear");
  // frame 0, time 0, ten empty high-level cells, open_jaw = 100
  EXPECT_EQ(row.rfind("0,0,,,,,,,,,,,100,,", 0), 0u) << row;
}

TEST(FapConvert, JsonNamesFapsAndCountsFrames) {
  const auto dir = test::scratch_dir("fap-json");
  write_fap_stream(dir / "c.json", two_frames());
  std::ifstream in(dir / "c.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["frame_count"], 2);
  EXPECT_EQ(doc["frames"][1]["faps"]["open_jaw"], 200);
  EXPECT_EQ(doc["frames"][1]["faps"]["raise_l_i_eyebrow"], -20);
  EXPECT_FALSE(doc["frames"][0]["faps"].contains("thrust_jaw"));
}

TEST(FapConvert, CsvAndJsonQuantiseFapsToIntegersAsTheFapFileDoes) {
  const auto dir = test::scratch_dir("fap-quantise");
  FapStream s = two_frames();
  s.frames[0].set(3, 202.12499999999997);
  s.frames[0].set(31, -20.5);  // halves round away from zero, as std::lround in the .fap
  write_fap_stream(dir / "q.csv", s);
  write_fap_stream(dir / "q.json", s);
  write_fap_stream(dir / "q.fap", s);
  for (const char* name : {"q.csv", "q.json", "q.fap"}) {
    const FapStream back = read_fap_stream(dir / name);
    EXPECT_EQ(back.frames[0].get(3), 202) << name;
    EXPECT_EQ(back.frames[0].get(31), -21) << name;
  }
  std::ifstream in(dir / "q.csv");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("202.1"), std::string::npos);
}

TEST(FapConvert, MalformedCsvAndJsonAreNamed) {
  const auto dir = test::scratch_dir("fap-bad-conv");
  const auto csv = test::write_text(dir / "bad.csv", "frame,time_s\n0,0\n");
  EXPECT_NE(test::read_error(csv).find(":1:"), std::string::npos) << test::read_error(csv);
  const auto json =
      test::write_text(dir / "bad.json", "{\"format\": \"rostro-fap\", \"fps\": 25, ");
  EXPECT_NE(test::read_error(json).find("not valid JSON"), std::string::npos);
  const auto unknown = test::write_text(
      dir / "unknown.json",
      R"({"format":"rostro-fap","fps":25,"frames":[{"frame":0,"faps":{"open_mouth":3}}]})");
  EXPECT_NE(test::read_error(unknown).find("unknown FAP 'open_mouth'"), std::string::npos);
}

}  // namespace
}  // namespace rostro
