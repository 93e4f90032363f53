#include <gtest/gtest.h>

#include <fstream>

#include "facecore/fap_io.hpp"
#include "fap_test_util.hpp"
#include "test_paths.hpp"

namespace rostro {
namespace {

TEST(FapFile, ReadsHeaderMaskAndValues) {
  const auto dir = test::scratch_dir("fapfile-read");
  const auto path =
      test::write_text(dir / "a.fap", "# a comment\n2.1 my_take 25 2\n" + test::mask_line({3, 48}) +
                                          "\n0 120 -500\n" + test::mask_line({1, 2, 19}) +
                                          "\n1 3 7 20 0 1 40 6 10 0 0 512\n");
  const FapStream s = read_fap_stream(path);
  EXPECT_EQ(s.header.version, "2.1");
  EXPECT_EQ(s.header.name, "my_take");
  EXPECT_DOUBLE_EQ(s.header.fps, 25);
  ASSERT_EQ(s.frames.size(), 2u);
  EXPECT_TRUE(s.frames[0].has(3));
  EXPECT_FALSE(s.frames[0].has(4));
  EXPECT_DOUBLE_EQ(s.frames[0].get(3), 120);
  EXPECT_DOUBLE_EQ(s.frames[0].get(48), -500);
  EXPECT_EQ(s.frames[1].index, 1);
  EXPECT_DOUBLE_EQ(s.frames[1].time_s, 1.0 / 25);
  EXPECT_EQ(s.frames[1].viseme, (VisemeParams{3, 7, 20, 0}));
  EXPECT_EQ(s.frames[1].expression, (ExpressionParams{1, 40, 6, 10, 0, 0}));
  EXPECT_DOUBLE_EQ(s.frames[1].get(19), 512);
}

// The 2004 Xface reader reads the values as a stream of numbers, FAP 1 and FAP 2 as one
// number each; files written for it are read alike.
TEST(FapFile, ReadsXfacesOneNumberHighLevelFapsAndWrappedValueLines) {
  const auto dir = test::scratch_dir("fapfile-xface");
  const auto path = test::write_text(
      dir / "x.fap", "2.1 Xface::FapFile 25 3\n" + test::mask_line({1, 2, 3}) + "\n0 4 2 120\n" +
                         test::mask_line({1, 3}) + "\n1 0 7 3 0 130\n" +
                         test::mask_line({3, 4, 5, 6}) + "\n2 10 20\n30\n 40\n");
  const FapStream s = read_fap_stream(path);
  ASSERT_EQ(s.frames.size(), 3u);
  EXPECT_EQ(s.frames[0].viseme, (VisemeParams{4, 0, 63, 0}));  // viseme 4 at full weight
  EXPECT_EQ(s.frames[0].expression, (ExpressionParams{2, 63, 0, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(s.frames[0].get(3), 120);
  EXPECT_EQ(s.frames[1].viseme, (VisemeParams{0, 7, 3, 0}));  // the standard's 4 fields
  EXPECT_DOUBLE_EQ(s.frames[1].get(3), 130);
  EXPECT_DOUBLE_EQ(s.frames[2].get(3), 10);  // one frame's values over three lines
  EXPECT_DOUBLE_EQ(s.frames[2].get(6), 40);

  // Neither form: the message names both counts.
  const auto bad = test::write_text(
      dir / "bad.fap", "2.1 x 25 1\n" + test::mask_line({1, 3}) + "\n0 1 2 120\n");
  const std::string e = test::read_error(bad);
  EXPECT_NE(e.find("expected 6"), std::string::npos) << e;
  EXPECT_NE(e.find("or 3 with FAP 1 and 2 as one number each"), std::string::npos) << e;
}

TEST(FapFile, TheWriterSaysWhenXfaceCannotReadTheFile) {
  const auto dir = test::scratch_dir("fapfile-xface-write");
  FapFrame plain;
  plain.set(3, 100);
  FapFrame high = plain;
  high.set_viseme({3, 0, 63, 0});
  const auto warning = [&](double fps, const FapFrame& frame) {
    FapHeader h;
    h.fps = fps;
    auto sink = open_fap_sink(dir / "w.fap", h);
    sink->write(frame);
    sink->finish();
    return sink->xface_warning();
  };
  EXPECT_EQ(warning(25, plain), "");
  EXPECT_NE(warning(29.97, plain).find("frame rate 29.97"), std::string::npos);
  EXPECT_NE(warning(30, high).find("FAP 1/2"), std::string::npos);
  // A whole rate is written as a whole number, as Xface reads it.
  std::ifstream in(dir / "w.fap");
  std::string version, name, fps;
  in >> version >> name >> fps;
  EXPECT_EQ(fps, "30");
}

TEST(FapFile, ToleratesCrlfTrailingSpacesCommentsAndPathNames) {
  const auto dir = test::scratch_dir("fapfile-tolerant");
  const auto path =
      test::write_text(dir / "b.fap", "2.1 C:\\Users\\x\\TempFile 30 1   \r\n#c\r\n\r\n" +
                                          test::mask_line({3}) + "  \r\n  0   42  \r\n");
  const FapStream s = read_fap_stream(path);
  EXPECT_EQ(s.header.name, "C:\\Users\\x\\TempFile");
  EXPECT_DOUBLE_EQ(s.header.fps, 30);
  ASSERT_EQ(s.frames.size(), 1u);
  EXPECT_DOUBLE_EQ(s.frames[0].get(3), 42);
}

TEST(FapFile, WriterQuantisesAndReadsBack) {
  const auto dir = test::scratch_dir("fapfile-write");
  FapStream s;
  s.header.name = "name with spaces";
  s.header.fps = 50;
  for (long i = 0; i < 3; ++i) {
    FapFrame f;
    f.index = i;
    f.time_s = static_cast<double>(i) / 50;
    f.set(3, 10.4 * static_cast<double>(i));
    f.set(60, -7.6);
    if (i == 1) f.set_viseme({1, 2, 30, 0});
    s.frames.push_back(f);
  }
  write_fap_stream(dir / "w.fap", s);
  const FapStream r = read_fap_stream(dir / "w.fap");
  EXPECT_EQ(r.header.name, "name_with_spaces");
  EXPECT_EQ(r.header.frame_count, 3);
  ASSERT_EQ(r.frames.size(), 3u);
  EXPECT_DOUBLE_EQ(r.frames[2].get(3), 21);  // 20.8 rounds to 21
  EXPECT_DOUBLE_EQ(r.frames[0].get(60), -8);
  EXPECT_EQ(r.frames[1].viseme, (VisemeParams{1, 2, 30, 0}));
  EXPECT_FALSE(r.frames[0].has(1));
}

TEST(FapFile, UnfinishedWriterLeavesNoFileAndKeepsTheOldOne) {
  const auto dir = test::scratch_dir("fapfile-atomic");
  const auto path = test::write_text(dir / "keep.fap", "old contents");
  {
    auto sink = open_fap_sink(path, FapHeader{});
    sink->write(FapFrame{});
    // destroyed without finish(): as if the process failed mid-write
  }
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "old contents");
  int files = 0;
  for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1) << "the temporary file must be removed";
}

TEST(FapFile, StreamingReaderHandsOutFramesOneByOne) {
  const auto dir = test::scratch_dir("fapfile-stream");
  std::string text = "2.1 s 25 100\n";
  for (int i = 0; i < 100; ++i)
    text += test::mask_line({5}) + "\n" + std::to_string(i) + " " + std::to_string(i * 2) + "\n";
  test::write_text(dir / "s.fap", text);
  auto source = open_fap_source(dir / "s.fap");
  FapFrame f;
  long n = 0;
  while (source->next(f)) {
    EXPECT_DOUBLE_EQ(f.get(5), 2.0 * static_cast<double>(n));
    ++n;
  }
  EXPECT_EQ(n, 100);
}

}  // namespace
}  // namespace rostro
