// No take is ever lost: the .fap sink keeps its temporary readable while it writes, a
// killed writer's temporary is recovered, a take can be kept under another name, and every
// reader rejects a number outside its type or meaning, quoting the offending token.

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "facecore/fap_io.hpp"
#include "fap_test_util.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

FapFrame jaw_frame(long index, double value) {
  FapFrame f;
  f.index = index;
  f.set(3, value);
  return f;
}

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::filesystem::path temporary_of(const std::filesystem::path& path) {
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  return tmp;
}

// The header's count field after the last checkpoint.
long header_count(const std::filesystem::path& path) {
  std::istringstream header(slurp(path).substr(0, slurp(path).find('\n')));
  std::string version, name;
  double fps = 0;
  long count = -1;
  header >> version >> name >> fps >> count;
  return count;
}

TEST(FapSafety, TemporaryVouchesForEveryCheckpointedSecond) {
  const auto dir = test::scratch_dir("fap-safety-checkpoint");
  const auto path = dir / "take.fap";
  FapHeader header;
  header.fps = 25;
  auto sink = open_fap_sink(path, header);
  const auto tmp = temporary_of(path);
  ASSERT_TRUE(std::filesystem::exists(tmp));
  EXPECT_EQ(header_count(tmp), 0);  // a valid count from the first moment
  for (long i = 0; i < 60; ++i) sink->write(jaw_frame(i, static_cast<double>(i)));
  // Two whole seconds of the take (50 frames) are on disk and vouched for; the rest may wait.
  EXPECT_GE(header_count(tmp), 50);
  const auto recovered = dir / "recovered.fap";
  const RecoveredTake take = recover_fap_file(tmp, recovered);
  EXPECT_GE(take.frames, 50);
  EXPECT_EQ(take.vouched, header_count(tmp));
  EXPECT_TRUE(validate_fap_file(recovered).empty());
  const FapStream stream = read_fap_stream(recovered);
  ASSERT_EQ(static_cast<long>(stream.frames.size()), take.frames);
  EXPECT_EQ(stream.frames[49].get(3), 49.0);
  sink->finish();
  EXPECT_EQ(read_fap_stream(path).frames.size(), 60u);
  EXPECT_FALSE(std::filesystem::exists(tmp));
}

TEST(FapSafety, RecoverStopsBeforeALineCutShort) {
  const auto dir = test::scratch_dir("fap-safety-cut");
  const std::string m3 = test::mask_line({3});
  // Count 1 checkpointed, a second frame whole, a third cut in the middle of its value.
  const auto tmp =
      test::write_text(dir / "take.fap.tmp-77", "2.1 take 25 1           \n" + m3 + "\n0 10\n" +
                                                    m3 + "\n1 20\n" + m3 + "\n2 3");
  const RecoveredTake take = recover_fap_file(tmp, dir / "take.fap");
  EXPECT_EQ(take.frames, 2);
  EXPECT_EQ(take.vouched, 1);
  EXPECT_TRUE(take.stopped.empty()) << take.stopped;
  EXPECT_TRUE(validate_fap_file(dir / "take.fap").empty());
  // Garbage after the vouched frames (a power loss before the sync) ends the take there.
  const auto junk = test::write_text(dir / "junk.fap.tmp-78",
                                     "2.1 take 25 1           \n" + m3 + "\n0 10\n\x01\x02\n");
  const RecoveredTake kept = recover_fap_file(junk, dir / "junk.fap");
  EXPECT_EQ(kept.frames, 1);
  EXPECT_NE(kept.stopped.find(":4:"), std::string::npos) << kept.stopped;
}

TEST(FapSafety, FinishAsKeepsTheTakeUnderAnotherNameAndLeavesTheOldOne) {
  const auto dir = test::scratch_dir("fap-safety-finish-as");
  const auto path = dir / "take.fap";
  test::write_text(path, "previous take\n");
  for (const char* ext : {".fap", ".csv", ".json"}) {
    const auto out = dir / (std::string("take") + ext);
    const auto partial = dir / (std::string("take.partial") + ext);
    auto sink = open_fap_sink(out, FapHeader{});
    for (long i = 0; i < 3; ++i) sink->write(jaw_frame(i, 1.0));
    sink->finish_as(partial);
    EXPECT_EQ(read_fap_stream(partial).frames.size(), 3u) << ext;
  }
  EXPECT_EQ(slurp(path), "previous take\n");
}

std::string error_of(const std::string& text, FapFormat format) {
  try {
    auto source = open_fap_source("in", text, format);
    FapFrame frame;
    while (source->next(frame)) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FapSafety, FapReaderRejectsNumbersThatWouldWrapAndQuotesTheirToken) {
  const std::string m3 = test::mask_line({3});
  const std::string m2 = test::mask_line({2});
  const std::string m35 = test::mask_line({3, 5});
  std::string e = error_of("2.1 n 25 1\n" + m3 + "\n0 99999999999999999999\n", FapFormat::Fap);
  EXPECT_NE(e.find("in:3:"), std::string::npos) << e;
  EXPECT_NE(e.find("'99999999999999999999'"), std::string::npos) << e;
  e = error_of("2.1 n 25 1\n" + m2 + "\n0 1 3000000000 0 0 0 0\n", FapFormat::Fap);
  EXPECT_NE(e.find("intensity1 of FAP 2"), std::string::npos) << e;
  EXPECT_NE(e.find("'3000000000'"), std::string::npos) << e;
  e = error_of("2.1 n 1e308 1\n" + m3 + "\n0 1\n", FapFormat::Fap);
  EXPECT_NE(e.find("in:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("'1e308'"), std::string::npos) << e;
  // The token quoted is the bad one, not its neighbour.
  e = error_of("2.1 n 25 1\n" + m35 + "\n0 0 nan\n", FapFormat::Fap);
  EXPECT_NE(e.find("is 'nan'"), std::string::npos) << e;
  EXPECT_NE(e.find("FAP 5"), std::string::npos) << e;
}

TEST(FapSafety, CsvAndJsonReadersRejectNumbersOutsideTheirMeaning) {
  auto sink_text = [](FapFormat format) {
    const auto dir = test::scratch_dir("fap-safety-text");
    const auto path = dir / (format == FapFormat::Csv ? "a.csv" : "a.json");
    FapStream stream;
    FapFrame f = jaw_frame(0, 5.0);
    ExpressionParams ex;
    ex.select1 = 1;
    ex.intensity1 = 63;
    f.set_expression(ex);
    stream.frames.push_back(f);
    write_fap_stream(path, stream);
    return slurp(path);
  };
  std::string csv = sink_text(FapFormat::Csv);
  ASSERT_EQ(error_of(csv, FapFormat::Csv), "");
  std::string bad = csv;
  bad.replace(bad.rfind(",63,"), 4, ",3000000000,");
  std::string e = error_of(bad, FapFormat::Csv);
  EXPECT_NE(e.find("'3000000000'"), std::string::npos) << e;
  bad = csv;
  bad.replace(bad.find("fps=25"), 6, "fps=1e308");
  e = error_of(bad, FapFormat::Csv);
  EXPECT_NE(e.find("fps '1e308'"), std::string::npos) << e;

  std::string json = sink_text(FapFormat::Json);
  ASSERT_EQ(error_of(json, FapFormat::Json), "");
  bad = json;
  bad.replace(bad.find("\"intensity1\":63"), 15, "\"intensity1\":3000000000");
  e = error_of(bad, FapFormat::Json);
  EXPECT_NE(e.find("'intensity1'"), std::string::npos) << e;
  EXPECT_NE(e.find("3000000000"), std::string::npos) << e;
  bad = json;
  bad.replace(bad.find("\"open_jaw\":5"), 12, "\"open_jaw\":\"wide\"");
  e = error_of(bad, FapFormat::Json);
  EXPECT_NE(e.find("'open_jaw' should be a number"), std::string::npos) << e;
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
  bad = json;
  bad.replace(bad.find("\"name\":\"rostro\""), 15, "\"name\":7");
  e = error_of(bad, FapFormat::Json);
  EXPECT_NE(e.find("in: 'name' should be a string, not 7"), std::string::npos) << e;
  // Found by fuzz_fap_json: a number too long for any type is an out_of_range while
  // parsing, not a parse_error, and was thrown past the reader.
  e = error_of(
      "{\"format\":\"rostro-fap\",\"fps\":25,\"frames\":[],\"x\":" + std::string(400, '1') + "}",
      FapFormat::Json);
  EXPECT_NE(e.find("in: the FAP stream is not valid JSON"), std::string::npos) << e;
}

}  // namespace
}  // namespace rostro
