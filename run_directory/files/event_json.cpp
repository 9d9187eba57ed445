#include "run_directory/files/event_json.h"

#include <array>

#include "simulation/enum_names.h"

namespace poet {

std::string_view solved_by_name(SolvedBy by) {
  static constexpr std::array<std::string_view, 3> kNames = {"admission", "es", "transfer"};
  return enum_name(by, kNames, "?");
}

namespace {

using Json = nlohmann::ordered_json;

Json fields(const SolvedEvent& e) {
  return {{"event", "solved"},
          {"pair", e.pair},
          {"env", e.env},
          {"score", e.score},
          {"iterations_to_solve", e.iterations_to_solve},
          {"by", solved_by_name(e.by)}};
}

Json fields(const ChildEvent& e) {
  Json j = {{"event", "child"}, {"attempt", e.attempt},    {"parent", e.parent}, {"env", e.env},
            {"e", e.e},         {"duplicate", e.duplicate}};
  if (e.mc_score) {
    j["mc_score"] = *e.mc_score;
    j["passed_mc"] = e.passed_mc;
  }
  return j;
}

Json fields(const PairCreatedEvent& e) {
  return {{"event", "pair_created"}, {"pair", e.pair},     {"env", e.env},
          {"seed", e.seed},          {"parent", e.parent}, {"source", e.source},
          {"proposal", e.proposal},  {"score", e.score},   {"novelty", e.novelty}};
}

Json fields(const ReproductionEvent& e) {
  if (e.eligible == 0) return {{"event", "reproduction"}, {"eligible", 0}};
  Json j = {{"event", "reproduction"},    {"eligible", e.eligible},   {"tried", e.tried},
            {"duplicates", e.duplicates}, {"passed_mc", e.passed_mc}, {"admitted", e.admitted}};
  if (e.pata_ec_evaluations) j["pata_ec_evaluations"] = *e.pata_ec_evaluations;
  return j;
}

Json fields(const PairRetiredEvent& e) {
  return {{"event", "pair_retired"}, {"pair", e.pair}, {"env", e.env}, {"solved", e.solved}};
}

Json fields(const TransferEvent& e) {
  return {{"event", "transfer"},    {"target", e.target}, {"source", e.source},
          {"proposal", e.proposal}, {"score", e.score},   {"previous_score", e.previous_score}};
}

Json fields(const TransferRoundEvent& e) {
  Json j = {{"event", "transfer_round"}, {"test", e.full_test ? "full" : "threshold"},
            {"pairs", e.pairs},          {"candidates", e.candidates},
            {"proposals", e.proposals},  {"accepted", e.accepted},
            {"rollouts", e.rollouts}};
  if (e.unconfirmed) j["unconfirmed"] = *e.unconfirmed;  // only with confirm_transfers: other runs' lines unchanged
  return j;
}

Json fields(const StageEvent& e) {
  return {{"event", e.solved ? "stage_solved" : "stage_advanced"},
          {"stage", e.stage},
          {"env", e.env},
          {"distance_to_target", e.distance_to_target}};
}

Json fields(const RunFinishedEvent& e) {
  return {{"event", "run_finished"},
          {"reason", e.target_solved ? "target solved" : "budget spent"},
          {"es_steps", e.es_steps}};
}

}  // namespace

nlohmann::ordered_json event_json(int iteration, const RunEvent& event) {
  Json j = {{"iteration", iteration}};
  const Json rest = std::visit([](const auto& e) { return fields(e); }, event);
  for (const auto& [key, value] : rest.items()) j[key] = value;
  return j;
}

std::vector<nlohmann::ordered_json> events_json(const IterationReport& report) {
  std::vector<nlohmann::ordered_json> out;
  out.reserve(report.events.size());
  for (const RunEvent& event : report.events) out.push_back(event_json(report.iteration, event));
  return out;
}

}  // namespace poet
