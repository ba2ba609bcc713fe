// What one stage of an association cost (docs/design.md §4, the stages of every path): its wall
// time and the process's peak resident memory at its end. Every tensor path (the default sparse
// S-D, --sparse, and the dense --3d and --sd, whose partition is the whole problem) lists its
// stages in AssociationSummary::stages (engine/pipeline/associator.hpp), which `associate` prints.
#pragma once

#include <chrono>
#include <span>
#include <string>

namespace trackassoc {

// Wall time and memory of one stage.
struct StageReport {
  std::string name;
  double seconds = 0.0;
  double peak_rss_mib = 0.0;  // process peak resident set (getrusage) at the end of the stage
  double data_mib = 0.0;      // bytes held by the stage's output
};

// Peak resident set size of this process so far [MiB] (getrusage ru_maxrss).
double peak_rss_mib();

// The report of a stage that started at t0 and ends now (data_mib: what its output holds).
StageReport stage_since(std::string name, std::chrono::steady_clock::time_point t0, double data_mib = 0.0);

// Σ of the stages' seconds.
double total_seconds(std::span<const StageReport> stages);

}  // namespace trackassoc
