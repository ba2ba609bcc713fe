#include "engine/pipeline/associator_fields.hpp"

#include <algorithm>
#include <string>

#include "io/memory_budget.hpp"

namespace trackassoc {

namespace {

using O = AssociatorOptions;

// A field whose JSON value is one of two strings, setting a bool or an enum without a name table.
template <class A, class T>
OptionField<O> choice_field(std::string key, A member, std::string first, T first_value, std::string second,
                            T second_value, std::string doc) {
  const auto at = option_detail::as_path(member);
  return {key, first + " | " + second, std::move(doc),
          [=](O& o, const nlohmann::json& v, const std::string& k, const std::string& solver) {
            if (!v.is_string() || (v != first && v != second))
              throw InputError("solver '" + solver + "' options: '" + k + "' must be \"" + first +
                               "\" or \"" + second + "\", got " + v.dump().substr(0, 80));
            at(o) = v == first ? first_value : second_value;
          },
          [=](const O& o) -> std::optional<nlohmann::json> { return at(o) == first_value ? first : second; }};
}

}  // namespace

const OptionFields<AssociatorOptions>& associator_option_fields() {
  static const OptionFields<O> fields{{
      field("solver", &O::solver, "a solver name",
            "lr+ls (default), lr, exact; a 3-D solver (three sensors); fuzzy, ftaa; siamese"),
      field("sd", &O::sd, "", "the dense S-D formulation with a dummy per sensor (--sd)"),
      field("three_d", &O::three_d, "", "the three-sensor cost-tensor pipeline for any solver (--3d)"),
      field("sparse", &O::sparse, "", "the three-sensor sparse path (--sparse)"),
      field("sensor_ids", path(&O::pipeline, &PipelineOptions::sensors), "none or >= 2 ids",
            "the /sensors ids to associate (--sensors; default: every sensor)"),
      field("gate", path(&O::pipeline, &PipelineOptions::statistic, &StatisticOptions::gate_probability),
            "(0, 1]", "gate probability: the share of true pairs the gate keeps (--gate)"),
      field("gate_method", path(&O::pipeline, &PipelineOptions::statistic, &StatisticOptions::gate), "",
            "calibrated or chi2-sum (--gate-method)"),
      field("alignment", path(&O::pipeline, &PipelineOptions::alignment, &AlignmentOptions::method), "",
            "two-sided or forward (--alignment)"),
      field("cost_form", path(&O::pipeline, &PipelineOptions::cost, &CostTensorOptions::form), "",
            "all-pairs or chain (--cost-form)"),
      {"correlated", "[0, 1)", "the correlated-error statistic with cross-correlation RHO (--correlated)",
       [](O& o, const nlohmann::json& v, const std::string& key, const std::string& solver) {
         read_number_value(v, key, o.pipeline.statistic.cross_correlation, solver);
         o.pipeline.statistic.correlated = true;
       },
       [](const O& o) -> std::optional<nlohmann::json> {
         if (!o.pipeline.statistic.correlated) return std::nullopt;
         return o.pipeline.statistic.cross_correlation;
       }},
      field("common_period", path(&O::pipeline, &PipelineOptions::common_period), ">= 0",
            "step of the common time grid [s] (0 = the largest scan period)"),
      field("process_noise",
            path(&O::pipeline, &PipelineOptions::alignment, &AlignmentOptions::process_noise), ">= 0",
            "white-noise acceleration sigma [m/s^2] moving tracks to common times"),
      field("extent_sigma", path(&O::pipeline, &PipelineOptions::alignment, &AlignmentOptions::extent_sigma),
            ">= 0", "reference-point sigma [m] per axis added to every pair's position covariance"),
      choice_field("common_span", path(&O::pipeline, &PipelineOptions::span_union), "union", true,
                   "intersection", false, "common times over the union or intersection of report spans"),
      choice_field("link_cost", path(&O::pipeline, &PipelineOptions::statistic, &StatisticOptions::link),
                   "per-scan", LinkCost::kPerScan, "per-independent-scan", LinkCost::kPerIndependentScan,
                   "S-D link cost of a gated-in pair (--link-cost)"),
      field("common_process_noise",
            path(&O::pipeline, &PipelineOptions::statistic, &StatisticOptions::common_process_noise),
            "[0, 1000]",
            "Bar-Shalom-Campo cross-covariance from common process noise SIGMA [m/s^2] (0 = off)"),
      {"options", "a JSON object", "the solver's own options (--options; `trackassoc solvers NAME`)",
       [](O& o, const nlohmann::json& v, const std::string& key, const std::string& solver) {
         if (!v.is_object()) option_detail::type_error(solver, key, "a dict (JSON object)");
         o.solver_options = v;
       },
       [](const O& o) -> std::optional<nlohmann::json> { return o.solver_options; }},
      field("seed", &O::seed, "[0, 2^64-1]", "random seed; results are bit-identical for any thread count"),
      field("name", &O::name, "", "the association's name (default: the solver name)"),
      field("model", &O::siamese_model, "", "solver siamese: the model file (train-siamese)"),
      field("radius_scale", &O::radius_scale, ">= 1",
            "sparse paths: widens the candidate search bound (1 = the gate's own bound)"),
      field("max_component_entries", &O::max_component_entries, ">= 1",
            "sparse paths: the largest dense sub-tensor of a component, prod(n_s + 1) entries (default: "
            "LAP merging above it; --sparse: refused)"),
      field("family_wise_veto", &O::family_wise_veto, "",
            "default pipeline: a coexisting pair outside the gate forbids a tuple only when it fails the "
            "family-wise gate 1 - (1 - p)/(S(S-1)/2) too (false: always)"),
      field("rival_exponent", &O::rival_exponent, ">= 0",
            "default pipeline: exponent of the rival-weighted link cost, gate 1 - (1 - p)*m^k for m "
            "rivals (0 = the gate itself)"),
      field("miss_cost", &O::miss_cost, ">= 0",
            "sparse=True: the cost of a missing track in a component's sub-tensor (default +inf: every "
            "track assigned)"),
      field("segments", path(&O::segments, &SegmentOptions::enabled), "",
            "default pipeline: join the segments of a target on one sensor (False = --no-segments)"),
      field("segment_overlap", path(&O::segments, &SegmentOptions::max_overlap_s), ">= 0",
            "default pipeline: report overlap [s] of two segments that still follow each other"),
      field(
          "duplicate_sensors", path(&O::segments, &SegmentOptions::duplicate_sensors), "sensor ids",
          "default pipeline: sensors whose tracker may hold two tracks of one target (--duplicate-sensors)"),
      field("registration", path(&O::registration, &RegistrationStageOptions::enabled), "",
            "default pipeline: joint registration and association (False = --no-registration)"),
      field("reference_sensor", path(&O::registration, &RegistrationStageOptions::reference_sensor),
            "sensor id",
            "default pipeline: the sensor the registration holds fixed (-1: the one with the most tracks; "
            "--reference-sensor)"),
      field("split", path(&O::split, &TrackSplitOptions::enabled), "",
            "default pipeline: split recycled track numbers into new local tracks (False = --no-split)"),
      field("stitch", path(&O::stitching, &TrackStitchOptions::enabled), "",
            "default pipeline: join output targets that never coexist when one continues the other "
            "(False = --no-stitch)"),
  }};
  return fields;
}

AssociatorOptions read_associator_options(const nlohmann::json& fields, const std::string& caller) {
  const std::string prefix = "solver '" + caller + "' options: ";
  try {
    AssociatorOptions o;
    associator_option_fields().read(fields, o, caller);
    o.validate();
    // The dense tensor's budget, as `associate`'s (engine/cli/association_flags.hpp): the smaller
    // of CostTensorOptions' 2 GiB and the process's memory budget.
    o.pipeline.cost.memory_budget_bytes =
        memory_budget_was_set() ? memory_budget_bytes()
                                : std::min(o.pipeline.cost.memory_budget_bytes, memory_budget_bytes());
    o.pipeline.validate();
    return o;
  } catch (const InputError& e) {
    std::string msg = e.what();
    if (msg.rfind(prefix, 0) == 0) msg.erase(0, prefix.size());
    throw InputError(caller + ": " + msg);
  }
}

}  // namespace trackassoc
