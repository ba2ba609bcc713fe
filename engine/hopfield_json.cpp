#include "engine/hopfield_json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/solver_registry.hpp"
#include "kernels/error.hpp"

namespace trackassoc {

namespace {

// The registry's Hopfield solvers: name, description (solve3d --help) and preset.
struct HopfieldPresetEntry {
  const char* name;
  const char* description;
  HopfieldOptions (*preset)();
};

const std::vector<HopfieldPresetEntry>& hopfield_presets() {
  static const std::vector<HopfieldPresetEntry> presets{
      {"hopfield", "discrete 3-D Hopfield network, full-plane energy, mean-field start (seed 000)",
       [] { return HopfieldOptions{}; }},
      {"hopfield-paper",
       "discrete 3-D Hopfield network as printed (seed 000 Eq. 11, A=B=C=300, D=200, E=1100)",
       [] {
         // seed 000 §3–4 as printed: Eq. 11 with A=B=C=300, D=200, E=1100; Eq. 10 updates. The paper
         // does not give the initial state or the order: all neurons off, asynchronous in a fresh
         // uniform random order, one run.
         HopfieldOptions o;
         o.energy = HopfieldEnergy::kPrinted;
         o.auto_weights = false;
         o.weights = HopfieldWeights{300.f, 300.f, 300.f, 200.f, 1100.f, 0};
         o.init = HopfieldInit::kZero;
         o.order = HopfieldOrder::kRandom;
         o.restarts = 1;
         o.max_sweeps = 500;
         return o;
       }},
      {"chnn", "continuous Hopfield network with gain annealing (CHNN, seed 004)", [] {
         HopfieldOptions o;
         o.network = HopfieldNetwork::kContinuous;
         return o;
       }}};
  return presets;
}

}  // namespace

const std::vector<std::string>& hopfield_preset_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& p : hopfield_presets()) n.push_back(p.name);
    return n;
  }();
  return names;
}

std::string hopfield_preset_description(const std::string& name) {
  for (const auto& p : hopfield_presets())
    if (name == p.name) return p.description;
  throw InputError("hopfield preset: unknown name '" + name + "'");
}

HopfieldOptions hopfield_preset(const std::string& name) {
  for (const auto& p : hopfield_presets())
    if (name == p.name) return p.preset();
  throw InputError("hopfield preset: unknown name '" + name + "'");
}

std::vector<std::string> hopfield_schedule_names(HopfieldNetwork network) {
  if (network == HopfieldNetwork::kContinuous) return {"sync", "async", "continuous"};
  return {"sync", "async", "diagonal"};
}

std::string hopfield_schedule_error(HopfieldNetwork network, const std::string& schedule) {
  const std::vector<std::string> own = hopfield_schedule_names(network);
  if (std::find(own.begin(), own.end(), schedule) != own.end()) return "";
  if (schedule != "sync" && schedule != "async" && schedule != "diagonal" && schedule != "continuous")
    return "schedule: expected sync, async, diagonal or continuous, found '" + schedule + "'";
  // Each registry name is one network, and `schedule` picks among that network's schedules: chnn
  // steps its Euler equations sync (Jacobi) or async (neuron by neuron); hopfield and
  // hopfield-paper are discrete. (A schedule that swapped the network would leave a record named
  // "chnn" that ran the discrete network.)
  if (network == HopfieldNetwork::kContinuous)
    return "schedule: 'diagonal' is a schedule of the discrete network (solver 'hopfield'); the "
           "continuous network takes sync, async or continuous (= sync Euler steps)";
  return "schedule: 'continuous' is the continuous network, solver 'chnn'; the discrete "
         "network takes sync, async or diagonal";
}

namespace {

// `schedule` (one of the network's own) into o.
void set_hopfield_schedule(HopfieldOptions& o, const std::string& schedule) {
  if (o.network == HopfieldNetwork::kContinuous)
    o.continuous_async = schedule == "async";  // "continuous" = "sync"
  else
    o.schedule = parse_hopfield_schedule(schedule);
}

}  // namespace

std::string hopfield_preset_schedule_error(const std::string& name, const std::string& schedule) {
  HopfieldOptions o = hopfield_preset(name);
  std::string why = hopfield_schedule_error(o.network, schedule);
  if (why.empty()) {
    set_hopfield_schedule(o, schedule);
    try {
      o.validate();  // e.g. diagonal needs the full-plane energy, which hopfield-paper does not use
    } catch (const InputError& e) {
      why = e.what();
    }
  }
  return why.empty() ? "" : "solver '" + name + "' options: " + why;
}

std::vector<std::string> hopfield_preset_schedules(const std::string& name) {
  std::vector<std::string> out;
  for (const std::string& s : hopfield_schedule_names(hopfield_preset(name).network))
    if (hopfield_preset_schedule_error(name, s).empty()) out.push_back(s);
  return out;
}

namespace {

// The keys hopfield_options_from_json reads (engine/hopfield_json.hpp), for the message on an unknown one.
const std::vector<std::string> kHopfieldKeys{"energy",
                                             "schedule",
                                             "restarts",
                                             "max_sweeps",
                                             "init",
                                             "init_density",
                                             "greedy_noise",
                                             "order",
                                             "anneal_E_factor",
                                             "anneal_sweeps",
                                             "temperature",
                                             "damping",
                                             "continuous_async",
                                             "dt",
                                             "tau",
                                             "u0_start",
                                             "u0_end",
                                             "gain_anneal_steps",
                                             "noise",
                                             "self_excitation",
                                             "tolerance",
                                             "mean_field_steps",
                                             "repair",
                                             "trace",
                                             "polish",
                                             "A",
                                             "B",
                                             "C",
                                             "D",
                                             "E"};

// The checks of read_option_number (engine/solver_registry.hpp): type, integer, and the field's range
// (5e9 for an int32 count, 1e300 for a float weight).
template <class T>
T get_number(const nlohmann::json& j, const std::string& key, const std::string& solver) {
  T value{};
  read_option_number(nlohmann::json{{key, j}}, key.c_str(), value, solver);
  return value;
}

std::string get_string(const nlohmann::json& j, const std::string& key, const std::string& solver) {
  if (!j.is_string()) throw InputError("solver '" + solver + "' options: '" + key + "' must be a string");
  return j.get<std::string>();
}

bool get_bool(const nlohmann::json& j, const std::string& key, const std::string& solver) {
  if (!j.is_boolean())
    throw InputError("solver '" + solver + "' options: '" + key + "' must be true or false");
  return j.get<bool>();
}

}  // namespace

HopfieldOptions hopfield_options_from_json(const std::string& name, const nlohmann::json& options,
                                           bool& polish) {
  HopfieldOptions o = hopfield_preset(name);
  polish = false;
  if (options.is_null()) return o;
  if (!options.is_object()) throw InputError("solver '" + name + "' options: expected a JSON object");
  bool weights_given = false;
  HopfieldWeights w = o.auto_weights ? HopfieldWeights{1.f, 1.f, 1.f, 0.f, 1.4985f, 0} : o.weights;
  for (auto it = options.begin(); it != options.end(); ++it) {
    const std::string& k = it.key();
    const nlohmann::json& v = it.value();
    try {
      if (k == "energy") {
        const std::string e = get_string(v, k, name);
        if (e == "full_plane")
          o.energy = HopfieldEnergy::kFullPlane;
        else if (e == "printed")
          o.energy = HopfieldEnergy::kPrinted;
        else
          throw InputError("energy: expected full_plane or printed, found '" + e + "'");
      } else if (k == "schedule") {
        const std::string value = get_string(v, k, name);
        const std::string why = hopfield_schedule_error(o.network, value);
        if (!why.empty()) throw InputError(why);
        set_hopfield_schedule(o, value);
      } else if (k == "restarts")
        o.restarts = get_number<int32_t>(v, k, name);
      else if (k == "max_sweeps")
        o.max_sweeps = get_number<int32_t>(v, k, name);
      else if (k == "init")
        o.init = parse_hopfield_init(get_string(v, k, name));
      else if (k == "init_density")
        o.init_density = get_number<double>(v, k, name);
      else if (k == "greedy_noise")
        o.greedy_noise = get_number<double>(v, k, name);
      else if (k == "order")
        o.order = parse_hopfield_order(get_string(v, k, name));
      else if (k == "anneal_E_factor")
        o.anneal_E_factor = get_number<double>(v, k, name);
      else if (k == "anneal_sweeps")
        o.anneal_sweeps = get_number<int32_t>(v, k, name);
      else if (k == "temperature")
        o.temperature = get_number<double>(v, k, name);
      else if (k == "damping")
        o.damping = get_number<double>(v, k, name);
      else if (k == "continuous_async")
        o.continuous_async = get_bool(v, k, name);
      else if (k == "dt")
        o.dt = get_number<double>(v, k, name);
      else if (k == "tau")
        o.tau = get_number<double>(v, k, name);
      else if (k == "u0_start")
        o.u0_start = get_number<double>(v, k, name);
      else if (k == "u0_end")
        o.u0_end = get_number<double>(v, k, name);
      else if (k == "gain_anneal_steps")
        o.gain_anneal_steps = get_number<int32_t>(v, k, name);
      else if (k == "noise")
        o.noise = get_number<double>(v, k, name);
      else if (k == "self_excitation")
        o.self_excitation = get_number<double>(v, k, name);
      else if (k == "tolerance")
        o.tolerance = get_number<double>(v, k, name);
      else if (k == "mean_field_steps")
        o.mean_field_steps = get_number<int32_t>(v, k, name);
      else if (k == "repair") {
        const std::string r = get_string(v, k, name);
        if (r == "greedy")
          o.repair = HopfieldRepair::kGreedy;
        else if (r == "lap")
          o.repair = HopfieldRepair::kLap;
        else
          throw InputError("repair: expected greedy or lap, found '" + r + "'");
      } else if (k == "trace")
        o.trace = get_bool(v, k, name);
      else if (k == "polish")
        o.polish = polish = get_bool(v, k, name);
      else if (k == "A" || k == "B" || k == "C" || k == "D" || k == "E") {
        const float x = get_number<float>(v, k, name);
        weights_given = true;
        (k == "A" ? w.A : k == "B" ? w.B : k == "C" ? w.C : k == "D" ? w.D : w.E) = x;
      } else {
        throw InputError(unknown_name_message("key", k, kHopfieldKeys));
      }
    } catch (const InputError& e) {
      const std::string msg = e.what();
      if (msg.rfind("solver '", 0) == 0) throw;
      throw InputError("solver '" + name + "' options: " + msg);
    }
  }
  if (weights_given) {
    o.auto_weights = false;
    o.weights = w;
  }
  try {
    o.validate();
  } catch (const InputError& e) {
    throw InputError("solver '" + name + "' options: " + std::string(e.what()));
  }
  return o;
}

Solution3 solve_hopfield_json(const std::string& name, const CostTensor3& cost, const nlohmann::json& options,
                              uint64_t seed) {
  bool polish = false;
  const HopfieldOptions o = hopfield_options_from_json(name, options, polish);
  HopfieldResult r = solve_hopfield(cost, o, seed);
  Solution3 s = std::move(r.solution);
  s.restarts = hopfield_restart_table(r);
  if (o.trace && !r.restarts.empty()) {
    std::size_t cols = 0;
    for (const auto& rr : r.restarts) cols = std::max(cols, rr.energy_trace.size());
    s.energy_rows = static_cast<int32_t>(r.restarts.size());
    s.energy_cols = static_cast<int32_t>(cols);
    s.energy_trace.assign(r.restarts.size() * cols, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < r.restarts.size(); ++i)
      std::copy(r.restarts[i].energy_trace.begin(), r.restarts[i].energy_trace.end(),
                s.energy_trace.begin() + i * cols);
  }
  return s;
}

}  // namespace trackassoc
