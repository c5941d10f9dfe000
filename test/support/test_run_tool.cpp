#include <gtest/gtest.h>

#include "support/run_tool.h"

namespace soccer_vision::test {

TEST(RunTool, KeepsStdoutAndStderrAndTheExitStatus) {
  const ToolRun run = runTool("/bin/sh", "-c 'echo out; echo err >&2; exit 3'");
  EXPECT_EQ(run.status, 3);
  EXPECT_EQ(run.output, "out\nerr\n");
}

TEST(RunTool, ReportsSuccessAsStatusZero) {
  const ToolRun run = runTool("/bin/echo", "two words");
  EXPECT_EQ(run.status, 0);
  EXPECT_EQ(run.output, "two words\n");
}

}  // namespace soccer_vision::test
