// writeFileAtomically: the bytes land at the path, replacing what was there, with no
// temporary file left; a path that cannot be written throws naming it and leaves nothing.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "soccer_vision/common/atomic_file.h"
#include "soccer_vision/common/exchange_formats.h"

using namespace soccer_vision;
namespace fs = std::filesystem;

namespace {

fs::path scratchDirectory() {
  char pattern[] = "/tmp/soccer_vision_atomic_file_XXXXXX";
  const char* dir = mkdtemp(pattern);
  EXPECT_NE(dir, nullptr);
  return dir ? fs::path(dir) : fs::path("/tmp");
}

std::size_t filesIn(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

}  // namespace

TEST(AtomicFile, ReplacesTheFileWholeAndLeavesNoTemporary) {
  const fs::path dir = scratchDirectory();
  const std::string path = (dir / "table.svct").string();
  const std::string first(100000, 'a'), second = "second, shorter\n";
  writeFileAtomically(path, first.data(), first.size());
  EXPECT_EQ(readTextFile(path), first);
  writeFileAtomically(path, second.data(), second.size());
  EXPECT_EQ(readTextFile(path), second) << "replaced, not overwritten in place";
  writeTextFile(path, "text");  // the text files go the same way
  EXPECT_EQ(readTextFile(path), "text");
  EXPECT_EQ(filesIn(dir), 1u) << "a temporary file was left";
  fs::remove_all(dir);
}

TEST(AtomicFile, AnUnwritablePathThrowsNamingItAndKeepsTheOldFile) {
  const fs::path dir = scratchDirectory();
  const std::string missing = (dir / "no_such_directory" / "t.svct").string();
  try {
    writeFileAtomically(missing, "x", 1);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  // A directory where the file should go: the rename fails, the directory stays, no
  // temporary file is left beside it.
  const fs::path occupied = dir / "occupied";
  fs::create_directory(occupied);
  fs::path inside = occupied / "keep";
  std::ofstream(inside) << "kept";
  EXPECT_THROW(writeFileAtomically(occupied.string(), "x", 1), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(occupied));
  EXPECT_EQ(readTextFile(inside.string()), "kept");
  EXPECT_EQ(filesIn(dir), 1u);
  fs::remove_all(dir);
}
