// The stages an association request runs (docs/design.md §4, "An association is one pipeline of
// stages"): choose_association_plan picks each stage from the request, and the plan's path is the
// associator (engine/pipeline/associator.hpp) that runs that combination.
//
//   front end        SensorRule::kThree for the 3-D tensor, kTwoOrMore for every other solver
//                    (engine/pipeline/front_end.hpp); --sensors selects sensors, never a stage
//   pair source      the per-scan candidate index (the default path and --sparse) or all pairs
//                    (--sd, --3d, and a solver of the whole problem: chnn-pseudo, the 3-D
//                    Hopfield and greedy solvers without --sparse); engine/pipeline/pair_source.hpp
//   partition        connected components of the gated pair graph after the index, the whole
//                    problem after all pairs (engine/pipeline/partition.hpp)
//   component solver the S-D tensor with dummies (the S-D solvers), the 3-D tensor (the 3-D
//                    solvers, or an S-D solver with --3d), or a method that pairs and partitions by
//                    itself: seed 001's fusion centre, seed 003's Siamese classifier
//
// The rules, in order: fuzzy and ftaa → fusion centre (no --sparse); siamese without --sd →
// Siamese; an S-D solver of the default path (lr+ls, lr, exact) without --sd, --3d, --sparse →
// S-D tensor over the index; --sd, chnn-pseudo, or two or more than three --sensors → S-D tensor
// over all pairs (no --sparse); otherwise the 3-D tensor, over the index with --sparse, else over
// all pairs. The solver name is checked against the chosen component solver before any file is read.
#pragma once

#include <string>

#include "engine/pipeline/front_end.hpp"

namespace trackassoc {

struct AssociatorOptions;  // engine/pipeline/associator.hpp

// The associator that runs a plan (one implementation each, engine/pipeline/associators.cpp).
enum class AssociationPath { kSparseSD, kDenseSD, kDense3D, kSparse3D, kFusionCentre, kSiamese };

enum class PairSourceStage {
  kCandidateIndex,  // per-scan candidate index, then the gate (the sparse paths)
  kAllPairs,        // every pair of two sensors' tracks, then the gate (the dense paths)
  kByTheMethod,     // the fusion centre and the Siamese classifier pair tracks themselves
};
enum class PartitionStage {
  kConnectedComponents,  // of the gated pair graph
  kWholeProblem,         // one component
  kByTheMethod,
};
enum class ComponentSolverStage { kSDTensor, kTensor3D, kFusionCentre, kSiamese };

struct AssociationPlan {
  SensorRule sensors = SensorRule::kTwoOrMore;
  PairSourceStage pairs = PairSourceStage::kCandidateIndex;
  PartitionStage partition = PartitionStage::kConnectedComponents;
  ComponentSolverStage solver = ComponentSolverStage::kSDTensor;

  bool operator==(const AssociationPlan&) const = default;
  // The associator of this combination of stages; throws InputError for one that no path runs.
  AssociationPath path() const;
  // "every sensor -> candidate index -> connected components -> S-D tensor with dummies".
  std::string describe() const;
};

// The stages of `options` by the rules above; validates the request and the solver name first.
// Throws InputError with the rule's message on a combination no path runs (--sparse with an S-D
// or fusion solver, a finite miss cost off --sparse).
AssociationPlan choose_association_plan(const AssociatorOptions& options);

// The stages a path runs (the inverse of AssociationPlan::path).
AssociationPlan plan_of(AssociationPath path);

}  // namespace trackassoc
