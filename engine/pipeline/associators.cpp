// The implementations of TrackAssociator (engine/pipeline/associator.hpp), one per path, each a thin
// wrapper of its pipeline's entry points, and the factory; the rules that pick the stages, and so
// the path, are engine/pipeline/association_plan.cpp's.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <span>
#include <unordered_set>
#include <utility>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/fuzzy_pipeline.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/siamese_track_file.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/local_track_rows.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

// The name of the record: --name when given, else the one the pipeline set (the solver name).
void apply_name(const AssociatorOptions& o, AssociationRecord& rec) {
  if (!o.name.empty()) rec.name = o.name;
}
std::string group_name(const AssociatorOptions& o) { return o.name.empty() ? o.solver : o.name; }

// Fills the outcome's unassociated tracks from its record and summary.sensor_ids, and the
// summary's fields every path has: the solver, the file's sensors, the record's result.
AssociationOutcome finish(const TrackFile& file, const AssociatorOptions& o, AssociationOutcome out) {
  out.unassociated = unassociated_tracks(file, out.summary.sensor_ids, out.record);
  AssociationSummary& s = out.summary;
  const AssociationRecord& rec = out.record;
  s.solver = o.solver;
  s.file_sensors = static_cast<int32_t>(file.sensors.size());
  s.tuples = static_cast<int64_t>(rec.num_tuples());
  s.objective = rec.objective;
  s.lower_bound = rec.lower_bound;
  s.gap = rec.gap;
  s.termination = rec.termination;
  for (const UnassociatedTracks& u : out.unassociated) s.unassociated.push_back(std::ssize(u.tracks));
  return out;
}

// A dense path's partition is the whole problem (engine/pipeline/partition.hpp): one component.
// Its summary lists the problem's stages (alignment, statistics, tensor) and the solve, whose
// time is the record's; its candidate pairs are every pair of two sensors' tracks.
void whole_problem_stages(const std::vector<StageReport>& problem,
                          std::span<const PairStatistic* const> pairs, const AssociationRecord& rec,
                          AssociationSummary& s) {
  s.stages = problem;
  s.stages.push_back({"solve", rec.runtime_s, peak_rss_mib(), 0.0});
  s.components = 1;
  for (const PairStatistic* st : pairs) {
    s.candidate_pairs += std::ssize(st->in_gate);
    s.gated_pairs += std::count(st->in_gate.begin(), st->in_gate.end(), uint8_t{1});
  }
}

template <class Range>
std::vector<int32_t> track_counts(const Range& aligned) {
  std::vector<int32_t> n;
  for (const auto& a : aligned) n.push_back(a.n_tracks());
  return n;
}

class SparseSDAssociator final : public TrackAssociator {
 public:
  explicit SparseSDAssociator(const AssociatorOptions& o) : o_(o) { require_sparse_sd_solver(o.solver); }
  AssociationPath path() const override { return AssociationPath::kSparseSD; }
  AssociationOutcome associate(const TrackFile& file) const override {
    SparseSDOptions so;
    so.pipeline = o_.pipeline;
    so.radius_scale = o_.radius_scale;
    so.max_component_entries = o_.max_component_entries;
    so.rival_exponent = o_.rival_exponent;
    so.family_wise_veto = o_.family_wise_veto;
    so.segments = o_.segments;
    so.ranks = o_.ranks;
    AssociationOutcome out;
    RegistrationStageOptions ro = o_.registration;
    RegistrationStageResult reg;
    std::vector<SparseSDReport> reports;  // one per association the registration stage ran
    const auto t0 = std::chrono::steady_clock::now();
    out.record = associate_with_registration(
        file, ro,
        [&](const TrackFile& f) {
          return associate_sparse_sd(f, o_.solver, o_.solver_options, o_.seed, so, &reports.emplace_back());
        },
        &reg);
    // The association returned: the last one when the registration applied, else the first.
    SparseSDReport& kept = reg.applied ? reports.back() : reports.front();
    AssociationSummary& s = out.summary;
    s.stages = std::move(kept.stages);
    // The registration's own time (everything but the kept association: the fits and, when it
    // re-associated, the other association on corrected reports) ran before the stitching, and so
    // did the peak memory it reached.
    if (reg.fitted)
      s.stages.push_back(
          {"registration", std::max(0.0, seconds_since(t0) - out.record.runtime_s), peak_rss_mib(), 0.0});
    // Fragments: on the reports the association used (corrected when the registration applied).
    if (o_.stitching.enabled) {
      const auto ts = std::chrono::steady_clock::now();
      s.stitching = stitch_fragments(reg.registered ? *reg.registered : file, out.record, o_.stitching);
      s.stages.push_back(stage_since("stitching", ts));
      out.record.runtime_s += s.stages.back().seconds;
    }
    reg.registered.reset();  // the corrected copy is not needed past here
    apply_name(o_, out.record);
    if (reg.fitted) {
      out.registration = reg.to_record(file, out.record.name, ro);
      s.registration = out.registration;
      out.record.runtime_s = seconds_since(t0);
    }
    s.path = path();
    s.sensor_ids = select_sensors(file, o_.pipeline, SensorRule::kTwoOrMore).ids;
    s.runtime_s = out.record.runtime_s;
    s.components = kept.solve.components;
    s.candidate_pairs = kept.solve.candidate_pairs;
    s.gated_pairs = kept.solve.gated_pairs;
    s.fallback_components = kept.solve.fallback_components;
    s.listed_components = kept.solve.listed_components;
    s.largest_listed_tuples = static_cast<int64_t>(kept.solve.largest_listed_tuples);
    s.largest_component_gap = kept.solve.largest_component_gap;
    s.components_above_1pct_gap = kept.solve.components_above_1pct_gap;
    s.segments = kept.segments;
    s.empty_sensors = std::move(kept.empty_sensor_ids);
    s.unfiltered_sensors = std::move(kept.unfiltered);
    return finish(file, o_, std::move(out));
  }

 private:
  AssociatorOptions o_;
};

class DenseSDAssociator final : public TrackAssociator {
 public:
  explicit DenseSDAssociator(const AssociatorOptions& o) : o_(o) { require_sd_solver(o.solver); }
  AssociationPath path() const override { return AssociationPath::kDenseSD; }
  AssociationOutcome associate(const TrackFile& file) const override {
    const SDProblem problem = build_sd_problem(file, o_.pipeline);
    AssociationOutcome out;
    out.record = solve_sd_association(problem, o_.solver, o_.solver_options, o_.seed, o_.pipeline);
    apply_name(o_, out.record);
    std::vector<const PairStatistic*> pairs;
    for (int32_t a = 0; a < problem.S(); ++a)
      for (int32_t b = a + 1; b < problem.S(); ++b)
        pairs.push_back(&problem.pairs[std::size_t(a) * problem.S() + b]);
    whole_problem_stages(problem.stages, pairs, out.record, out.summary);
    out.record.runtime_s += total_seconds(problem.stages);  // built here: the record's time is the path's
    out.summary.path = path();
    out.summary.sensor_ids = problem.sensor_ids;
    out.summary.track_counts = track_counts(problem.aligned);
    out.summary.unfiltered_sensors = unfiltered_sensors(problem);
    out.summary.runtime_s = out.record.runtime_s;
    return finish(file, o_, std::move(out));
  }

 private:
  AssociatorOptions o_;
};

// Dense and sparse 3-D: the problem is built here, or shared (PreparedThreeSensorProblem).
class ThreeSensorAssociator final : public TrackAssociator {
 public:
  ThreeSensorAssociator(const AssociatorOptions& o, bool sparse, PreparedThreeSensorProblem prepared = {})
      : o_(o), sparse_(sparse), prepared_(std::move(prepared)) {
    find_solver(o.solver);  // an unknown name fails before anything is read
    sparse_options_.pipeline = o.pipeline;
    sparse_options_.radius_scale = o.radius_scale;
    sparse_options_.miss_cost = o.miss_cost;
    sparse_options_.max_component_entries = o.max_component_entries;
    if (sparse) sparse_options_.ranks = o.ranks;  // --sparse: the components shared over MPI ranks
  }
  AssociationPath path() const override {
    return sparse_ ? AssociationPath::kSparse3D : AssociationPath::kDense3D;
  }
  AssociationOutcome associate(const TrackFile& file) const override {
    AssociationOutcome out;
    AssociationSummary& s = out.summary;
    s.path = path();
    if (sparse_) {
      std::shared_ptr<const SparseAssociationProblem> p = prepared_.sparse;
      if (!p)
        p = std::make_shared<SparseAssociationProblem>(
            build_sparse_association_problem(file, sparse_options_));
      s.stages = p->stages;  // the problem's (built here or shared), then the solve
      out.record =
          solve_sparse_association(*p, o_.solver, o_.solver_options, o_.seed, sparse_options_, &s.stages);
      if (!prepared_.sparse) out.record.runtime_s += total_seconds(p->stages);
      s.sensor_ids.assign(p->sensor_ids.begin(), p->sensor_ids.end());
      s.track_counts = track_counts(p->aligned);
      s.unfiltered_sensors = unfiltered_sensors(*p);
      s.components = p->components.count;
      for (int q = 0; q < 3; ++q) s.candidate_pairs += static_cast<int64_t>(p->candidate_pairs[q]);
      s.gated_pairs = static_cast<int64_t>(p->s12.size() + p->s23.size() + p->s13.size());
    } else {
      std::shared_ptr<const AssociationProblem> p = prepared_.dense;
      if (!p) {
        require_dense_tensor_fits(file, o_.pipeline);
        p = std::make_shared<AssociationProblem>(build_association_problem(file, o_.pipeline));
      }
      out.record = solve_association(*p, o_.solver, o_.solver_options, o_.seed, o_.pipeline);
      const std::array<const PairStatistic*, 3> pairs{&p->s12, &p->s23, &p->s13};
      whole_problem_stages(p->stages, pairs, out.record, s);
      if (!prepared_.dense) out.record.runtime_s += total_seconds(p->stages);
      s.sensor_ids.assign(p->sensor_ids.begin(), p->sensor_ids.end());
      s.track_counts = {p->tensor.n1, p->tensor.n2, p->tensor.n3};
      s.unfiltered_sensors = unfiltered_sensors(*p);
    }
    apply_name(o_, out.record);
    s.runtime_s = out.record.runtime_s;
    return finish(file, o_, std::move(out));
  }

 private:
  AssociatorOptions o_;
  bool sparse_;
  PreparedThreeSensorProblem prepared_;
  SparsePipelineOptions sparse_options_;
};

// Seed 001's fusion centre over every sensor; the system tracks are its side output.
class FusionCentreAssociator final : public TrackAssociator {
 public:
  explicit FusionCentreAssociator(const AssociatorOptions& o)
      : o_(o),
        fuzzy_(fuzzy_pipeline_options(parse_enum<FusionMethod>(o.solver, "--solver"), o.solver_options)) {}
  AssociationPath path() const override { return AssociationPath::kFusionCentre; }
  AssociationOutcome associate(const TrackFile& file) const override {
    FuzzyPipelineResult res = run_fuzzy_pipeline(file.tracks, file.sensors, fuzzy_, group_name(o_),
                                                 file.measurements ? &*file.measurements : nullptr);
    AssociationOutcome out;
    out.record = std::move(res.association);
    out.system_tracks = std::move(res.system_tracks);
    AssociationSummary& s = out.summary;
    s.path = path();
    for (const auto& sensor : file.sensors) s.sensor_ids.push_back(sensor.id);
    s.runtime_s = res.fusion.summary.wall_time_s;
    s.local_tracks = static_cast<int64_t>(res.packets.num_local());
    s.packets = static_cast<int64_t>(res.packets.size());
    s.system_tracks = res.fusion.num_system_tracks;
    return finish(file, o_, std::move(out));
  }

 private:
  AssociatorOptions o_;
  FuzzyPipelineOptions fuzzy_;
};

// Seed 003's Siamese BiLSTM on two sensors; the model is read before any track file.
class SiameseAssociator final : public TrackAssociator {
 public:
  explicit SiameseAssociator(const AssociatorOptions& o)
      : o_(o),
        siamese_(siamese_track_file_options(o.solver_options)),
        model_(read_siamese_model(o.siamese_model)) {}
  AssociationPath path() const override { return AssociationPath::kSiamese; }
  AssociationOutcome associate(const TrackFile& file) const override {
    SiameseTrackFileResult res = associate_siamese_tracks(file, model_.model, siamese_, group_name(o_));
    res.record.seed = o_.seed;
    AssociationOutcome out;
    out.record = std::move(res.record);
    AssociationSummary& s = out.summary;
    s.path = path();
    s.sensor_ids = {res.sensor_ids[0], res.sensor_ids[1]};
    s.track_counts = {res.tracks[0], res.tracks[1]};
    s.runtime_s = out.record.runtime_s;
    s.points = res.points;
    s.points_outside_domain = res.points_outside_domain;
    return finish(file, o_, std::move(out));
  }

 private:
  AssociatorOptions o_;
  SiameseTrackFileOptions siamese_;
  LoadedSiameseModel model_;
};

}  // namespace

void AssociatorOptions::validate() const {
  if (int(sd) + int(three_d) + int(sparse) > 1)
    throw InputError("--sd, --3d and --sparse choose different pipelines: give at most one");
  if (solver.empty()) throw InputError("--solver: expected a solver name, got an empty string");
  if (!solver_options.is_object())
    throw InputError("--options: expected a JSON object, got '" + solver_options.dump().substr(0, 200) + "'");
  if (!(radius_scale >= 1.0) || !std::isfinite(radius_scale))
    throw InputError("AssociatorOptions.radius_scale: expected a finite number >= 1, got " +
                     std::to_string(radius_scale));
  if (max_component_entries < 1)
    throw InputError("AssociatorOptions.max_component_entries: expected >= 1, got 0");
  if (!(rival_exponent >= 0.0) || !std::isfinite(rival_exponent))
    throw InputError("AssociatorOptions.rival_exponent: expected a finite exponent >= 0, got " +
                     std::to_string(rival_exponent));
  if (std::isnan(miss_cost) || miss_cost < 0.f)
    throw InputError("AssociatorOptions.miss_cost: expected >= 0 (+inf: every track assigned), got " +
                     std::to_string(miss_cost));
  segments.validate();
  stitching.validate();
  if (!segments.enabled && !segments.duplicate_sensors.empty())
    throw InputError("--duplicate-sensors: duplicates join targets in the segment pass; drop --no-segments");
}

TrackSplitSummary split_recorded_keys(TrackFile& file, const AssociatorOptions& options) {
  if (!options.split.enabled || choose_association_path(options) != AssociationPath::kSparseSD) return {};
  return split_tracks(file, options.split);
}

AssociationPath choose_association_path(const AssociatorOptions& o) {
  return choose_association_plan(o).path();
}

std::unique_ptr<TrackAssociator> make_associator(AssociationPath path, const AssociatorOptions& o) {
  o.validate();
  switch (path) {
    case AssociationPath::kSparseSD:
      return std::make_unique<SparseSDAssociator>(o);
    case AssociationPath::kDenseSD:
      return std::make_unique<DenseSDAssociator>(o);
    case AssociationPath::kDense3D:
      return std::make_unique<ThreeSensorAssociator>(o, false);
    case AssociationPath::kSparse3D:
      return std::make_unique<ThreeSensorAssociator>(o, true);
    case AssociationPath::kFusionCentre:
      return std::make_unique<FusionCentreAssociator>(o);
    case AssociationPath::kSiamese:
      return std::make_unique<SiameseAssociator>(o);
  }
  throw InputError("association path: unknown");
}

std::unique_ptr<TrackAssociator> make_associator(const AssociatorOptions& o) {
  return make_associator(choose_association_path(o), o);
}

std::unique_ptr<TrackAssociator> make_three_sensor_associator(const AssociatorOptions& o,
                                                              PreparedThreeSensorProblem prepared) {
  o.validate();
  require(bool(prepared.dense) != bool(prepared.sparse), "PreparedThreeSensorProblem",
          "exactly one of dense and sparse must be set");
  const bool sparse = bool(prepared.sparse);
  return std::make_unique<ThreeSensorAssociator>(o, sparse, std::move(prepared));
}

std::vector<UnassociatedTracks> unassociated_tracks(const TrackFile& file,
                                                    const std::vector<int32_t>& sensor_ids,
                                                    const AssociationRecord& rec) {
  std::map<int32_t, int32_t> column;  // /sensors id → tuple column
  for (int32_t c = 0; c < static_cast<int32_t>(file.sensors.size()); ++c) column[file.sensors[c].id] = c;
  // (column, track) in a tuple of two or more, or in a target (rec.target) of two or more tracks.
  std::set<std::pair<int32_t, int32_t>> linked;
  const int32_t S = rec.num_sensors;
  const bool targets = rec.target.size() == rec.num_tuples();
  std::map<int32_t, std::set<std::pair<int32_t, int32_t>>> of_target;
  for (std::size_t k = 0; k < rec.num_tuples(); ++k) {
    const int32_t* row = rec.tuples.data() + k * S;
    const bool pair = std::count_if(row, row + S, [](int32_t t) { return t >= 0; }) >= 2;
    for (int32_t c = 0; c < S; ++c) {
      if (row[c] < 0) continue;
      if (pair) linked.insert({c, row[c]});
      if (targets) of_target[rec.target[k]].insert({c, row[c]});
    }
  }
  for (const auto& [t, members] : of_target)
    if (members.size() >= 2) linked.insert(members.begin(), members.end());
  std::map<int32_t, std::set<int32_t>> alone;  // associated sensor id → its tracks in no such tuple
  for (int32_t id : sensor_ids) {
    require(column.count(id), "sensor id", "id " + std::to_string(id) + " is not in /sensors/id");
    alone[id];
  }
  // One pass over the rows, each local track looked at once (a hash of the keys seen: the rows of
  // a track need not be adjacent).
  std::unordered_set<uint64_t> seen;
  for (std::size_t r = 0; r < file.tracks.size(); ++r) {
    const int32_t id = file.tracks.sensor[r], track = file.tracks.track[r];
    if (!seen.insert(packed_local_track(id, track)).second) continue;
    auto it = alone.find(id);
    if (it != alone.end() && !linked.count({column.at(id), track})) it->second.insert(track);
  }
  std::vector<UnassociatedTracks> out;
  for (int32_t id : sensor_ids) out.push_back({id, {alone[id].begin(), alone[id].end()}});
  return out;
}

void store_outcome(TrackFile& file, const AssociationOutcome& outcome) {
  const std::string& name = outcome.record.name;
  std::erase_if(file.associations, [&](const AssociationRecord& a) { return a.name == name; });
  std::erase_if(file.fused, [&](const FusedTrackRecord& r) { return r.association == name; });  // stale now
  file.associations.push_back(outcome.record);
  std::vector<int32_t>& rows = file.associations.back().unassociated;  // /associations/<name>/unassociated
  rows.clear();
  for (const UnassociatedTracks& u : outcome.unassociated)
    for (int32_t track : u.tracks) rows.insert(rows.end(), {u.sensor_id, track});
  if (outcome.registration)
    file.registration = outcome.registration;
  else if (file.registration && file.registration->association == name)
    file.registration.reset();  // stale now
  if (outcome.system_tracks) {
    std::erase_if(file.system_tracks,
                  [&](const SystemTrackRecord& r) { return r.name == outcome.system_tracks->name; });
    file.system_tracks.push_back(*outcome.system_tracks);
  }
}

}  // namespace trackassoc
