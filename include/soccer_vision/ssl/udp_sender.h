// Sends datagrams to one IPv4 address and port with a plain POSIX socket. For a multicast
// address (224.0.0.0/4, e.g. the league's 224.5.23.2) the packets leave through the named
// interface (or the system's default) with a TTL of 1 and loop back to this host.
#pragma once

#include <cstdint>
#include <string>

namespace soccer_vision::ssl {

class UdpSender {
 public:
  // Throws std::runtime_error naming the address, the port or the interface when one is invalid
  // (not an IPv4 address, port outside 1..65535, unknown interface) or the socket cannot be made.
  UdpSender(const std::string& address, int port, const std::string& interface = "");
  ~UdpSender();
  UdpSender(const UdpSender&) = delete;
  UdpSender& operator=(const UdpSender&) = delete;

  // One datagram; false on failure, with the reason in lastError().
  bool send(const std::string& payload);
  const std::string& lastError() const { return last_error_; }
  bool multicast() const { return multicast_; }

 private:
  int fd_ = -1;
  std::uint32_t address_ = 0;  // network byte order
  std::uint16_t port_ = 0;     // host byte order
  bool multicast_ = false;
  std::string last_error_;
};

}  // namespace soccer_vision::ssl
