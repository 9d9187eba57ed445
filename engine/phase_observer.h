#pragma once
// The phases of an iteration, announced as each begins, for whoever times them: the engine keeps no clock (its
// runs are functions of their config), the coordinator measures where a run's time goes.

namespace poet {

enum class IterationPhase {
  kReproduction,  // the children's minimal-criterion evaluations, novelty and the admission walk
  kEsSteps,       // every active pair's perturbed rollouts
  kEvaluations,   // the evaluation of each new θ on its own environment
  kTransfer,      // a transfer round
};
inline constexpr int kIterationPhases = 4;

class PhaseObserver {
 public:
  virtual ~PhaseObserver() = default;
  // A phase begins, ending the one before it (an iteration's phases come in the order above; some are skipped).
  virtual void phase_begins(IterationPhase phase) = 0;
  // The iteration's last phase has ended.
  virtual void iteration_ends() = 0;
};

}  // namespace poet
