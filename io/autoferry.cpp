// Autoferry benchmark reader (see autoferry.hpp).
#include "io/autoferry.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "io/json_input.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using nlohmann::json;

std::string where(const std::string& source, std::size_t entry, const std::string& field) {
  return source + ": entry " + std::to_string(entry) + ", field '" + field + "'";
}

double finite_number(const json& v, const std::string& at) {
  if (!v.is_number()) throw InputError(at + ": expected a number, found " + std::string(v.type_name()));
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw InputError(at + ": expected a finite number");
  return d;
}

const json& field(const json& obj, const char* name, const std::string& source, std::size_t entry) {
  if (!obj.is_object())
    throw InputError(source + ": entry " + std::to_string(entry) + ": expected an object");
  auto it = obj.find(name);
  if (it == obj.end()) throw InputError(where(source, entry, name) + ": missing");
  return *it;
}

std::vector<double> number_row(const json& row, const std::string& at) {
  if (!row.is_array()) throw InputError(at + ": expected an array of numbers");
  std::vector<double> out;
  out.reserve(row.size());
  for (std::size_t k = 0; k < row.size(); ++k)
    out.push_back(finite_number(row[k], at + "[" + std::to_string(k) + "]"));
  return out;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::string autoferry_scenario_dir(const std::string& root, int number) {
  return root + "/scenario" + std::to_string(number);
}

std::vector<AutoferryScan> parse_autoferry_detections(const std::string& text, const std::string& source,
                                                      double& t0_unix) {
  const json doc = parse_json_input(text, source);
  if (!doc.is_array() || doc.empty())
    throw InputError(source + ": expected a non-empty array of detection entries");
  std::vector<AutoferryScan> scans;
  scans.reserve(doc.size());
  std::map<int32_t, double> last_time;
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const json& e = doc[i];
    AutoferryScan s;
    const double id = finite_number(field(e, "sensorID", source, i), where(source, i, "sensorID"));
    if (!(id == 1 || id == 2 || id == 3 || id == 4))
      throw InputError(where(source, i, "sensorID") +
                       ": expected 1 (lidar), 2 (radar), 3 (IR) or 4 (EO), found " +
                       field(e, "sensorID", source, i).dump());
    s.sensor = static_cast<int32_t>(id);
    const double t = finite_number(field(e, "time", source, i), where(source, i, "time"));
    if (i == 0) t0_unix = t;
    s.t = t - t0_unix;
    auto [it, fresh] = last_time.emplace(s.sensor, s.t);
    if (!fresh) {
      if (s.t < it->second)
        throw InputError(where(source, i, "time") + ": time goes backwards for sensor " +
                         std::to_string(s.sensor));
      it->second = s.t;
    }
    const std::vector<double> own =
        number_row(field(e, "ownshipPosition", source, i), where(source, i, "ownshipPosition"));
    if (own.size() != 2)
      throw InputError(where(source, i, "ownshipPosition") + ": expected [north, east], found " +
                       std::to_string(own.size()) + " numbers");
    s.ownship = {own[0], own[1]};
    const json& m = field(e, "measurement", source, i);
    const std::string at = where(source, i, "measurement");
    if (s.sensor == kAutoferryLidar || s.sensor == kAutoferryRadar) {
      if (!m.is_array())
        throw InputError(at + ": expected a 2xM matrix of plots, found " + std::string(m.type_name()));
      if (m.size() == 2 && m[0].is_array()) {
        s.north = number_row(m[0], at + "[0]");
        s.east = number_row(m[1], at + "[1]");
        if (s.north.size() != s.east.size())
          throw InputError(at + ": expected two rows of equal length (north, east), found " +
                           std::to_string(s.north.size()) + " and " + std::to_string(s.east.size()));
      } else if (m.size() == 2) {  // M = 1, written as [n, e]
        const std::vector<double> ne = number_row(m, at);
        s.north = {ne[0]};
        s.east = {ne[1]};
      } else if (!m.empty()) {
        throw InputError(at + ": expected [], [north, east] or [[north...], [east...]], found an array of " +
                         std::to_string(m.size()));
      }
    } else if (m.is_number()) {
      s.bearing = {finite_number(m, at)};
    } else {
      s.bearing = number_row(m, at);
    }
    scans.push_back(std::move(s));
  }
  return scans;
}

TruthTable parse_autoferry_truth(const std::string& text, const std::string& source, double t0_unix) {
  const json doc = parse_json_input(text, source);
  if (!doc.is_array()) throw InputError(source + ": expected an array of ground-truth entries");
  std::map<int32_t, std::map<double, std::array<double, 2>>> fixes;  // target -> t -> (n, e)
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const json& list = doc[i];
    if (!list.is_array())
      throw InputError(source + ": entry " + std::to_string(i) + ": expected an array of targets");
    for (std::size_t k = 0; k < list.size(); ++k) {
      std::string tag = std::to_string(k);  // "[k]." (built in place: GCC 12 -Wrestrict false positive)
      tag.insert(tag.begin(), '[');
      tag += "].";
      const json& g = list[k];
      const double id = finite_number(field(g, "targetID", source, i), where(source, i, tag + "targetID"));
      if (!(id >= 0 && id == std::floor(id) && id < 1e6))
        throw InputError(where(source, i, tag + "targetID") + ": expected an integer >= 0");
      const double t = finite_number(field(g, "time", source, i), where(source, i, tag + "time")) - t0_unix;
      const std::vector<double> p =
          number_row(field(g, "position", source, i), where(source, i, tag + "position"));
      if (p.size() < 2)
        throw InputError(where(source, i, tag + "position") + ": expected [north, east, down]");
      fixes[static_cast<int32_t>(id)].emplace(t, std::array<double, 2>{p[0], p[1]});
    }
  }
  TruthTable truth(StateLayout::kXY_VXVY);
  for (const auto& [target, series] : fixes) {
    std::vector<std::pair<double, std::array<double, 2>>> f(series.begin(), series.end());
    for (std::size_t k = 0; k < f.size(); ++k) {
      const std::size_t a = k > 0 ? k - 1 : k, b = k + 1 < f.size() ? k + 1 : k;
      const double dt = f[b].first - f[a].first;
      truth.target.push_back(target);
      truth.t.push_back(f[k].first);
      truth.state[0].push_back(f[k].second[0]);
      truth.state[1].push_back(f[k].second[1]);
      truth.state[2].push_back(dt > 0 ? (f[b].second[0] - f[a].second[0]) / dt : 0.0);
      truth.state[3].push_back(dt > 0 ? (f[b].second[1] - f[a].second[1]) / dt : 0.0);
    }
  }
  return truth;
}

std::array<std::string, 2> autoferry_input_files(const std::string& root, int number) {
  const std::string stem = autoferry_scenario_dir(root, number) + "/scenario" + std::to_string(number);
  return {stem + "_detections.json", stem + "_groundTruth.json"};
}

AutoferryScenario read_autoferry_scenario(const std::string& root, int number) {
  if (std::find(kAutoferryScenarios.begin(), kAutoferryScenarios.end(), number) == kAutoferryScenarios.end())
    throw InputError("--scenario: expected one of 2, 3, 4, 5, 6, 13, 16, 17, 22, found " +
                     std::to_string(number));
  const auto files = autoferry_input_files(root, number);
  AutoferryScenario sc;
  sc.number = number;
  const std::string &det = files[0], &gt = files[1];
  sc.scans = parse_autoferry_detections(read_text(det), det, sc.t0_unix);
  sc.truth = parse_autoferry_truth(read_text(gt), gt, sc.t0_unix);
  return sc;
}

}  // namespace trackassoc
