#include "mapping/fap_mapper.hpp"

#include "facecore/error.hpp"
#include "mapping/seed2d_mapper.hpp"

namespace rostro::mapping {
namespace {

class CeresMapper : public FapMapper {
 public:
  CeresMapper(const calib::ActorProfile& p, const MapperOptions& o)
      : solver_(p, o.solver), hierarchy_(o.hierarchy), fapu_(p.fapu) {}
  FapFrame map(const tracking::TrackedFrame& frame) override {
    FitResult r = solver_.fit(frame);
    if (r.ok)
      pose_ = r.pose;
    else
      pose_.reset();
    if (hierarchy_) apply_hierarchy(*hierarchy_, fapu_, r.faps);
    return r.faps;
  }
  std::optional<tracking::HeadPose> last_pose() const override { return pose_; }

 private:
  FapSolver solver_;
  std::optional<Hierarchy> hierarchy_;
  Fapu fapu_;
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
