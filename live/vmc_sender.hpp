#pragma once
// Sends FAP frames to VMC protocol receivers (VSeeFace, Warudo, ...) over OSC/UDP with liblo:
// per frame one OSC bundle holding every ARKit blend shape (/VMC/Ext/Blend/Val), the apply
// message, the root at the origin (/VMC/Ext/Root/Pos), the head bone (/VMC/Ext/Bone/Pos
// "Head" from FAPs 48-50), the loaded state and the time. One bundle per frame means a
// receiver never sees half a face.

#include <memory>
#include <string>
#include <vector>

#include "facecore/fap_frame.hpp"
#include "live/arkit_mapping.hpp"

namespace rostro::live {

struct VmcOptions {
  std::string host = "127.0.0.1";
  int port = 39539;  // VSeeFace's and Warudo's default VMC receiver port
  // The head bone's local position in the avatar rig (metres): VMC carries position and
  // rotation together; receivers expect a plausible neck-to-head offset, not zero.
  float head_offset_y = 0.06f;
  // Blend shape names as Apple writes them ("eyeBlinkLeft"), or PascalCase ("EyeBlinkLeft"),
  // the "perfect sync" clip names some VRM avatars and receivers expect instead.
  bool pascal_case_names = false;
};

class VmcSender {
 public:
  // Throws InputError when the address cannot be resolved.
  VmcSender(ArkitMapping mapping, const VmcOptions& options);
  ~VmcSender();
  VmcSender(const VmcSender&) = delete;
  VmcSender& operator=(const VmcSender&) = delete;

  // Sends one frame; `time_s` is the frame's capture time. Throws InputError when sending
  // fails (the network is gone), so a live session can stop cleanly.
  void send(const FapFrame& frame, double time_s);

 private:
  struct Address;
  ArkitMapping mapping_;
  VmcOptions options_;
  std::unique_ptr<Address> address_;
  std::vector<float> weights_;
};

// The head rotation of FAPs 48-50 (pitch down, yaw to the face's left, roll to the face's
// right, in 1e-5 rad) as a unit quaternion (x, y, z, w) in Unity's left-handed frame, which
// VMC uses: y up, the avatar facing +z, so +x is the avatar's right, and a positive angle
// turns clockwise looking along its axis. A turn to the actor's left is a turn to the
// avatar's left: a negative rotation about y.
std::array<float, 4> head_quaternion(const FapFrame& frame);

}  // namespace rostro::live
