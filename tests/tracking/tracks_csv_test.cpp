#include "tracking/tracks_csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "facecore/error.hpp"

namespace fs = std::filesystem;
using rostro::InputError;
using rostro::tracking::MarkerObservation;
using rostro::tracking::read_tracks;
using rostro::tracking::TrackedFrame;
using rostro::tracking::TracksReader;
using rostro::tracking::TracksWriter;
using rostro::tracking::write_tracks;

namespace {

fs::path temp_path(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("rostro_tracks_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

fs::path write_text(const std::string& name, const std::string& text) {
  fs::path p = temp_path(name);
  std::ofstream(p) << text;
  return p;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<TrackedFrame> sample_frames() {
  std::vector<TrackedFrame> frames;
  for (long f = 0; f < 5; ++f) {
    TrackedFrame tf;
    tf.frame = f * 2;  // gaps are allowed (dropped frames)
    tf.time_s = static_cast<double>(tf.frame) / 29.97;
    tf.markers.push_back(
        {"brow_l_in", {4, 1}, {100.125 + 0.1 * static_cast<double>(f), 50.0 / 3}, true, 0.9});
    tf.markers.push_back(
        {"lip_top", {8, 1}, {321.5, 400.75 - static_cast<double>(f)}, f != 3, f == 3 ? 0 : 1.0});
    tf.markers.push_back({"tag36h11:3", {}, {640.0 + 1e-7, 12.0}, true, 0.5});
    frames.push_back(tf);
  }
  return frames;
}

// Returns the message of the InputError `fn` throws, or fails the test.
template <typename Fn>
std::string error_of(Fn fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return {};
}

}  // namespace

TEST(TracksCsv, RoundTripIsExact) {
  auto frames = sample_frames();
  fs::path p = temp_path("roundtrip.csv");
  write_tracks(p, frames);
  auto back = read_tracks(p);
  ASSERT_EQ(back.size(), frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(back[i].frame, frames[i].frame);
    EXPECT_EQ(back[i].time_s, frames[i].time_s);
    ASSERT_EQ(back[i].markers.size(), frames[i].markers.size());
    for (size_t m = 0; m < frames[i].markers.size(); ++m) {
      const MarkerObservation& a = frames[i].markers[m];
      const MarkerObservation& b = back[i].markers[m];
      EXPECT_EQ(a.marker, b.marker);
      EXPECT_EQ(a.feature_point, b.feature_point);
      EXPECT_EQ(a.position.x, b.position.x);
      EXPECT_EQ(a.position.y, b.position.y);
      EXPECT_EQ(a.valid, b.valid);
      EXPECT_EQ(a.quality, b.quality);
    }
  }
}

// The identification rides along as a comment line before its frame's rows, which readers
// that skip comments pass over.
TEST(TracksCsv, IdentificationIsACommentBeforeItsFrame) {
  auto frames = sample_frames();
  ASSERT_GE(frames.size(), 2u);
  frames[1].identification = "identified, 30/31 dots,\nresidual 0.2";
  fs::path p = temp_path("identification.csv");
  write_tracks(p, frames);
  std::ifstream in(p);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\n# identification: identified, 30/31 dots, residual 0.2\n" +
                      std::to_string(frames[1].frame) + ","),
            std::string::npos)
      << text;
  auto back = read_tracks(p);
  ASSERT_EQ(back.size(), frames.size());
  EXPECT_EQ(back[0].identification, "");
  EXPECT_EQ(back[1].identification, "identified, 30/31 dots, residual 0.2");
  EXPECT_EQ(back[1].markers.size(), frames[1].markers.size());
}

TEST(TracksCsv, HeaderAndOneRowPerMarkerPerFrame) {
  fs::path p = temp_path("rows.csv");
  write_tracks(p, sample_frames());
  std::string text = read_text(p);
  EXPECT_EQ(text.substr(0, text.find('\n')), "frame,time_s,marker,fp,x,y,valid,quality");
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 5 * 3);
  EXPECT_NE(text.find("\n0,0,brow_l_in,4.1,100.125,"), std::string::npos);
  EXPECT_NE(text.find(",tag36h11:3,,"), std::string::npos);  // no feature point: empty
}

TEST(TracksCsv, StreamsFramesOneAtATime) {
  fs::path p = temp_path("stream.csv");
  {
    TracksWriter w(p);
    for (const auto& f : sample_frames()) w.write(f);
    EXPECT_FALSE(fs::exists(p));  // nothing appears before finish()
    w.finish();
  }
  TracksReader r(p);
  TrackedFrame f;
  long count = 0, last = -1;
  while (r.next(f)) {
    EXPECT_GT(f.frame, last);
    EXPECT_EQ(f.markers.size(), 3u);
    last = f.frame;
    ++count;
  }
  EXPECT_EQ(count, 5);
  EXPECT_FALSE(r.next(f));
}

TEST(TracksCsv, UnfinishedWriterLeavesEarlierFileAlone) {
  fs::path p = write_text("keep.csv", "earlier contents\n");
  {
    TracksWriter w(p);
    w.write(sample_frames()[0]);
  }  // destroyed without finish()
  EXPECT_EQ(read_text(p), "earlier contents\n");
}

TEST(TracksCsv, InvalidRowsMayHaveEmptyPositions) {
  TrackedFrame tf;
  tf.markers.push_back({"lost", {2, 1}, {std::nan(""), std::nan("")}, false, 0});
  fs::path p = temp_path("nan.csv");
  write_tracks(p, {tf});
  EXPECT_NE(read_text(p).find("0,0,lost,2.1,,,0,0"), std::string::npos);
  auto back = read_tracks(p);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_TRUE(std::isnan(back[0].markers[0].position.x));
  EXPECT_FALSE(back[0].markers[0].valid);
}

TEST(TracksCsv, AcceptsCrlfAndBlankLines) {
  auto p = write_text("crlf.csv",
                      "frame,time_s,marker,fp,x,y,valid,quality\r\n"
                      "0,0,a,2.1,1,2,1,1\r\n\r\n1,0.04,a,2.1,1.5,2,1,0.5\r\n");
  auto frames = read_tracks(p);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_DOUBLE_EQ(frames[1].markers[0].position.x, 1.5);
}

struct BadCase {
  const char* name;
  const char* body;  // rows after the header
  long line;
  const char* fragment;
};

class TracksCsvBad : public testing::TestWithParam<BadCase> {};

TEST_P(TracksCsvBad, ThrowsWithFileAndLine) {
  const BadCase& c = GetParam();
  auto p = write_text(std::string(c.name) + ".csv",
                      std::string("frame,time_s,marker,fp,x,y,valid,quality\n") + c.body);
  std::string msg = error_of([&] { read_tracks(p); });
  EXPECT_NE(msg.find(p.string() + ":" + std::to_string(c.line) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find(c.fragment), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, TracksCsvBad,
    testing::Values(
        BadCase{"columns", "0,0,a,2.1,1,2,1,1\n0,0,b,2.1,1,2,1\n", 3, "expected 8 columns"},
        BadCase{"extra", "0,0,a,2.1,1,2,1,1,9\n", 2, "found 9"},
        BadCase{"number", "0,0,a,2.1,1x,2,1,1\n", 2, "'x' should be a finite number"},
        BadCase{"nan", "0,0,a,2.1,nan,2,1,1\n", 2, "'x' should be a finite number, got 'nan'"},
        BadCase{"frame", "zero,0,a,2.1,1,2,1,1\n", 2, "'frame' should be an integer"},
        BadCase{"fp", "0,0,a,12.9,1,2,1,1\n", 2, "unknown feature point '12.9'"},
        BadCase{"valid", "0,0,a,2.1,1,2,2,1\n", 2, "'valid' should be 0 or 1"},
        BadCase{"emptyvalid", "0,0,a,2.1,,,1,1\n", 2, "'x' should be a finite number"},
        BadCase{"order", "0,0,a,2.1,1,2,1,1\n2,0.1,a,2.1,1,2,1,1\n1,0.05,a,2.1,1,2,1,1\n", 4,
                "frame 1 comes after frame 2"},
        BadCase{"split", "0,0,a,2.1,1,2,1,1\n1,0.1,a,2.1,1,2,1,1\n0,0,b,2.1,1,2,1,1\n", 4,
                "frame 0 comes after frame 1"},
        BadCase{"dup", "0,0,a,2.1,1,2,1,1\n0,0,a,2.1,1,2,1,1\n", 3, "appears twice"},
        BadCase{"time", "0,0,a,2.1,1,2,1,1\n0,0.5,b,2.1,1,2,1,1\n", 3, "time_s differs"}),
    [](const testing::TestParamInfo<BadCase>& param) { return std::string(param.param.name); });

// A capture stopped by a bad row keeps every whole frame before it: the problem in the row
// after a frame is reported on the next call, not in place of that frame.
TEST(TracksCsv, WholeFramesBeforeABadRowAreHandedOut) {
  TracksReader reader("mem.csv",
                      "frame,time_s,marker,fp,x,y,valid,quality\n"
                      "0,0,a,2.1,1,2,1,1\n0,0,b,2.1,1,2,1,1\n"
                      "1,0.04,a,2.1,1,2,1,1\n1,0.04,b,2.1,1,2,1,1\n"
                      "2,0.08,a,2.1,x,2,1,1\n");
  TrackedFrame frame;
  ASSERT_TRUE(reader.next(frame));
  EXPECT_EQ(frame.markers.size(), 2u);
  ASSERT_TRUE(reader.next(frame));
  EXPECT_EQ(frame.frame, 1);
  EXPECT_EQ(frame.markers.size(), 2u);
  const std::string msg = error_of([&] { reader.next(frame); });
  EXPECT_NE(msg.find("mem.csv:6:"), std::string::npos) << msg;
  // A writer killed mid-row: the whole frames before the cut are all there.
  TracksReader cut("cut.csv",
                   "frame,time_s,marker,fp,x,y,valid,quality\n0,0,a,2.1,1,2,1,1\n1,0.04,a,2.");
  ASSERT_TRUE(cut.next(frame));
  EXPECT_EQ(frame.frame, 0);
  EXPECT_NE(error_of([&] { cut.next(frame); }).find("cut.csv:3:"), std::string::npos);
}

TEST(TracksCsv, BadHeaderNamesLineOne) {
  auto p = write_text("header.csv", "frame,time,marker\n0,0,a\n");
  std::string msg = error_of([&] { TracksReader r(p); });
  EXPECT_NE(msg.find(p.string() + ":1:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected the header"), std::string::npos) << msg;
}

TEST(TracksCsv, MissingFileIsAnInputError) {
  std::string msg = error_of([&] { TracksReader r(temp_path("does_not_exist.csv")); });
  EXPECT_NE(msg.find("cannot open"), std::string::npos) << msg;
}
