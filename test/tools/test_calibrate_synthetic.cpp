// calibrate_synthetic as demo.launch runs it: with --remove-on-exit the table is written (and
// loads), the tool stays until roslaunch's SIGINT, then removes it and exits 0: the demo's
// start-up tables leave nothing behind in /tmp.
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <signal.h>
#include <spawn.h>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "soccer_vision/segmentation/color_table.h"

using namespace soccer_vision;
namespace fs = std::filesystem;

namespace {

// Waits up to `seconds` for the child to end; its exit status, or -1 while it runs on.
int waitForExit(pid_t pid, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  do {
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  } while (std::chrono::steady_clock::now() < until);
  return -1;
}

}  // namespace

TEST(CalibrateSynthetic, RemoveOnExitKeepsTheTableUntilTheLaunchEndsThenRemovesIt) {
  const fs::path dir = fs::path(::testing::TempDir()) / "calibrate_synthetic_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string prefix = (dir / "tables").string();
  const fs::path table = prefix + "_0.svct";

  const char* argv[] = {
      CALIBRATE_SYNTHETIC_BIN, "--out", prefix.c_str(), "--cameras", "1", "--width", "320", "--height", "256",
      "--remove-on-exit",      nullptr};
  pid_t pid = 0;
  ASSERT_EQ(::posix_spawn(&pid, CALIBRATE_SYNTHETIC_BIN, nullptr, nullptr, const_cast<char**>(argv), environ),
            0);

  const auto until = std::chrono::steady_clock::now() + std::chrono::minutes(3);
  while (!fs::exists(table) && std::chrono::steady_clock::now() < until && waitForExit(pid, 0.1) == -1) {
  }
  ASSERT_TRUE(fs::exists(table)) << "no table written";
  EXPECT_NO_THROW(ColorTable::load(table.string()));

  // Written, it waits for the launch's end rather than exiting.
  EXPECT_EQ(waitForExit(pid, 0.5), -1);
  EXPECT_TRUE(fs::exists(table));

  ::kill(pid, SIGINT);
  EXPECT_EQ(waitForExit(pid, 30.0), 0);
  EXPECT_FALSE(fs::exists(table));
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing else (no .partial) is left";
  fs::remove_all(dir);
}
