#include "engine/solvers/hopfield_json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/solvers/option_fields.hpp"
#include "kernels/core/error.hpp"

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
  // The discrete schedules (HopfieldSchedule's name table) and "continuous" (= sync Euler steps).
  std::string every;
  bool known = schedule == "continuous";
  for (const auto& n : enum_names(HopfieldSchedule{})) {
    every += std::string(n.name) + ", ";
    known |= schedule == n.name;
  }
  if (!known)
    return "schedule: expected " + every.substr(0, every.size() - 2) + " or continuous, found '" + schedule +
           "'";
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
    o.schedule = parse_enum<HopfieldSchedule>(schedule, "schedule");
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

// The "schedule" key. Each registry name is one network, and `schedule` picks among that network's
// schedules: chnn steps its Euler equations sync (Jacobi) or async (neuron by neuron); hopfield and
// hopfield-paper are discrete. (A schedule that swapped the network would leave a record named
// "chnn" that ran the discrete network.)
void read_schedule(HopfieldOptions& o, const nlohmann::json& v, const std::string& key,
                   const std::string& solver) {
  if (!v.is_string()) throw InputError("solver '" + solver + "' options: '" + key + "' must be a string");
  const std::string value = v.get<std::string>();
  const std::string why = hopfield_schedule_error(o.network, value);
  if (!why.empty()) throw InputError(why);
  set_hopfield_schedule(o, value);
}

// What read_schedule reads back: the continuous network's step order, or the discrete schedule.
std::optional<nlohmann::json> write_schedule(const HopfieldOptions& o) {
  if (o.network == HopfieldNetwork::kContinuous) return o.continuous_async ? "async" : "sync";
  return enum_name(o.schedule);
}

// A, B, C, D, E: giving any of them switches off the automatic weights; the others keep the
// preset's values (automatic: A = B = C = 1, D = 0, E = 1.4985).
OptionField<HopfieldOptions> weight_field(const char* key, float HopfieldWeights::*w, const char* doc) {
  OptionField<HopfieldOptions> f = field(key, path(&HopfieldOptions::weights, w), "finite, >= 0", doc);
  auto read = f.read;
  f.read = [read](HopfieldOptions& o, const nlohmann::json& v, const std::string& k,
                  const std::string& solver) {
    if (o.auto_weights) {
      o.weights = HopfieldWeights{1.f, 1.f, 1.f, 0.f, 1.4985f, 0};
      o.auto_weights = false;
    }
    read(o, v, k, solver);
  };
  auto write = f.write;
  f.write = [write](const HopfieldOptions& o) { return o.auto_weights ? std::nullopt : write(o); };
  return f;
}

}  // namespace

const OptionFields<HopfieldOptions>& hopfield_option_fields() {
  using O = HopfieldOptions;
  static const OptionFields<O> fields{{
      field("energy", &O::energy, "", "energy function: seed 000 Eq. 11 on the full planes, or as printed"),
      {"schedule", "sync | async | diagonal; chnn: sync | async | continuous",
       "update schedule of the solver's own network (chnn: its Euler steps; continuous = sync)",
       read_schedule, write_schedule},
      field("restarts", &O::restarts, "1..100000",
            "independent restarts; the best repaired assignment is kept"),
      field("max_sweeps", &O::max_sweeps, ">= 1", "discrete sweeps, or continuous Euler steps"),
      field("init", &O::init, "", "initial state of the discrete network"),
      field("init_density", &O::init_density, "> 0",
            "random init: each neuron on with probability density·N/K"),
      field("greedy_noise", &O::greedy_noise, ">= 0",
            "greedy init, restarts >= 1: cost order of ĉ + noise·U(0,1)"),
      field("order", &O::order, "", "async visiting order within a sweep"),
      field("anneal_E_factor", &O::anneal_E_factor, ">= 1",
            "E annealing: E_s = E·factor^(1 − s/anneal_sweeps)"),
      field("anneal_sweeps", &O::anneal_sweeps, ">= 0", "sweeps of E and temperature annealing"),
      field("temperature", &O::temperature, ">= 0", "Glauber temperature T0 (async), annealed to 0"),
      field("damping", &O::damping, "(0, 1]", "sync: share of neurons updated per sweep"),
      field("continuous_async", &O::continuous_async, "", "continuous network: async Euler steps"),
      field("dt", &O::dt, "> 0", "continuous: Euler step"),
      field("tau", &O::tau, ">= 0", "continuous: decay time constant (0 = no decay)"),
      field("u0_start", &O::u0_start, "> 0", "continuous: initial gain parameter u0"),
      field("u0_end", &O::u0_end, "> 0", "continuous: final gain parameter u0"),
      field("gain_anneal_steps", &O::gain_anneal_steps, ">= 0",
            "continuous: steps of geometric gain annealing"),
      field("noise", &O::noise, ">= 0", "continuous: initial u noise, in units of u0_start"),
      field("self_excitation", &O::self_excitation, "[0, 1]", "continuous: λ (1 = multilinear energy)"),
      field("tolerance", &O::tolerance, "> 0", "continuous: stop when max |ΔV| < tolerance"),
      field("mean_field_steps", &O::mean_field_steps, ">= 1",
            "init mean_field: Euler steps of the continuous phase"),
      field("repair", &O::repair, "", "repair of an invalid final state"),
      field("trace", &O::trace, "", "record the energy after every sweep, per restart"),
      field("polish", &O::polish, "", "LAP local search on every restart's assignment"),
      weight_field("A", &HopfieldWeights::A,
                   "penalty of the sensor-1 planes, seed 000 Eq. 11 (unset: automatic)"),
      weight_field("B", &HopfieldWeights::B, "penalty of the sensor-2 planes"),
      weight_field("C", &HopfieldWeights::C, "penalty of the sensor-3 planes"),
      weight_field("D", &HopfieldWeights::D, "penalty of M != N active neurons"),
      weight_field("E", &HopfieldWeights::E, "weight of the normalised cost"),
  }};
  return fields;
}

HopfieldOptions hopfield_options_from_json(const std::string& name, const nlohmann::json& options,
                                           bool& polish) {
  HopfieldOptions o = hopfield_preset(name);
  hopfield_option_fields().read(options, o, name);
  polish = o.polish;
  try {
    o.validate();
  } catch (const InputError& e) {
    throw InputError("solver '" + name + "' options: " + std::string(e.what()));
  }
  return o;
}

nlohmann::json hopfield_options_to_json(const HopfieldOptions& options) {
  return hopfield_option_fields().write(options);
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
