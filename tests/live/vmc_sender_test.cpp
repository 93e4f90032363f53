// A VMC receiver inside the test, on loopback: the sender's bundles arrive with one full
// set of messages per frame and values that follow the FAPs.

#include "live/vmc_sender.hpp"

#include <gtest/gtest.h>
#include <lo/lo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace rostro::live {
namespace {

struct Received {
  std::vector<std::string> paths;
  std::map<std::string, float> blend;  // last value per shape
  std::vector<float> bone;             // last head bone args
  int applies = 0;
};

int on_message(const char* path, const char* types, lo_arg** argv, int argc, lo_message,
               void* user) {
  auto* r = static_cast<Received*>(user);
  r->paths.emplace_back(path);
  const std::string p(path);
  if (p == "/VMC/Ext/Blend/Val" && argc == 2 && types[0] == 's' && types[1] == 'f')
    r->blend[&argv[0]->s] = argv[1]->f;
  if (p == "/VMC/Ext/Blend/Apply") ++r->applies;
  if (p == "/VMC/Ext/Bone/Pos" && argc == 8 && std::string(&argv[0]->s) == "Head") {
    r->bone.clear();
    for (int i = 1; i < 8; ++i) r->bone.push_back(argv[i]->f);
  }
  return 0;
}

class VmcLoopback : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = lo_server_new_with_proto(nullptr, LO_UDP, nullptr);  // any free port
    ASSERT_NE(server_, nullptr);
    lo_server_add_method(server_, nullptr, nullptr, on_message, &received_);
    port_ = lo_server_get_port(server_);
  }
  void TearDown() override { lo_server_free(server_); }
  // Receives until `frames` apply messages arrived or a generous deadline passed.
  void receive(int frames) {
    for (int tries = 0; tries < 200 && received_.applies < frames; ++tries)
      lo_server_recv_noblock(server_, 10);
  }

  lo_server server_ = nullptr;
  int port_ = 0;
  Received received_;
};

TEST_F(VmcLoopback, OneFullSetPerFrameFollowingTheFaps) {
  VmcOptions options;
  options.port = port_;
  VmcSender sender(ArkitMapping::load_default(), options);
  std::vector<float> jaw;
  for (int i = 0; i < 3; ++i) {
    FapFrame frame;
    frame.index = i;
    frame.set(3, 175.0 * (i + 1));  // open_jaw: 0.25, 0.5, 0.75 of full scale
    sender.send(frame, i / 25.0);
    const int before = received_.applies;
    receive(before + 1);
    ASSERT_EQ(received_.applies, before + 1) << "frame " << i << " did not arrive";
    jaw.push_back(received_.blend.at("jawOpen"));
  }
  EXPECT_NEAR(jaw[0], 0.25f, 1e-5);
  EXPECT_NEAR(jaw[1], 0.50f, 1e-5);
  EXPECT_NEAR(jaw[2], 0.75f, 1e-5);
  EXPECT_EQ(received_.blend.size(), 52u);
  int vals = 0, bones = 0, oks = 0, times = 0;
  for (const auto& p : received_.paths) {
    vals += p == "/VMC/Ext/Blend/Val";
    bones += p == "/VMC/Ext/Bone/Pos";
    oks += p == "/VMC/Ext/OK";
    times += p == "/VMC/Ext/T";
  }
  EXPECT_EQ(vals, 3 * 52);
  EXPECT_EQ(bones, 3);
  EXPECT_EQ(oks, 3);
  EXPECT_EQ(times, 3);
}

TEST_F(VmcLoopback, HeadBoneCarriesTheYaw) {
  VmcOptions options;
  options.port = port_;
  VmcSender sender(ArkitMapping::load_default(), options);
  FapFrame frame;
  frame.set(49, 20000);  // head_yaw 0.2 rad, to the actor's left
  sender.send(frame, 0);
  receive(1);
  ASSERT_EQ(received_.bone.size(), 7u);
  // Quaternion about y by -0.2 rad (Unity: negative is a turn to the avatar's left).
  EXPECT_NEAR(received_.bone[3], 0.0f, 1e-6);
  EXPECT_NEAR(received_.bone[4], -std::sin(0.1f), 1e-6);
  EXPECT_NEAR(received_.bone[5], 0.0f, 1e-6);
  EXPECT_NEAR(received_.bone[6], std::cos(0.1f), 1e-6);
}

TEST_F(VmcLoopback, PerfectSyncNamesAndTheRoot) {
  VmcOptions options;
  options.port = port_;
  options.pascal_case_names = true;
  VmcSender sender(ArkitMapping::load_default(), options);
  FapFrame frame;
  frame.set(3, 350);
  sender.send(frame, 0);
  receive(1);
  EXPECT_NEAR(received_.blend.at("JawOpen"), 0.5f, 1e-5);
  EXPECT_EQ(received_.blend.count("jawOpen"), 0u);
  EXPECT_EQ(received_.blend.size(), 52u);
  EXPECT_EQ(std::count(received_.paths.begin(), received_.paths.end(), "/VMC/Ext/Root/Pos"), 1);
}

// v rotated by the unit quaternion q = (x, y, z, w): the same formula in either handedness.
std::array<double, 3> rotate(const std::array<float, 4>& q, std::array<double, 3> v) {
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  const double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                          {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                          {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  std::array<double, 3> r{};
  for (int i = 0; i < 3; ++i) r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  return r;
}

// Unity, as VMC receivers use it: y up, the avatar facing +z, its right at +x.
TEST(HeadQuaternion, TheActorsTurnsArriveAsTheAvatarsTurns) {
  constexpr std::array<double, 3> kForward{0, 0, 1}, kRight{1, 0, 0};
  FapFrame turn;
  turn.set(49, 30000);  // head_yaw positive: a turn to the actor's left
  EXPECT_LT(rotate(head_quaternion(turn), kForward)[0], -0.25);  // the avatar looks left
  FapFrame nod;
  nod.set(48, 30000);  // head_pitch positive: the head down
  EXPECT_LT(rotate(head_quaternion(nod), kForward)[1], -0.25);  // the avatar looks down
  FapFrame tilt;
  tilt.set(50, 30000);  // head_roll positive: a tilt to the actor's right
  EXPECT_LT(rotate(head_quaternion(tilt), kRight)[1], -0.25);  // the avatar's right ear drops
}

TEST(HeadQuaternion, IsUnitForAnyPose) {
  FapFrame frame;
  frame.set(48, 12000);
  frame.set(49, -30000);
  frame.set(50, 7000);
  const auto q = head_quaternion(frame);
  EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, 1e-6);
}

}  // namespace
}  // namespace rostro::live
