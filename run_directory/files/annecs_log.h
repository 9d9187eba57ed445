#pragma once
// annecs.csv: ANNECS in both definitions (poet/annecs.h) at the end of every iteration — a header, then one line
// per iteration, "iteration,annecs_at_admission,annecs_at_archiving", appended as each iteration ends. Every line
// is a function of the state (each pair keeps its first-solved and retired iterations), so the checkpoint records
// nothing of the file: like the pair files, resume writes it again from the state when it differs (a crash after
// a checkpoint leaves lines of iterations the state has not seen).

#include <string>

#include "engine/annecs.h"
#include "engine/run_state.h"

namespace poet {

inline constexpr char kAnnecsFile[] = "annecs.csv";

// The header line and one iteration's line, both with their newline.
std::string annecs_header();
std::string annecs_line(int iteration, const Annecs& annecs);

// The whole file for a state: the header, then a line for each iteration 0 .. next_iteration − 1.
std::string annecs_text(const RunState& state);

}  // namespace poet
