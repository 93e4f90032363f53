// The layout file: a dot painted beside its feature point, and what is refused.

#include "tracking/layout.hpp"

#include <gtest/gtest.h>

#include <string>

#include "facecore/error.hpp"

namespace rostro::tracking {
namespace {

std::string with_marker(const std::string& marker) {
  return R"({"name": "t", "markers": [)" + marker + "]}";
}

TEST(Layout, ADotBesideItsPointKeepsThePointsPosition) {
  const MarkerLayout layout = parse_layout(
      with_marker(R"({"id": "lid", "type": "dot", "fp": "3.1", "position": [30, 42, -18],
                      "beside": [0, 3]})"),
      "t.json");
  ASSERT_EQ(layout.markers.size(), 1u);
  const MarkerSpec& lid = layout.markers[0];
  ASSERT_TRUE(lid.beside_mm);
  EXPECT_EQ(*lid.beside_mm, cv::Point2d(0, 3));
  EXPECT_EQ(lid.position_mm, cv::Point3d(30, 42, -18));
  EXPECT_FALSE(parse_layout(with_marker(R"({"id": "d", "type": "dot", "fp": "3.1",
                                            "position": [0, 0, 0]})"),
                            "t.json")
                   .markers[0]
                   .beside_mm);
}

TEST(Layout, BesideIsRefusedWhereItMeansNothing) {
  auto message = [](const std::string& marker) {
    try {
      parse_layout(with_marker(marker), "t.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(R"({"type": "apriltag", "family": "tag36h11", "tag_id": 0, "size_mm": 20,
                        "position": [0, 88, -12], "beside": [0, 3]})")
                .find("only a dot"),
            std::string::npos);
  EXPECT_NE(message(R"({"id": "d", "type": "dot", "fp": "3.1", "position": [0, 0, 0],
                        "beside": [3]})")
                .find("'beside' should be [x, y]"),
            std::string::npos);
  EXPECT_NE(message(R"({"id": "d", "type": "dot", "fp": "3.1", "position": [0, 0, 0],
                        "beside": [0, 25]})")
                .find("within 20 mm"),
            std::string::npos);
}

}  // namespace
}  // namespace rostro::tracking
