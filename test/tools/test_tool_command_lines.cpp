// Every tool's command line: --help exits 0 and shows the options; a malformed number and an
// unknown option end with status 2 and a message naming the option, before any work is done.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_tool.h"

namespace soccer_vision::test {

namespace {

struct Tool {
  std::string name, binary;
  std::string required;       // arguments that make the rest of the command line complete
  std::string number_option;  // an option taking a number; empty: the tool has none
  std::string listed;         // an option --help must list
};

const std::vector<Tool>& tools() {
  static const std::vector<Tool> all = {
      {"make_scenario", MAKE_SCENARIO_BIN, "--preset even_static --out /nonexistent/s.bag --frames 1",
       "--width", "--width"},
      {"calibrate_colors", CALIBRATE_COLORS_BIN, "--image a.png --samples s.yaml --out t.svct", "--v-margin",
       "--v-margin"},
      {"calibrate_field", CALIBRATE_FIELD_BIN, "--camera-info c.yaml --points p.yaml --out o.yaml",
       "--max-rms", "--corners"},
      {"calibrate_synthetic", CALIBRATE_SYNTHETIC_BIN, "--out /nonexistent/t.svct", "--camera", "--camera"},
      {"evaluate", EVALUATE_BIN, "--bag /nonexistent/s.bag", "--frame-step", "--frame-step"},
      {"bench", BENCH_BIN, "", "--frames", "--frames"},
      {"bench_pipeline", BENCH_PIPELINE_BIN, "", "--frames", "--frames"},
      {"demo_monitor", DEMO_MONITOR_BIN, "", "--duration", "--duration"},
      {"detect", DETECT_BIN, "--image /etc/passwd --colors /etc/passwd", "", "--overlay"},
      {"ssl_log_play", SSL_LOG_PLAY_BIN, "/etc/passwd --fast", "--speed", "--speed"},
      {"ssl_log_info", SSL_LOG_INFO_BIN, "/etc/passwd", "", "log"},
  };
  return all;
}

}  // namespace

TEST(ToolCommandLines, HelpExitsZeroAndListsTheOptions) {
  for (const Tool& t : tools()) {
    const ToolRun run = runTool(t.binary, "--help");
    EXPECT_EQ(run.status, 0) << t.name << ":\n" << run.output;
    EXPECT_NE(run.output.find(t.listed), std::string::npos) << t.name << ":\n" << run.output;
  }
}

TEST(ToolCommandLines, AMalformedNumberIsRefusedWithStatusTwoNamingTheOption) {
  for (const Tool& t : tools()) {
    if (t.number_option.empty()) continue;
    const ToolRun run = runTool(t.binary, t.required + " " + t.number_option + " 12abc");
    EXPECT_EQ(run.status, 2) << t.name << ":\n" << run.output;
    EXPECT_NE(run.output.find(t.number_option), std::string::npos) << t.name << ":\n" << run.output;
    EXPECT_NE(run.output.find(t.name + ": "), std::string::npos) << "one error style; " << t.name << ":\n"
                                                                 << run.output;
  }
}

TEST(ToolCommandLines, AnUnknownOptionIsRefusedWithStatusTwoNamingIt) {
  for (const Tool& t : tools()) {
    const ToolRun run = runTool(t.binary, t.required + " --no-such-option 3");
    EXPECT_EQ(run.status, 2) << t.name << ":\n" << run.output;
    EXPECT_NE(run.output.find("--no-such-option"), std::string::npos) << t.name << ":\n" << run.output;
  }
}

}  // namespace soccer_vision::test
