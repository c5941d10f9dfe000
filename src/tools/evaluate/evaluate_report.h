// The evaluate tool's report, from its JSON (the same object --json writes): the text
// printed to the terminal and the Markdown section docs/evaluation.md is made of, each
// beside the paper's figures. Keys: see evaluate.cpp (scoreJson, stageJson, runSummary).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace soccer_vision {

void printScore(const nlohmann::json& report);
void printTable2(const nlohmann::json& with_windows, const nlohmann::json& without_windows);
void printTable1(const nlohmann::json& rows);

// Accuracy, speed, Table II and (when swept) Table I as Markdown tables with the paper's
// numbers beside ours, under a heading `title`.
std::string markdownReport(const nlohmann::json& report, const std::string& title);

}  // namespace soccer_vision
