#pragma once
namespace trackassoc {
inline constexpr const char* kVersion = "0.1.0";
// Recorded in every output file's created_by attribute. No timestamp: outputs are bit-identical
// for the same seed (docs/design.md §7).
const char* created_by();
}  // namespace trackassoc
