#include "facecore/fapu.hpp"

#include <cmath>

#include "facecore/error.hpp"

namespace rostro {

double Fapu::unit_size(FapUnit unit) const {
  switch (unit) {
    case FapUnit::MNS:
      return mns0 / 1024.0;
    case FapUnit::MW:
      return mw0 / 1024.0;
    case FapUnit::ES:
      return es0 / 1024.0;
    case FapUnit::ENS:
      return ens0 / 1024.0;
    case FapUnit::IRISD:
      return irisd0 / 1024.0;
    case FapUnit::AU:
      return kAngleUnitRad;
    case FapUnit::None:
      break;
  }
  return 0.0;
}

double Fapu::convert(double value, FapUnit from, FapUnit to) const {
  if (from == to) return value;
  const double to_size = unit_size(to);
  if (to_size == 0.0) return 0.0;
  return value * unit_size(from) / to_size;
}

Fapu fapu_from_feature_points(const FeaturePointPositions& points) {
  auto at = [&](int group, int index) -> const Eigen::Vector3d& {
    auto it = points.find({group, index});
    if (it == points.end())
      throw InputError("FAPU needs feature point " + std::to_string(group) + "." +
                       std::to_string(index) + ", which is not given");
    return it->second;
  };
  Fapu f;
  f.irisd0 = std::abs(at(3, 1).y() - at(3, 3).y());
  f.es0 = std::abs(at(3, 5).x() - at(3, 6).x());
  f.ens0 = std::abs(at(3, 5).y() - at(9, 15).y());
  f.mns0 = std::abs(at(9, 15).y() - at(2, 2).y());
  f.mw0 = std::abs(at(8, 3).x() - at(8, 4).x());
  return f;
}

std::string where(const std::string& path, long line, const std::string& what) {
  if (line <= 0) return path + ": " + what;
  return path + ":" + std::to_string(line) + ": " + what;
}

}  // namespace rostro
