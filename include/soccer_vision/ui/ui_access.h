// Who may change the running system through the calibration UI. Reading (live view,
// status) is open to whoever reaches the port; changes (freeze, calibrate, save) need the
// token when one is set, and are refused altogether when the server listens beyond loopback
// without a token: a competition network is never open to changes by default.
#pragma once

#include <string>

namespace soccer_vision {

// 127.0.0.0/8, ::1 and "localhost".
bool isLoopbackAddress(const std::string& address);

class UiAccess {
 public:
  UiAccess(std::string address, std::string token);

  // False when bound beyond loopback without a token (read-only server).
  bool changesEnabled() const { return changes_enabled_; }
  bool tokenRequired() const { return !token_.empty(); }
  // Why changes are refused ("" when they are enabled).
  const std::string& readOnlyReason() const { return read_only_reason_; }
  // True when a change presenting `token` may go ahead (compared in constant time).
  bool mayChange(const std::string& token) const;

 private:
  std::string token_;
  bool changes_enabled_ = true;
  std::string read_only_reason_;
};

}  // namespace soccer_vision
