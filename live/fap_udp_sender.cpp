#include "live/fap_udp_sender.hpp"

#include <fmt/format.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include "facecore/error.hpp"

namespace rostro::live {

std::string fap_datagram(const FapFrame& frame, double fps) {
  std::string out = fmt::format("rostro-fap {:g} {:.6f}\n", fps, frame.time_s);
  for (int i = 0; i < kFapCount; ++i) {
    out += frame.mask.test(static_cast<std::size_t>(i)) ? '1' : '0';
    out += i + 1 < kFapCount ? ' ' : '\n';
  }
  out += std::to_string(frame.index);
  for (int id = 1; id <= kFapCount; ++id) {
    if (!frame.has(id)) continue;
    if (id == kVisemeFap) {
      const VisemeParams& v = frame.viseme;
      out += fmt::format(" {} {} {} {}", v.select1, v.select2, v.blend, v.def);
    } else if (id == kExpressionFap) {
      const ExpressionParams& e = frame.expression;
      out += fmt::format(" {} {} {} {} {} {}", e.select1, e.intensity1, e.select2, e.intensity2,
                         e.init_face, e.def);
    } else {
      out += fmt::format(" {}", std::lround(frame.get(id)));
    }
  }
  out += '\n';
  return out;
}

FapUdpSender::FapUdpSender(const std::string& host, int port, double fps)
    : host_(host), port_(port), fps_(fps) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const std::string where = host + ":" + std::to_string(port);
  if (port <= 0 || port > 65535)
    throw InputError("FAP UDP port " + std::to_string(port) + " is not in 1..65535");
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 ||
      found == nullptr)
    throw InputError("FAP UDP address " + where + " cannot be resolved");
  socket_ = ::socket(found->ai_family, found->ai_socktype, found->ai_protocol);
  if (socket_ < 0) {
    freeaddrinfo(found);
    throw InputError("FAP UDP socket for " + where + ": " + std::strerror(errno));
  }
  std::memcpy(&address_, found->ai_addr, found->ai_addrlen);
  address_length_ = found->ai_addrlen;
  freeaddrinfo(found);
}

FapUdpSender::~FapUdpSender() {
  if (socket_ >= 0) ::close(socket_);
}

void FapUdpSender::send(const FapFrame& frame) {
  datagram_ = fap_datagram(frame, fps_);
  if (::sendto(socket_, datagram_.data(), datagram_.size(), 0,
               reinterpret_cast<const sockaddr*>(&address_), address_length_) < 0)
    throw InputError("FAP UDP send to " + host_ + ":" + std::to_string(port_) +
                     " failed: " + std::strerror(errno));
}

}  // namespace rostro::live
