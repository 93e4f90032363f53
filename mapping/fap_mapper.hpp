#pragma once
// One entry point for turning tracked frames into FAP frames: the Ceres fit or the seed's
// 2D method, followed (unless switched off) by the relationship hierarchy.

#include <memory>
#include <optional>
#include <string>

#include "calib/actor_profile.hpp"
#include "mapping/fap_solver.hpp"
#include "mapping/hierarchy.hpp"

namespace rostro::mapping {

enum class Method { Ceres, Seed2d };

// "ceres" or "seed2d"; throws InputError for anything else.
Method parse_method(const std::string& name);

struct MapperOptions {
  Method method = Method::Ceres;
  SolverOptions solver;
  std::optional<Hierarchy> hierarchy;  // unset: no hierarchy (--no-hierarchy)
};

class FapMapper {
 public:
  virtual ~FapMapper() = default;
  virtual FapFrame map(const tracking::TrackedFrame& frame) = 0;
  // The head pose of the last frame when the method estimates one.
  virtual std::optional<tracking::HeadPose> last_pose() const { return std::nullopt; }
};

std::unique_ptr<FapMapper> make_fap_mapper(const calib::ActorProfile& profile,
                                           const MapperOptions& options);

}  // namespace rostro::mapping
