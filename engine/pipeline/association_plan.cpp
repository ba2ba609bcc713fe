#include "engine/pipeline/association_plan.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

AssociationPlan stages(SensorRule sensors, PairSourceStage pairs, ComponentSolverStage solver) {
  const PartitionStage partition = pairs == PairSourceStage::kCandidateIndex
                                       ? PartitionStage::kConnectedComponents
                                   : pairs == PairSourceStage::kAllPairs ? PartitionStage::kWholeProblem
                                                                         : PartitionStage::kByTheMethod;
  return {sensors, pairs, partition, solver};
}

AssociationPlan by_the_method(ComponentSolverStage solver) {
  return stages(SensorRule::kTwoOrMore, PairSourceStage::kByTheMethod, solver);
}

// The rules of the header, stage by stage.
AssociationPlan plan_by_rules(const AssociatorOptions& o) {
  const bool explicit_pipeline = o.sd || o.three_d || o.sparse;
  const bool fusion = o.solver == "fuzzy" || o.solver == "ftaa";
  const bool special = fusion || o.solver == "siamese";
  const std::size_t n_sensors = o.pipeline.sensors.size();
  const auto& sparse_sd = sparse_sd_solver_names();
  // --sensors selects sensors, never a stage: any number of them stays on the default stages.
  if (!explicit_pipeline && !special &&
      std::find(sparse_sd.begin(), sparse_sd.end(), o.solver) != sparse_sd.end())
    return stages(SensorRule::kTwoOrMore, PairSourceStage::kCandidateIndex, ComponentSolverStage::kSDTensor);
  if (fusion) {  // not a 3-D tensor solver (seed 001)
    if (o.sparse)
      throw InputError("--sparse: applies to the 3-D assignment solvers, not to '" + o.solver + "'");
    return by_the_method(ComponentSolverStage::kFusionCentre);
  }
  // Seed 003's Siamese classifier takes two sensors' plot sequences, named by --sensors or not.
  if (o.solver == "siamese" && !o.sd) return by_the_method(ComponentSolverStage::kSiamese);
  if (o.sd || o.solver == "chnn-pseudo" || n_sensors > 3 || n_sensors == 2) {
    if (o.sparse)
      throw InputError("--sparse: applies to the three-sensor pipeline, not to the S-D formulation (--sd)");
    require_sd_solver(o.solver);  // fail on an unknown name before reading anything
    return stages(SensorRule::kTwoOrMore, PairSourceStage::kAllPairs, ComponentSolverStage::kSDTensor);
  }
  find_solver(o.solver);  // fail on an unknown name before reading anything
  return stages(SensorRule::kThree, o.sparse ? PairSourceStage::kCandidateIndex : PairSourceStage::kAllPairs,
                ComponentSolverStage::kTensor3D);
}

// The combinations of stages that a path implements, one row each: path() and plan_of read it
// both ways.
struct Implementation {
  AssociationPath path;
  AssociationPlan plan;
};
const std::array<Implementation, 6>& implementations() {
  using P = AssociationPath;
  using Pairs = PairSourceStage;
  using Solver = ComponentSolverStage;
  static const std::array<Implementation, 6> rows{{
      {P::kSparseSD, stages(SensorRule::kTwoOrMore, Pairs::kCandidateIndex, Solver::kSDTensor)},
      {P::kDenseSD, stages(SensorRule::kTwoOrMore, Pairs::kAllPairs, Solver::kSDTensor)},
      {P::kDense3D, stages(SensorRule::kThree, Pairs::kAllPairs, Solver::kTensor3D)},
      {P::kSparse3D, stages(SensorRule::kThree, Pairs::kCandidateIndex, Solver::kTensor3D)},
      {P::kFusionCentre, by_the_method(Solver::kFusionCentre)},
      {P::kSiamese, by_the_method(Solver::kSiamese)},
  }};
  return rows;
}

}  // namespace

AssociationPath AssociationPlan::path() const {
  for (const Implementation& row : implementations())
    if (row.plan == *this) return row.path;
  throw InputError("association plan: no path runs " + describe());
}

std::string AssociationPlan::describe() const {
  switch (solver) {
    case ComponentSolverStage::kFusionCentre:
      return "every sensor -> seed 001's fusion centre (temporary tracks, fuzzy association)";
    case ComponentSolverStage::kSiamese:
      return "two sensors -> seed 003's Siamese classifier on every pair -> LAP";
    case ComponentSolverStage::kSDTensor:
    case ComponentSolverStage::kTensor3D:
      break;
  }
  std::string text = sensors == SensorRule::kThree ? "three sensors" : "every sensor (or --sensors)";
  text += pairs == PairSourceStage::kCandidateIndex ? " -> per-scan candidate index" : " -> all pairs";
  text += partition == PartitionStage::kConnectedComponents ? " -> connected components"
                                                            : " -> the whole problem";
  text += solver == ComponentSolverStage::kSDTensor ? " -> S-D tensor with dummies" : " -> 3-D tensor";
  return text;
}

AssociationPlan choose_association_plan(const AssociatorOptions& o) {
  o.validate();
  const AssociationPlan plan = plan_by_rules(o);
  if (plan.path() != AssociationPath::kSparse3D && std::isfinite(o.miss_cost))
    throw InputError("miss_cost: applies to the sparse three-sensor path (--sparse) only");
  return plan;
}

AssociationPlan plan_of(AssociationPath path) {
  for (const Implementation& row : implementations())
    if (row.path == path) return row.plan;
  throw InputError("association path: unknown");
}

}  // namespace trackassoc
