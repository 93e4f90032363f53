#include "calib/generic_face.hpp"

#include <utility>

namespace rostro::calib {
namespace {

struct Entry {
  int group, index;
  double x, y, z;
};

// Points on the face's left (positive x); each is mirrored (x -> -x) to its twin on the
// right by the table below, mid-line points are listed once.
constexpr Entry kLeftAndMiddle[] = {
    // group 2: chin and inner lips (closed mouth: inner contours meet at y = -66)
    {2, 1, 0, -110, 5},
    {2, 2, 0, -66, 12},
    {2, 3, 0, -66, 12},
    {2, 4, 23, -66, 4},
    {2, 6, 12, -65.5, 10},
    {2, 8, 12, -66.5, 10},
    {2, 10, 0, -96, 12},
    {2, 11, 15, -101, 6},
    {2, 13, 60, -75, -50},
    // group 3: eyes
    {3, 1, 31.5, 5, 1},
    {3, 3, 31.5, -5, 1},
    {3, 5, 31.5, 0, 0},
    {3, 7, 45, 0, -8},
    {3, 9, 31.5, -8, -1},
    {3, 11, 17, 0, -4},
    {3, 13, 31.5, 9, -1},
    // group 4: eyebrows
    {4, 1, 15, 17, 3},
    {4, 3, 32, 22, 0},
    {4, 5, 48, 17, -10},
    // group 5: cheeks
    {5, 1, 42, -48, -6},
    {5, 3, 50, -22, -12},
    // group 6: tongue (inside the closed mouth)
    {6, 1, 0, -67, 0},
    {6, 2, 0, -68, -20},
    {6, 3, 12, -68, -15},
    // group 7: centre of head rotation
    {7, 1, 0, -70, -90},
    // group 8: outer lips
    {8, 1, 0, -58, 16},
    {8, 2, 0, -75, 14},
    {8, 3, 25, -66, 4},
    {8, 5, 13, -60, 13},
    {8, 7, 13, -72, 11},
    {8, 10, 5, -57, 15.5},
    // group 9: nose and teeth
    {9, 1, 16, -42, 6},
    {9, 3, 0, -35, 22},
    {9, 5, 9, -45, 10},
    {9, 7, 8, 0, 4},
    {9, 8, 0, -60, 8},
    {9, 9, 0, -75, 6},
    {9, 10, 0, -67, 8},
    {9, 11, 0, -67, 7},
    {9, 12, 0, -15, 14},
    {9, 13, 6, -15, 10},
    {9, 15, 0, -45, 14},
    // group 10: ears
    {10, 1, 72, 5, -85},
    {10, 3, 78, -15, -100},
    {10, 5, 70, -45, -85},
    {10, 7, 68, -40, -80},
    {10, 9, 68, 0, -75},
    // group 11: hairline and skull
    {11, 1, 0, 70, -5},
    {11, 3, 45, 55, -25},
    {11, 4, 0, 105, -80},
    {11, 5, 0, 112, -80},
    {11, 6, 0, 20, -180},
};

FeaturePointPositions build() {
  FeaturePointPositions points;
  for (const Entry& e : kLeftAndMiddle) {
    const FeaturePointId id{e.group, e.index};
    points[id] = Eigen::Vector3d(e.x, e.y, e.z);
    const FeaturePointId twin = mirror(id);
    if (twin != id) points[twin] = Eigen::Vector3d(-e.x, e.y, e.z);
  }
  return points;
}

}  // namespace

const FeaturePointPositions& generic_face_points() {
  static const FeaturePointPositions points = build();
  return points;
}

}  // namespace rostro::calib
