#include "soccer_vision/ssl/udp_sender.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <unistd.h>

#include <arpa/inet.h>
#include <net/if.h>
#include <netinet/in.h>
#include <sys/socket.h>

namespace soccer_vision::ssl {

namespace {

std::runtime_error socketError(const std::string& what, const std::string& address, int port) {
  return std::runtime_error("UDP sender to " + address + ":" + std::to_string(port) + ": " + what + ": " +
                            std::strerror(errno));
}

}  // namespace

UdpSender::UdpSender(const std::string& address, int port, const std::string& interface) {
  in_addr addr{};
  if (inet_pton(AF_INET, address.c_str(), &addr) != 1) {
    throw std::runtime_error("UDP sender: address '" + address + "' is not an IPv4 address");
  }
  if (port < 1 || port > 65535) {
    throw std::runtime_error("UDP sender: port " + std::to_string(port) + " outside 1..65535");
  }
  address_ = addr.s_addr;
  port_ = static_cast<std::uint16_t>(port);
  multicast_ = IN_MULTICAST(ntohl(addr.s_addr));
  unsigned interface_index = 0;
  if (!interface.empty()) {
    interface_index = if_nametoindex(interface.c_str());
    if (interface_index == 0) throw std::runtime_error("UDP sender: unknown interface '" + interface + "'");
  }
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw socketError("socket", address, port);
  if (multicast_) {
    // Multicast stays on the local network and reaches receivers on this host too.
    const unsigned char ttl = 1, loop = 1;
    ip_mreqn request{};
    request.imr_ifindex = static_cast<int>(interface_index);
    if (setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0 ||
        setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0 ||
        (interface_index != 0 &&
         setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_IF, &request, sizeof request) != 0)) {
      const std::runtime_error error = socketError("multicast options", address, port);
      close(fd_);
      throw error;
    }
  } else if (interface_index != 0) {
    if (setsockopt(fd_, SOL_SOCKET, SO_BINDTODEVICE, interface.c_str(),
                   static_cast<socklen_t>(interface.size())) != 0) {
      const std::runtime_error error = socketError("binding to interface " + interface, address, port);
      close(fd_);
      throw error;
    }
  }
}

UdpSender::~UdpSender() {
  if (fd_ >= 0) close(fd_);
}

bool UdpSender::send(const std::string& payload) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = address_;
  to.sin_port = htons(port_);
  const ssize_t sent =
      sendto(fd_, payload.data(), payload.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  if (sent == static_cast<ssize_t>(payload.size())) return true;
  last_error_ = sent < 0 ? std::strerror(errno) : "short send";
  return false;
}

}  // namespace soccer_vision::ssl
