// A UDP receiver on 127.0.0.1 at a port the kernel picks: the tests of what we send (the
// SSL sender, ssl_log_play) read the datagrams back from it, never from the network.
#pragma once

#include <cstddef>
#include <poll.h>
#include <string>
#include <unistd.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

namespace soccer_vision::test {

struct LoopbackReceiver {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  int port = 0;
  LoopbackReceiver() {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
  }
  ~LoopbackReceiver() { close(fd); }
  LoopbackReceiver(const LoopbackReceiver&) = delete;
  LoopbackReceiver& operator=(const LoopbackReceiver&) = delete;

  // The next datagram, or a text saying why there is none (nothing within 2 s, an error).
  std::string receive() {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 2000) != 1) return "(nothing within 2 s)";
    char buffer[65536];
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    return n < 0 ? "(error)" : std::string(buffer, static_cast<std::size_t>(n));
  }
};

}  // namespace soccer_vision::test
