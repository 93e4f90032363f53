#include "live/vmc_sender.hpp"

#include <lo/lo.h>

#include <cmath>

#include "facecore/error.hpp"
#include "facecore/fapu.hpp"

namespace rostro::live {

struct VmcSender::Address {
  lo_address handle = nullptr;
  ~Address() {
    if (handle != nullptr) lo_address_free(handle);
  }
};

VmcSender::VmcSender(ArkitMapping mapping, const VmcOptions& options)
    : mapping_(std::move(mapping)), options_(options), address_(std::make_unique<Address>()) {
  if (options_.port <= 0 || options_.port > 65535)
    throw InputError("VMC port " + std::to_string(options_.port) + " is not in 1..65535");
  address_->handle = lo_address_new(options_.host.c_str(), std::to_string(options_.port).c_str());
  if (address_->handle == nullptr)
    throw InputError("VMC address " + options_.host + ":" + std::to_string(options_.port) +
                     " cannot be resolved");
}

VmcSender::~VmcSender() = default;

std::array<float, 4> head_quaternion(const FapFrame& frame) {
  // MPEG-4: pitch positive = head down, yaw positive = turn to the face's left, roll
  // positive = tilt to the face's right. Unity, the avatar facing +z: about x positive
  // tips the face down (the same), about y positive turns it to its right and about z
  // positive lifts its right side, tilting it to its left (both the opposite).
  const double pitch = frame.get(48) * kAngleUnitRad;
  const double yaw = -frame.get(49) * kAngleUnitRad;
  const double roll = -frame.get(50) * kAngleUnitRad;
  const double cx = std::cos(pitch / 2), sx = std::sin(pitch / 2);
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  const double cz = std::cos(roll / 2), sz = std::sin(roll / 2);
  // Unity's Euler order: z, then x, then y (q = qy * qx * qz).
  const double w = cy * cx * cz + sy * sx * sz;
  const double x = cy * sx * cz + sy * cx * sz;
  const double y = sy * cx * cz - cy * sx * sz;
  const double z = cy * cx * sz - sy * sx * cz;
  return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z),
          static_cast<float>(w)};
}

void VmcSender::send(const FapFrame& frame, double time_s) {
  mapping_.evaluate(frame, weights_);
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  const auto& rules = mapping_.rules();
  for (std::size_t i = 0; i < rules.size(); ++i) {
    lo_message m = lo_message_new();
    lo_message_add_string(
        m, (options_.pascal_case_names ? pascal_case(rules[i].name) : rules[i].name).c_str());
    lo_message_add_float(m, weights_[i]);
    lo_bundle_add_message(bundle, "/VMC/Ext/Blend/Val", m);
  }
  lo_bundle_add_message(bundle, "/VMC/Ext/Blend/Apply", lo_message_new());

  // The avatar stays where the receiver put it: the root at the origin, unrotated.
  lo_message root = lo_message_new();
  lo_message_add_string(root, "root");
  for (float v : {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f}) lo_message_add_float(root, v);
  lo_bundle_add_message(bundle, "/VMC/Ext/Root/Pos", root);

  const auto q = head_quaternion(frame);
  lo_message bone = lo_message_new();
  lo_message_add_string(bone, "Head");
  for (float v : {0.0f, options_.head_offset_y, 0.0f, q[0], q[1], q[2], q[3]})
    lo_message_add_float(bone, v);
  lo_bundle_add_message(bundle, "/VMC/Ext/Bone/Pos", bone);

  lo_message ok = lo_message_new();
  lo_message_add_int32(ok, 1);
  lo_bundle_add_message(bundle, "/VMC/Ext/OK", ok);
  lo_message t = lo_message_new();
  lo_message_add_float(t, static_cast<float>(time_s));
  lo_bundle_add_message(bundle, "/VMC/Ext/T", t);

  const int sent = lo_send_bundle(address_->handle, bundle);
  lo_bundle_free_recursive(bundle);
  if (sent < 0)
    throw InputError("VMC send to " + options_.host + ":" + std::to_string(options_.port) +
                     " failed: " + lo_address_errstr(address_->handle));
}

}  // namespace rostro::live
