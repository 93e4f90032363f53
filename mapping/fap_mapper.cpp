#include "mapping/fap_mapper.hpp"

#include <cmath>

#include "calib/actor_calibration.hpp"
#include "facecore/error.hpp"
#include "mapping/seed2d_mapper.hpp"

namespace rostro::mapping {
namespace {

class CeresMapper : public FapMapper {
 public:
  CeresMapper(const calib::ActorProfile& p, const MapperOptions& o)
      : profile_(p),
        options_(o.solver),
        solver_(std::make_unique<FapSolver>(p, o.solver)),
        hierarchy_(o.hierarchy) {}
  FapFrame map(const tracking::TrackedFrame& frame) override {
    FitResult r = solver_->fit(frame);
    if (r.ok)
      pose_ = r.pose;
    else
      pose_.reset();
    if (hierarchy_) apply_hierarchy(*hierarchy_, profile_.fapu, r.faps);
    recalibrate_if_focal_moved();
    return r.faps;
  }
  std::optional<tracking::HeadPose> last_pose() const override { return pose_; }

 private:
  // The solver refines a default focal length with the neutral shape adjusted to first order;
  // the calibration's own fit (pose and the prior's per-axis scale) moves with the focal
  // length too, and left alone that stops the estimate short (640 -> 914 px for a 1083 px
  // camera on exact tracks). Once the estimate has moved 2 % from the profile's, the profile
  // is recalibrated there and the fit restarts from it: on that clip 640 px reaches 1083 in
  // 16 recalibrations over the first two head sweeps, and a still head moves it not at all.
  void recalibrate_if_focal_moved() {
    if (!options_.refine_default_focal || !calib::is_default_intrinsics(profile_.camera)) return;
    const double f = solver_->focal_length();
    if (std::abs(std::log(f / profile_.camera.fx)) < 0.02) return;
    profile_ = calib::recalibrate_focal(profile_, f);
    // A fresh estimator: information gathered against the old shape would only slow it
    // (carrying it over stopped at 1028 px instead of 1083 on the exact-track clip).
    solver_ = std::make_unique<FapSolver>(profile_, options_);
  }

  calib::ActorProfile profile_;
  SolverOptions options_;
  std::unique_ptr<FapSolver> solver_;
  std::optional<Hierarchy> hierarchy_;
  std::optional<tracking::HeadPose> pose_;
};

class Seed2dAdapter : public FapMapper {
 public:
  Seed2dAdapter(const calib::ActorProfile& p, const MapperOptions& o)
      : mapper_(p), hierarchy_(o.hierarchy), fapu_(p.fapu_image) {}
  FapFrame map(const tracking::TrackedFrame& frame) override {
    FapFrame f = mapper_.map(frame);
    if (hierarchy_) apply_hierarchy(*hierarchy_, fapu_, f);
    return f;
  }

 private:
  Seed2dMapper mapper_;
  std::optional<Hierarchy> hierarchy_;
  Fapu fapu_;
};

}  // namespace

Method parse_method(const std::string& name) {
  if (name == "ceres") return Method::Ceres;
  if (name == "seed2d") return Method::Seed2d;
  throw InputError("unknown mapping method '" + name + "': expected ceres or seed2d");
}

std::unique_ptr<FapMapper> make_fap_mapper(const calib::ActorProfile& profile,
                                           const MapperOptions& options) {
  if (options.method == Method::Seed2d) return std::make_unique<Seed2dAdapter>(profile, options);
  MapperOptions o = options;
  if (o.hierarchy) o.solver.model.derived_rules = o.hierarchy->rules;
  return std::make_unique<CeresMapper>(profile, o);
}

}  // namespace rostro::mapping
