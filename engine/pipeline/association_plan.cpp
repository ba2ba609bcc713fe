#include "engine/pipeline/association_plan.hpp"

#include <algorithm>
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

}  // namespace

AssociationPath AssociationPlan::path() const {
  switch (solver) {
    case ComponentSolverStage::kFusionCentre:
      return AssociationPath::kFusionCentre;
    case ComponentSolverStage::kSiamese:
      return AssociationPath::kSiamese;
    case ComponentSolverStage::kSDTensor:
      return pairs == PairSourceStage::kCandidateIndex ? AssociationPath::kSparseSD
                                                       : AssociationPath::kDenseSD;
    case ComponentSolverStage::kTensor3D:
      return pairs == PairSourceStage::kCandidateIndex ? AssociationPath::kSparse3D
                                                       : AssociationPath::kDense3D;
  }
  throw InputError("association plan: unknown component solver");
}

std::string AssociationPlan::describe() const {
  std::string text;
  switch (solver) {
    case ComponentSolverStage::kFusionCentre:
      return "every sensor -> seed 001's fusion centre (temporary tracks, fuzzy association)";
    case ComponentSolverStage::kSiamese:
      return "two sensors -> seed 003's Siamese classifier on every pair -> LAP";
    case ComponentSolverStage::kSDTensor:
    case ComponentSolverStage::kTensor3D:
      break;
  }
  text = sensors == SensorRule::kThree ? "three sensors" : "every sensor (or --sensors)";
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
  switch (path) {
    case AssociationPath::kSparseSD:
      return stages(SensorRule::kTwoOrMore, PairSourceStage::kCandidateIndex,
                    ComponentSolverStage::kSDTensor);
    case AssociationPath::kDenseSD:
      return stages(SensorRule::kTwoOrMore, PairSourceStage::kAllPairs, ComponentSolverStage::kSDTensor);
    case AssociationPath::kDense3D:
      return stages(SensorRule::kThree, PairSourceStage::kAllPairs, ComponentSolverStage::kTensor3D);
    case AssociationPath::kSparse3D:
      return stages(SensorRule::kThree, PairSourceStage::kCandidateIndex, ComponentSolverStage::kTensor3D);
    case AssociationPath::kFusionCentre:
      return by_the_method(ComponentSolverStage::kFusionCentre);
    case AssociationPath::kSiamese:
      return by_the_method(ComponentSolverStage::kSiamese);
  }
  throw InputError("association path: unknown");
}

}  // namespace trackassoc
