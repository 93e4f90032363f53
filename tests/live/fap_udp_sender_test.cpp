#include "live/fap_udp_sender.hpp"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"

namespace rostro::live {
namespace {

FapFrame sample_frame() {
  FapFrame f;
  f.index = 7;
  f.time_s = 0.28;
  f.set(3, 120);
  f.set(60, -33);
  f.set_viseme({1, 4, 20, 0});
  return f;
}

TEST(FapDatagram, BodyIsAFapFrameThatAFapReaderParses) {
  const std::string datagram = fap_datagram(sample_frame(), 25);
  const auto newline = datagram.find('\n');
  EXPECT_EQ(datagram.substr(0, newline), "rostro-fap 25 0.280000");
  // The rest, behind a .fap header, reads back as the same frame.
  const auto path = std::filesystem::temp_directory_path() / "rostro-datagram.fap";
  std::ofstream(path) << "2.1 live 25 1\n" << datagram.substr(newline + 1);
  const FapStream s = read_fap_stream(path);
  ASSERT_EQ(s.frames.size(), 1u);
  EXPECT_EQ(s.frames[0].index, 7);
  EXPECT_EQ(s.frames[0].get(3), 120);
  EXPECT_EQ(s.frames[0].get(60), -33);
  EXPECT_EQ(s.frames[0].viseme, (VisemeParams{1, 4, 20, 0}));
}

TEST(FapUdpSender, DatagramArrivesOnLoopback) {
  const int receiver = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(receiver, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  ASSERT_EQ(::bind(receiver, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  ::getsockname(receiver, reinterpret_cast<sockaddr*>(&address), &length);
  timeval timeout{2, 0};
  ::setsockopt(receiver, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

  FapUdpSender sender("127.0.0.1", ntohs(address.sin_port), 25);
  sender.send(sample_frame());
  char buffer[4096];
  const auto received = ::recv(receiver, buffer, sizeof buffer, 0);
  ::close(receiver);
  ASSERT_GT(received, 0);
  EXPECT_EQ(std::string(buffer, static_cast<std::size_t>(received)),
            fap_datagram(sample_frame(), 25));
}

TEST(FapUdpSender, BadAddressIsAnInputError) {
  EXPECT_THROW(FapUdpSender("no-such-host.invalid", 9000, 25), InputError);
  EXPECT_THROW(FapUdpSender("127.0.0.1", 70000, 25), InputError);
}

}  // namespace
}  // namespace rostro::live
