// Runs a program as a user would from a shell and keeps what it printed: the tools' tests
// check exit statuses and messages.
#pragma once

#include <array>
#include <cstdio>
#include <string>

#include <sys/wait.h>

namespace soccer_vision::test {

struct ToolRun {
  int status = -1;     // exit status; -1 when the program did not exit normally
  std::string output;  // stdout and stderr, interleaved as printed
};

// `program args` through /bin/sh (args are shell words: quote what needs quoting).
inline ToolRun runTool(const std::string& program, const std::string& args) {
  const std::string command = program + " " + args + " 2>&1";
  ToolRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe)) run.output += buffer.data();
  const int status = ::pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

}  // namespace soccer_vision::test
