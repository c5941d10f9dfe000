// pathInsideDirectory: what ~calibrate may overwrite when asked to save a table.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "soccer_vision/common/path_inside_directory.h"

namespace sv = soccer_vision;
namespace fs = std::filesystem;

namespace {

class PathInsideDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("sv_path_inside_" + std::to_string(getpid()));
    fs::create_directories(root_ / "allowed" / "sub");
    fs::create_directories(root_ / "elsewhere");
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string allowed() const { return (root_ / "allowed").string(); }
  fs::path root_;
};

TEST_F(PathInsideDirectory, RelativeAndAbsolutePathsInsideAreAccepted) {
  EXPECT_EQ(sv::pathInsideDirectory(allowed(), "t.svct"), (root_ / "allowed" / "t.svct").string());
  EXPECT_EQ(sv::pathInsideDirectory(allowed() + "/", "sub/t.svct"),
            (root_ / "allowed" / "sub" / "t.svct").string());
  EXPECT_EQ(sv::pathInsideDirectory(allowed(), allowed() + "/sub/new/t.svct"),
            (root_ / "allowed" / "sub" / "new" / "t.svct").string());
}

TEST_F(PathInsideDirectory, ParentComponentsAndPathsElsewhereAreRefused) {
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), "../elsewhere/t.svct"), std::invalid_argument);
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), "sub/../t.svct"), std::invalid_argument);
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), (root_ / "elsewhere" / "t.svct").string()),
               std::invalid_argument);
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), "/etc/passwd"), std::invalid_argument);
  // A sibling whose name starts with the allowed one's is elsewhere too.
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), allowed() + "2/t.svct"), std::invalid_argument);
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), allowed()), std::invalid_argument);
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), ""), std::invalid_argument);
  EXPECT_THROW(sv::pathInsideDirectory("", "t.svct"), std::invalid_argument);
  try {
    sv::pathInsideDirectory(allowed(), "/etc/passwd");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("outside the allowed directory"), std::string::npos) << e.what();
  }
}

TEST_F(PathInsideDirectory, SymbolicLinksLeadingOutAreRefused) {
  fs::create_directory_symlink(root_ / "elsewhere", root_ / "allowed" / "link");
  EXPECT_THROW(sv::pathInsideDirectory(allowed(), "link/t.svct"), std::invalid_argument);
}

}  // namespace
