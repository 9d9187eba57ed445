// Tests run_directory/files/phase_timer.cpp on a fake clock: each phase gets the time until the next begins or the
// iteration ends, time between iterations counts for none, and take() starts the count again.

#include "run_directory/files/phase_timer.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

TEST(PhaseTimer, EachPhaseGetsTheTimeUntilTheNextBegins) {
  double now = 10;
  PhaseTimer timer([&] { return now; });
  timer.phase_begins(IterationPhase::kReproduction);
  now = 12;
  timer.phase_begins(IterationPhase::kEsSteps);
  now = 17;
  timer.phase_begins(IterationPhase::kEvaluations);
  now = 17.5;
  timer.phase_begins(IterationPhase::kTransfer);
  now = 20;
  timer.iteration_ends();
  now = 25;  // saving the checkpoint: no phase
  timer.phase_begins(IterationPhase::kEsSteps);
  now = 26;
  timer.phase_begins(IterationPhase::kEvaluations);
  now = 26.25;
  timer.iteration_ends();
  EXPECT_EQ(timer.take(), (PhaseSeconds{2, 6, 0.75, 2.5}));
  EXPECT_EQ(timer.take(), (PhaseSeconds{0, 0, 0, 0}));
}

}  // namespace
}  // namespace poet
