// A plain-text table for the terminal (columns padded to their widest cell) and the number
// formats of the printed tables, shared by the CLI and the studies.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

namespace trackassoc::report {

class TextTable {
 public:
  explicit TextTable(std::vector<std::string> header) { rows_.push_back(std::move(header)); }
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  void print(std::ostream& os) const {
    std::vector<std::size_t> w;
    for (const auto& r : rows_) {
      w.resize(std::max(w.size(), r.size()), 0);
      for (std::size_t c = 0; c < r.size(); ++c) w[c] = std::max(w[c], r[c].size());
    }
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      for (std::size_t c = 0; c < rows_[i].size(); ++c)
        os << (c ? "  " : "") << rows_[i][c] << std::string(w[c] - rows_[i][c].size(), ' ');
      os << "\n";
      if (i == 0) {
        std::size_t total = 0;
        for (auto x : w) total += x + 2;
        os << std::string(total > 2 ? total - 2 : 0, '-') << "\n";
      }
    }
  }

 private:
  std::vector<std::vector<std::string>> rows_;
};

inline std::string fmt(double v, const char* f = "%.4g") {
  if (std::isnan(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
inline std::string percent(double v) { return fmt(100.0 * v, "%.1f %%"); }

}  // namespace trackassoc::report
