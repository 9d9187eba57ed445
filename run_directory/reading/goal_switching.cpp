#include "run_directory/reading/goal_switching.h"

#include <algorithm>
#include <array>

#include "run_directory/files/event_json.h"
#include "run_directory/reading/event_fields.h"
#include "simulation/enum_names.h"

namespace poet {
namespace {

// What solved a pair: its "solved" event's "by", recorded by the engine with the evaluation. A log written before
// the engine recorded it (or with a "by" not known here) says it by order instead: the engine writes an evaluation's
// solve right after the event it followed ("pair_created" at admission, "transfer" for a transfer; alone after an ES
// step).
SolveCause cause_of(const RunSnapshot& run, const Pair& pair) {
  if (!pair.solved()) return SolveCause::kNotSolved;
  const nlohmann::json* previous = nullptr;
  for (const nlohmann::json& event : run.events) {
    // read_run_snapshot guarantees every event an integer "iteration" and a string "event"
    if (event["iteration"].get<int>() == pair.first_solved_iteration && event["event"] == "solved" &&
        field_or(event, "pair", kNone) == pair.id) {
      const std::string by = field_or(event, "by", std::string());
      if (by == solved_by_name(SolvedBy::kAdmission)) return SolveCause::kAdmission;
      if (by == solved_by_name(SolvedBy::kTransfer)) return SolveCause::kTransfer;
      if (by == solved_by_name(SolvedBy::kOwnEs)) return SolveCause::kOwnEs;
      if (previous && (*previous)["iteration"] == event["iteration"]) {
        if ((*previous)["event"] == "transfer" && field_or(*previous, "target", kNone) == pair.id)
          return SolveCause::kTransfer;
        if ((*previous)["event"] == "pair_created" && field_or(*previous, "pair", kNone) == pair.id)
          return SolveCause::kAdmission;
      }
      return SolveCause::kOwnEs;
    }
    previous = &event;
  }
  // a run whose events do not record the solve: the first pair's first evaluation follows its ES step
  return SolveCause::kOwnEs;
}

}  // namespace

const char* to_string(SolveCause cause) {
  static constexpr std::array<std::string_view, 4> kNames = {"not solved", "at admission", "by its own ES",
                                                             "by a transfer"};
  return enum_name(cause, kNames, "?").data();
}

std::vector<LineageLink> lineage_chain(const RunSnapshot& run, const RunMetrics& metrics, int pair_id) {
  std::vector<LineageLink> chain;
  for (const Pair* pair = run.state.find(pair_id); pair && chain.size() <= run.state.pairs.size();
       pair = run.state.find(pair->parent_id)) {
    LineageLink link;
    link.pair = pair->id;
    link.env = pair->env.encoding.name;
    link.level = static_cast<int>(difficulty(pair->env.encoding));
    link.created = pair->created_iteration;
    link.parent = pair->parent_id;
    link.first_theta_from = pair->initial_source_pair;
    link.first_by_proposal = pair->initial_by_proposal;
    link.admission_score = pair->admission_score;
    link.solved = pair->first_solved_iteration;
    link.cause = cause_of(run, *pair);
    for (const AcceptedTransfer& t : metrics.accepted_transfers)
      if (t.target == pair->id) link.transfers_in.push_back(t);
    if (link.cause == SolveCause::kAdmission) link.solved_by = pair->initial_source_pair;
    if (link.cause == SolveCause::kTransfer)
      for (const AcceptedTransfer& t : link.transfers_in)
        if (t.iteration == link.solved) link.solved_by = t.source;
    const bool started_elsewhere = pair->parent_id != kNone && pair->initial_source_pair != pair->parent_id;
    // a transfer in the iteration of the solve came after it (transfers follow the ES steps) unless it solved
    const bool took_transfer = link.cause == SolveCause::kTransfer ||
                               std::any_of(link.transfers_in.begin(), link.transfers_in.end(),
                                           [&](const AcceptedTransfer& t) { return t.iteration < link.solved; });
    link.solved_through_transfer = pair->solved() && (started_elsewhere || took_transfer);
    chain.push_back(std::move(link));  // the size bound above: a damaged state's parent cycle cannot loop
  }
  std::reverse(chain.begin(), chain.end());
  return chain;
}

}  // namespace poet
