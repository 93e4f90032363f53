// Image folders: natural name order, fps from the options, errors naming the folder/file.
#include "capture/image_folder_source.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "capture/open_source.hpp"
#include "facecore/error.hpp"
#include "test_dir.hpp"

namespace rostro::capture {
namespace {

// Writes an image whose grey level is `level`, so the order read back can be checked.
void write_grey(const std::filesystem::path& path, int level, cv::Size size = {32, 24}) {
  ASSERT_TRUE(cv::imwrite(path.string(), cv::Mat(size, CV_8UC3, cv::Scalar::all(level))));
}

TEST(NaturalOrder, NumbersCompareByValue) {
  EXPECT_TRUE(natural_less("frame2.png", "frame10.png"));
  EXPECT_FALSE(natural_less("frame10.png", "frame2.png"));
  EXPECT_TRUE(natural_less("frame0009.png", "frame0010.png"));
  EXPECT_TRUE(natural_less("a.png", "b.png"));
  EXPECT_TRUE(natural_less("take1_9.png", "take2_1.png"));
  EXPECT_FALSE(natural_less("x.png", "x.png"));
  // equal by value, different spelling: still a strict order
  EXPECT_NE(natural_less("img01.png", "img1.png"), natural_less("img1.png", "img01.png"));
}

TEST(ImageFolderSource, SortedByNameWithTimestampsFromFps) {
  testing::TestDir dir;
  // Written out of order, with names that sort wrongly as plain strings.
  write_grey(dir.path / "f10.png", 100);
  write_grey(dir.path / "f2.png", 20);
  write_grey(dir.path / "f1.png", 10);
  write_grey(dir.path / "f3.jpg", 30);
  std::ofstream(dir.path / "notes.txt") << "not an image";
  SourceOptions options;
  options.fps = 50;
  auto source = open_frame_source(dir.path.string(), options);
  EXPECT_EQ(source->frame_count(), 4);
  EXPECT_EQ(source->frame_size(), cv::Size(32, 24));
  EXPECT_DOUBLE_EQ(source->nominal_fps(), 50);
  const int expected_levels[] = {10, 20, 30, 100};
  for (int i = 0; i < 4; ++i) {
    auto frame = source->next();
    ASSERT_TRUE(frame) << "frame " << i;
    EXPECT_EQ(frame->sequence, i);
    EXPECT_DOUBLE_EQ(frame->timestamp_s, i / 50.0);
    EXPECT_NEAR(cv::mean(frame->image)[0], expected_levels[i], 2) << "frame " << i;
  }
  EXPECT_FALSE(source->next());
  EXPECT_EQ(source->stats().delivered, 4);
}

TEST(ImageFolderSource, DefaultRateIs25) {
  testing::TestDir dir;
  write_grey(dir.path / "a.png", 1);
  write_grey(dir.path / "b.png", 2);
  auto source = open_frame_source(dir.path.string());
  EXPECT_DOUBLE_EQ(source->nominal_fps(), 25);
  source->next();
  EXPECT_DOUBLE_EQ(source->next()->timestamp_s, 0.04);
}

TEST(ImageFolderSource, EmptyFolderIsNamed) {
  testing::TestDir dir;
  std::ofstream(dir.path / "readme.txt") << "no images here";
  try {
    open_frame_source(dir.path.string());
    FAIL() << "an empty folder opened";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(dir.path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("no images"), std::string::npos) << message;
  }
}

TEST(ImageFolderSource, UnreadableImageIsNamedAndEarlierFramesStayValid) {
  testing::TestDir dir;
  write_grey(dir.path / "0001.png", 50);
  std::ofstream(dir.path / "0002.png") << "this is not a png";
  auto source = open_frame_source(dir.path.string());
  auto first = source->next();
  ASSERT_TRUE(first);
  try {
    source->next();
    FAIL() << "a broken image was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0002.png"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(cv::mean(first->image)[0], 50, 1);
}

TEST(ImageFolderSource, FirstImageUnreadableFailsAtOpen) {
  testing::TestDir dir;
  std::ofstream(dir.path / "a.jpg") << "garbage";
  EXPECT_THROW(open_frame_source(dir.path.string()), InputError);
}

TEST(ImageFolderSource, SizeChangeIsNamed) {
  testing::TestDir dir;
  write_grey(dir.path / "a.png", 1, {32, 24});
  write_grey(dir.path / "b.png", 1, {16, 24});
  auto source = open_frame_source(dir.path.string());
  ASSERT_TRUE(source->next());
  try {
    source->next();
    FAIL() << "an image of another size was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.png"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rostro::capture
