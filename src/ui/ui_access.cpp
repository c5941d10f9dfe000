#include "soccer_vision/ui/ui_access.h"

#include <utility>

#include <arpa/inet.h>

namespace soccer_vision {

bool isLoopbackAddress(const std::string& address) {
  if (address == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, address.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, address.c_str(), &v6) == 1) {
    static const in6_addr loopback = IN6ADDR_LOOPBACK_INIT;
    for (int i = 0; i < 16; ++i)
      if (v6.s6_addr[i] != loopback.s6_addr[i]) return false;
    return true;
  }
  return false;  // 0.0.0.0, ::, a host name or an interface address: reachable from outside
}

UiAccess::UiAccess(std::string address, std::string token) : token_(std::move(token)) {
  if (token_.empty() && !isLoopbackAddress(address)) {
    changes_enabled_ = false;
    read_only_reason_ =
        "ui_address " + address + " is beyond loopback and no ui_token is set: changes are refused";
  }
}

bool UiAccess::mayChange(const std::string& token) const {
  if (!changes_enabled_) return false;
  if (token_.empty()) return true;
  // Constant time in the token's content: every byte is compared.
  unsigned char diff = token.size() == token_.size() ? 0 : 1;
  for (std::size_t i = 0; i < token_.size(); ++i)
    diff |= static_cast<unsigned char>(token_[i] ^ (i < token.size() ? token[i] : 0));
  return diff == 0;
}

}  // namespace soccer_vision
