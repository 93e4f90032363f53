#pragma once
// The raw FAP frame over UDP, one datagram per frame, for programs that speak MPEG-4 FAPs
// rather than blend shapes. The datagram is the frame as a .fap file holds it, after a tag
// line, so any .fap reader can parse it:
//   rostro-fap <fps> <time_s>\n<68 mask values>\n<frame number> <values...>\n

#include <sys/socket.h>

#include <string>

#include "facecore/fap_frame.hpp"

namespace rostro::live {

class FapUdpSender {
 public:
  // Throws InputError when the host cannot be resolved or no socket can be made.
  FapUdpSender(const std::string& host, int port, double fps);
  ~FapUdpSender();
  FapUdpSender(const FapUdpSender&) = delete;
  FapUdpSender& operator=(const FapUdpSender&) = delete;

  void send(const FapFrame& frame);

 private:
  int socket_ = -1;
  std::string host_;
  int port_;
  double fps_;
  std::string datagram_;
  sockaddr_storage address_{};
  socklen_t address_length_ = 0;
};

// The datagram's text, separated out so it is testable without a socket.
std::string fap_datagram(const FapFrame& frame, double fps);

}  // namespace rostro::live
