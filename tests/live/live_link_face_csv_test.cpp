#include "live/live_link_face_csv.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "facecore/error.hpp"

namespace rostro::live {
namespace {

std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream in(row.substr(0, row.find('\n')));
  for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
  return out;
}

std::size_t column(const std::string& name) {
  const auto header = cells(LiveLinkFaceCsv::header());
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

TEST(LiveLinkFaceCsv, HeaderHasLiveLinkFacesSixtyThreeColumnsInItsOrder) {
  const auto header = cells(LiveLinkFaceCsv::header());
  ASSERT_EQ(header.size(), 63u);
  EXPECT_EQ(header[0], "Timecode");
  EXPECT_EQ(header[1], "BlendShapeCount");
  EXPECT_EQ(header[2], "EyeBlinkLeft");
  EXPECT_EQ(header[17], "JawRight");  // Live Link Face puts right before left here
  EXPECT_EQ(header[18], "JawLeft");
  EXPECT_EQ(header[53], "TongueOut");
  EXPECT_EQ(header[54], "HeadYaw");
  EXPECT_EQ(header[62], "RightEyeRoll");
}

TEST(LiveLinkFaceCsv, TimecodeCountsFramesWithinTheSecond) {
  EXPECT_EQ(LiveLinkFaceCsv::timecode(0, 25), "00:00:00:00.000");
  EXPECT_EQ(LiveLinkFaceCsv::timecode(61.2, 25), "00:01:01:05.000");
  EXPECT_EQ(LiveLinkFaceCsv::timecode(3725.0 + 0.5 / 30, 30), "01:02:05:00.500");
  // 29.97 fps counts at 30: frame 30 lands a little after second 1.
  EXPECT_EQ(LiveLinkFaceCsv::timecode(30 / 29.97, 29.97), "00:00:01:00.030");
}

TEST(LiveLinkFaceCsv, RowsCarryTheShapesAndTheHeadInRadians) {
  LiveLinkFaceCsv csv(ArkitMapping::load_default(), 25);
  FapFrame frame;
  frame.time_s = 0.08;
  frame.set(3, 350);     // open_jaw: half of jawOpen's full scale
  frame.set(49, 10000);  // head_yaw 0.1 rad to the face's left
  frame.set(25, -5000);  // pitch_l_eyeball: the left eye 0.05 rad up
  const auto row = cells(csv.row(frame));
  ASSERT_EQ(row.size(), 63u);
  EXPECT_EQ(row[0], "00:00:00:02.000");
  EXPECT_EQ(row[1], "61");
  EXPECT_NEAR(std::stod(row[column("JawOpen")]), 0.5, 1e-6);
  EXPECT_NEAR(std::stod(row[column("MouthSmileLeft")]), 0.0, 1e-6);
  EXPECT_NEAR(std::stod(row[column("HeadYaw")]), 0.1, 1e-6);
  EXPECT_NEAR(std::stod(row[column("HeadPitch")]), 0.0, 1e-6);
  EXPECT_NEAR(std::stod(row[column("LeftEyePitch")]), -0.05, 1e-6);
  EXPECT_GT(std::stod(row[column("EyeLookUpLeft")]), 0.1);
}

TEST(LiveLinkFaceCsv, ABadRateIsAnInputError) {
  EXPECT_THROW(LiveLinkFaceCsv(ArkitMapping::load_default(), 0), InputError);
}

}  // namespace
}  // namespace rostro::live
