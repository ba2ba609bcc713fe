// The "wide_area" block of a scenario (io/scenario_json.hpp; the model:
// engine/simulation/simulation_widearea.hpp). Whole-scenario rules (coast_scans needed by the
// radii, births needing lives) are checked by the simulation's validation, which names the field.
#include <limits>

#include "io/scenario_json_reader.hpp"

namespace trackassoc::scenario_json_detail {

namespace {

void read_mask(Reader& r, MaskSpec& m) {
  r.integer("sensor", m.sensor, 0, std::numeric_limits<int32_t>::max());
  r.integer("target", m.target, 0, std::numeric_limits<int32_t>::max());
  r.number("start", m.start);
  r.number("end", m.end);
  r.finish();
  if (!(m.end > m.start))
    throw InputError(r.source() + ": " + r.key_path("end") + ": expected end > start [s], found end " +
                     std::to_string(m.end) + " <= start " + std::to_string(m.start));
}

bool below_one(double v) { return v >= 0 && v < 1; }

}  // namespace

void read_wide_area(Reader& r, WideAreaSpec& w) {
  r.number("edge_fraction", w.edge_fraction, below_one, " in [0, 1)");
  r.number("fade_rate", w.fade_rate, non_negative, " >= 0");
  r.number("fade_duration_min", w.fade_duration_min, non_negative, " >= 0");
  r.number("fade_duration_max", w.fade_duration_max, non_negative, " >= 0");
  if (const json* masks = r.array("masks"))
    for (std::size_t i = 0; i < masks->size(); ++i) {
      Reader mr((*masks)[i], r.key_path("masks[" + std::to_string(i) + "]"), r.source());
      MaskSpec m;
      read_mask(mr, m);
      w.masks.push_back(m);
    }
  r.integer("coast_scans", w.coast_scans, 0, 1000);
  r.number("birth_rate", w.birth_rate, non_negative, " >= 0");
  r.number("lifetime_mean", w.lifetime_mean, non_negative, " >= 0");
  r.finish();
  r.not_below("fade_duration_max", w.fade_duration_max, "fade_duration_min", w.fade_duration_min);
}

nlohmann::ordered_json wide_area_json(const WideAreaSpec& w) {
  nlohmann::ordered_json j;
  j["edge_fraction"] = w.edge_fraction;
  j["fade_rate"] = w.fade_rate;
  j["fade_duration_min"] = w.fade_duration_min;
  j["fade_duration_max"] = w.fade_duration_max;
  if (!w.masks.empty()) {
    j["masks"] = nlohmann::ordered_json::array();
    for (const MaskSpec& m : w.masks)
      j["masks"].push_back({{"sensor", m.sensor}, {"target", m.target}, {"start", m.start}, {"end", m.end}});
  }
  j["coast_scans"] = w.coast_scans;
  j["birth_rate"] = w.birth_rate;
  j["lifetime_mean"] = w.lifetime_mean;
  return j;
}

}  // namespace trackassoc::scenario_json_detail
