#include "evaluate_report.h"

#include <cstdio>
#include <map>
#include <sstream>
#include <string>

namespace soccer_vision {

using nlohmann::json;

namespace {

// The paper's Table I columns (30 fps video) and Table II (frame step 4, R = 200 px).
struct PaperColumn {
  int step, side;
  double time_s;
  int detected, global, windows, failed;
  double failure, success;
};
constexpr PaperColumn kPaperTable1[] = {{3, 50, 20.15, 148, 7, 146, 5, 0.03, 0.97},
                                        {3, 100, 20.73, 149, 5, 147, 3, 0.02, 0.98},
                                        {3, 200, 21.49, 149, 5, 147, 3, 0.02, 0.98},
                                        {2, 200, 30.18, 221, 9, 219, 7, 0.03, 0.97},
                                        {4, 200, 15.4, 111, 6, 109, 4, 0.035, 0.97}};
const std::pair<const char*, const char*> kStages[] = {{"preprocessing", "Pretreatment (illumination)"},
                                                       {"classification", "Pixel classification"},
                                                       {"recognition_and_pose", "Recognition and pose"},
                                                       {"tracking", "Target tracking (+ next windows)"},
                                                       {"total", "Total"}};
const std::map<std::string, std::pair<double, double>> kPaperTable2 = {{"preprocessing", {17.3, 19.1}},
                                                                       {"classification", {96.4, 107.4}},
                                                                       {"recognition_and_pose", {15.0, 15.4}},
                                                                       {"tracking", {0.5, 0.6}},
                                                                       {"total", {130.2, 141.8}}};

std::string fmt(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

std::string percent(double v) { return fmt("%.3f %%", 100 * v); }

}  // namespace

void printScore(const json& j) {
  if (j.contains("measured")) {
    const json& m = j["measured"];
    std::string why;  // " (area 15, unpaired 8)": the rejected team regions found on the robots
    const json by_cause = m.value("identification_rejected_by_cause", json::object());
    for (const auto& [cause, n] : by_cause.items())
      why += (why.empty() ? " (" : ", ") + cause + " " + std::to_string(n.get<long long>());
    if (!why.empty()) why += ")";
    std::printf(
        "measured: %.3f %% of visible robots in their own frame (%lld of %lld); missed: %lld wrong id, %lld "
        "identification rejected%s, %lld nothing segmented\n",
        100 * m["rate"].get<double>(), m["measured"].get<long long>(), m["visible"].get<long long>(),
        m["wrong_id"].get<long long>(), m["identification_rejected"].get<long long>(), why.c_str(),
        m["nothing_segmented"].get<long long>());
  }
  const json& r = j["robots"];
  const json& b = j["ball"];
  const json& a = j["all"];
  std::printf(
      "robots: detection %.3f %%, precision %.3f %% (%lld of %lld matched, %lld false), position RMSE %.2f "
      "mm, "
      "heading RMSE %.2f deg\n",
      100 * r["detection_rate"].get<double>(), 100 * r["precision"].get<double>(),
      r["matched"].get<long long>(), r["truth"].get<long long>(), r["false_positives"].get<long long>(),
      r["position_rmse_mm"].get<double>(), r["heading_rmse_deg"].get<double>());
  std::printf(
      "ball:   detection %.3f %%, precision %.3f %% (%lld of %lld matched, %lld false), position RMSE %.2f "
      "mm\n",
      100 * b["detection_rate"].get<double>(), 100 * b["precision"].get<double>(),
      b["matched"].get<long long>(), b["truth"].get<long long>(), b["false_positives"].get<long long>(),
      b["position_rmse_mm"].get<double>());
  std::printf(
      "all:    detection %.3f %%, precision %.3f %%; identity switches %lld, identity errors %lld; "
      "%lld frames scored, %lld failed, %lld without truth\n",
      100 * a["detection_rate"].get<double>(), 100 * a["precision"].get<double>(),
      j["identity_switches"].get<long long>(), j["identity_errors"].get<long long>(),
      j["frames_scored"].get<long long>(), j["failed_frames"].get<long long>(),
      j["frames_without_truth"].get<long long>());
}

void printTable2(const json& with, const json& without) {
  std::printf("\nTable II: time per stage [ms, mean per processed frame]\n");
  std::printf("  %-36s %12s %12s %14s\n", "", "w/ windows", "w/o windows", "paper w/ | w/o");
  for (const auto& [key, label] : kStages) {
    const auto& paper = kPaperTable2.at(key);
    std::printf("  %-36s %12.3f %12.3f %7.1f | %5.1f\n", label, with[key]["mean_ms"].get<double>(),
                without[key]["mean_ms"].get<double>(), paper.first, paper.second);
  }
}

void printTable1(const json& rows) {
  std::printf(
      "\nTable I: frame step x window side (paper, 30 fps video: 3-50 3-100 3-200 2-200 4-200 -> success "
      "0.97 0.98 0.98 0.97 0.97)\n");
  std::printf("  %-10s %9s %9s %9s %9s %7s %9s %9s %10s %10s\n", "step-R", "time [s]", "processed", "global",
              "windows", "failed", "fail rate", "success", "detection", "pred. RMSE");
  for (const json& r : rows) {
    std::printf(
        "  %-10s %9.3f %9lld %9lld %9lld %7lld %9.4f %9.4f %9.3f%% %7.1f mm\n",
        (std::to_string(r["frame_step"].get<int>()) + "-" + std::to_string(r["window_side"].get<int>()))
            .c_str(),
        r["time_s"].get<double>(), r["processed_frames"].get<long long>(),
        r["global_search_frames"].get<long long>(), r["window_frames"].get<long long>(),
        r["failed_frames"].get<long long>(), r["failure_rate"].get<double>(), r["success_rate"].get<double>(),
        100 * r["robot_detection_rate"].get<double>(), r["prediction_rmse_mm"].get<double>());
  }
}

std::string markdownReport(const json& report, const std::string& title) {
  std::ostringstream md;
  md << "### " << title << "\n\n";
  md << report["images"].get<long long>() << " images of " << report["cameras"].get<int>() << " camera(s) at "
     << report["width"].get<int>() << "x" << report["height"].get<int>() << " "
     << report["encoding"].get<std::string>() << ", pattern " << report["pattern"].get<std::string>()
     << "; frame step " << report["frame_step"].get<int>()
     << ", windows R = " << report["window_side"].get<int>() << " px"
     << (report["search_windows"].get<bool>() ? "" : " (off)")
     << (report.value("online_calibration", false)
             ? "; online calibration (" + std::to_string(report.value("learned_cells", 0)) + " cells learned)"
             : "")
     << "; " << report["frames_processed"].get<long long>() << " frames processed ("
     << report["global_search_frames"].get<long long>() << " searched whole).\n\n";

  const json& r = report["robots"];
  const json& b = report["ball"];
  const json& a = report["all"];
  md << "| | robots | ball | all | paper (all) |\n|---|---|---|---|---|\n";
  md << "| detection rate | " << percent(r["detection_rate"]) << " | " << percent(b["detection_rate"])
     << " | " << percent(a["detection_rate"]) << " | 99.68 % |\n";
  md << "| precision | " << percent(r["precision"]) << " | " << percent(b["precision"]) << " | "
     << percent(a["precision"]) << " | 99.92 % |\n";
  md << "| position RMSE | " << fmt("%.2f mm", r["position_rmse_mm"]) << " | "
     << fmt("%.2f mm", b["position_rmse_mm"]) << " | | |\n";
  md << "| heading RMSE | " << fmt("%.2f°", r["heading_rmse_deg"]) << " | | | |\n";
  md << "| identity switches / errors | " << report["identity_switches"].get<long long>() << " / "
     << report["identity_errors"].get<long long>() << " | | | |\n";
  md << "| failed frames | | | " << report["failed_frames"].get<long long>() << " of "
     << report["frames_scored"].get<long long>() << " | |\n";
  md << "| speed (in-process, one core) | | | " << fmt("%.0f frames/s", report["frames_per_second"])
     << " | 7.7 frames/s (130 ms) |\n\n";

  if (report.contains("table2")) {
    const json& with = report["table2"]["with_windows"];
    const json& without = report["table2"]["without_windows"];
    md << "Table II, time per stage [ms per processed frame, mean (p99)]:\n\n";
    md << "| stage | w/ windows | w/o windows | paper w/ | paper w/o |\n|---|---|---|---|---|\n";
    for (const auto& [key, label] : kStages) {
      const auto& paper = kPaperTable2.at(key);
      md << "| " << label << " | " << fmt("%.3f", with[key]["mean_ms"]) << fmt(" (%.3f)", with[key]["p99_ms"])
         << " | " << fmt("%.3f", without[key]["mean_ms"]) << fmt(" (%.3f)", without[key]["p99_ms"]) << " | "
         << fmt("%.1f", paper.first) << " | " << fmt("%.1f", paper.second) << " |\n";
    }
    md << "\n";
  }
  if (report.contains("table1")) {
    md << "Table I, frame step × window side R (failed frame: any robot or ball in view missed, or a false "
          "positive):\n\n";
    md << "| step-R | time [ms/frame] | processed | global | windows | failed | failure rate | success rate "
          "| "
          "robot detection | prediction RMSE | paper time [ms/frame] | paper failure / success |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const json& row : report["table1"]) {
      const int step = row["frame_step"], side = row["window_side"];
      std::string paper_time, paper_rates;
      for (const PaperColumn& p : kPaperTable1) {
        if (p.step == step && p.side == side) {
          paper_time = fmt("%.0f", 1e3 * p.time_s / p.detected);
          paper_rates = fmt("%.3f", p.failure) + " / " + fmt("%.2f", p.success);
        }
      }
      const double processed = row["processed_frames"].get<double>();
      md << "| " << step << "-" << side << " | "
         << fmt("%.3f", processed > 0 ? 1e3 * row["time_s"].get<double>() / processed : 0.0) << " | "
         << row["processed_frames"].get<long long>() << " | " << row["global_search_frames"].get<long long>()
         << " | " << row["window_frames"].get<long long>() << " | " << row["failed_frames"].get<long long>()
         << " | " << fmt("%.4f", row["failure_rate"]) << " | " << fmt("%.4f", row["success_rate"]) << " | "
         << percent(row["robot_detection_rate"]) << " | " << fmt("%.1f mm", row["prediction_rmse_mm"])
         << " | " << paper_time << " | " << paper_rates << " |\n";
    }
    md << "\n";
  }
  return md.str();
}

}  // namespace soccer_vision
