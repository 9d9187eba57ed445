#include "run_directory/files/checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/formats/envgen/env_proto.h"
#include "common/program/build_fingerprint.h"
#include "common/program/command_line.h"
#include "common/text/text_format.h"
#include "common/text/utf8.h"
#include "engine/state_consistency.h"
#include "run_directory/config/run_config.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

// ------------------------------------------------------------------------------------------------------------
// State → message.

void copy_values(const std::vector<double>& from, google::protobuf::RepeatedField<double>* to) {
  to->Reserve(static_cast<int>(from.size()));
  for (double x : from) to->Add(x);
}

std::vector<double> values(const google::protobuf::RepeatedField<double>& from) {
  return std::vector<double>(from.begin(), from.end());
}

pb::OptimizerState to_proto(const OptimizerState& state) {
  pb::OptimizerState out;
  copy_values(state.m, out.mutable_m());
  copy_values(state.v, out.mutable_v());
  out.set_t(state.t);
  out.set_lr(state.lr);
  out.set_sigma(state.sigma);
  return out;
}

pb::PairState to_proto(const Pair& pair) {
  pb::PairState out;
  out.set_id(pair.id);
  *out.mutable_env() = to_proto(pair.env);
  out.set_created_iteration(pair.created_iteration);
  out.set_parent_id(pair.parent_id);
  out.set_initial_source_pair(pair.initial_source_pair);
  out.set_initial_by_proposal(pair.initial_by_proposal);
  out.set_admission_score(pair.admission_score);
  copy_values(pair.theta, out.mutable_theta());
  *out.mutable_optimizer() = to_proto(pair.optimizer);
  out.set_latest_score(pair.latest_score);
  out.set_latest_finished(pair.latest_finished);
  out.set_best_score(pair.best_score);
  copy_values(pair.best_theta, out.mutable_best_theta());
  out.set_best_iteration(pair.best_iteration);
  out.set_first_solved_iteration(pair.first_solved_iteration);
  out.set_retired_iteration(pair.retired_iteration);
  out.set_es_steps(pair.es_steps);
  out.set_es_env_steps(pair.es_env_steps);
  for (const TransferRecord& record : pair.transfers) {
    pb::TransferRecord* r = out.add_transfers();
    r->set_iteration(record.iteration);
    r->set_source_pair(record.source_pair);
    r->set_proposal(record.proposal);
    r->set_score(record.score);
  }
  out.set_transfer_attempts(pair.transfer_attempts);
  copy_values(pair.recent_scores, out.mutable_recent_scores());
  return out;
}

pb::RunCounters to_proto(const RunCounters& counters) {
  pb::RunCounters out;
  out.set_rollouts(counters.rollouts);
  out.set_env_steps(counters.env_steps);
  out.set_transfer_attempts(counters.transfer_attempts);
  out.set_transfer_successes(counters.transfer_successes);
  out.set_children_tried(counters.children_tried);
  out.set_children_passed_mc(counters.children_passed_mc);
  out.set_children_admitted(counters.children_admitted);
  return out;
}

// ------------------------------------------------------------------------------------------------------------
// Message → state, checked. Each check returns the first problem as "field: what is wrong".

using Error = std::optional<std::string>;

Error check_finite(const std::string& field, double value) {
  if (std::isfinite(value)) return std::nullopt;
  return field + ": must be finite (got " + number_text(value) + ")";
}

// The learning rate and σ decay toward floors that may be 0, never below.
Error check_non_negative(const std::string& field, double value) {
  if (std::isfinite(value) && value >= 0) return std::nullopt;
  return field + ": must be finite and >= 0 (got " + number_text(value) + ")";
}

Error check_at_least(const std::string& field, int64_t value, int64_t lo) {
  if (value >= lo) return std::nullopt;
  return field + ": must be >= " + number_text(lo) + " (got " + number_text(value) + ")";
}

// An iteration that is either kNone or one the run has reached (t <= next_iteration).
Error check_iteration_or_none(const std::string& field, int value, int next_iteration) {
  if (value == kNone || (value >= 0 && value <= next_iteration)) return std::nullopt;
  return field + ": must be -1 or in [0, " + number_text(int64_t{next_iteration}) + "] (got " +
         number_text(int64_t{value}) + ")";
}

// kParamCount finite values, and none negative when non_negative (Adam's second moment is a mean of squares).
Error check_params(const std::string& field, const google::protobuf::RepeatedField<double>& params,
                   bool non_negative = false) {
  if (params.size() != kParamCount)
    return field + ": " + number_text(int64_t{params.size()}) + " values, expected " +
           number_text(int64_t{kParamCount});
  for (int i = 0; i < params.size(); ++i) {
    if (!std::isfinite(params[i]) || (non_negative && params[i] < 0))
      return field + "[" + number_text(int64_t{i}) + "]: must be " + (non_negative ? "finite and >= 0" : "finite") +
             " (got " + number_text(params[i]) + ")";
  }
  return std::nullopt;
}

Expected<EnvDef> read_env(const std::string& field, bool present, const pb::EnvDef& message) {
  if (!present) return Unexpected{field + ": missing"};
  Expected<EnvDef> env = env_def_from_proto(message);
  if (!env) return Unexpected{field + "." + env.error()};
  return env;
}

Expected<OptimizerState> read_optimizer(const std::string& field, const pb::PairState& pair) {
  if (!pair.has_optimizer()) return Unexpected{field + ": missing"};
  const pb::OptimizerState& message = pair.optimizer();
  Error error = check_params(field + ".m", message.m());
  if (!error) error = check_params(field + ".v", message.v(), /*non_negative=*/true);
  if (!error) error = check_at_least(field + ".t", message.t(), 0);
  if (!error) error = check_non_negative(field + ".lr", message.lr());
  if (!error) error = check_non_negative(field + ".sigma", message.sigma());
  if (error) return Unexpected{*error};
  OptimizerState state;
  state.m = values(message.m());
  state.v = values(message.v());
  state.t = message.t();
  state.lr = message.lr();
  state.sigma = message.sigma();
  return state;
}

// One pair, except references to other pairs (checked once all ids are known).
Expected<Pair> read_pair(const std::string& field, const pb::PairState& message, int next_iteration) {
  Pair pair;
  if (!message.has_id()) return Unexpected{field + ".id: missing"};
  pair.id = message.id();
  Expected<EnvDef> env = read_env(field + ".env", message.has_env(), message.env());
  if (!env) return Unexpected{env.error()};
  pair.env = std::move(*env);

  Error error = check_iteration_or_none(field + ".created_iteration", message.created_iteration(), next_iteration);
  if (!error && message.created_iteration() < 0) error = field + ".created_iteration: must be >= 0 (got -1)";
  if (!error) error = check_finite(field + ".admission_score", message.admission_score());
  if (!error) error = check_params(field + ".theta", message.theta());
  if (!error) error = check_finite(field + ".latest_score", message.latest_score());
  if (!error) error = check_finite(field + ".best_score", message.best_score());
  if (!error) error = check_params(field + ".best_theta", message.best_theta());
  if (!error) error = check_iteration_or_none(field + ".best_iteration", message.best_iteration(), next_iteration);
  if (!error)
    error =
        check_iteration_or_none(field + ".first_solved_iteration", message.first_solved_iteration(), next_iteration);
  if (!error)
    error = check_iteration_or_none(field + ".retired_iteration", message.retired_iteration(), next_iteration);
  if (!error) error = check_at_least(field + ".es_steps", message.es_steps(), 0);
  if (!error) error = check_at_least(field + ".es_env_steps", message.es_env_steps(), 0);
  if (!error) error = check_at_least(field + ".transfer_attempts", message.transfer_attempts(), 0);
  if (!error && static_cast<size_t>(message.recent_scores_size()) > kRecentScores)
    error = field + ".recent_scores: " + number_text(int64_t{message.recent_scores_size()}) + " scores, at most " +
            number_text(static_cast<int64_t>(kRecentScores));
  for (int i = 0; !error && i < message.recent_scores_size(); ++i)
    error = check_finite(field + ".recent_scores[" + number_text(int64_t{i}) + "]", message.recent_scores(i));
  if (error) return Unexpected{*error};

  Expected<OptimizerState> optimizer = read_optimizer(field + ".optimizer", message);
  if (!optimizer) return Unexpected{optimizer.error()};
  pair.optimizer = std::move(*optimizer);

  for (int i = 0; i < message.transfers_size(); ++i) {
    const pb::TransferRecord& record = message.transfers(i);
    const std::string path = field + ".transfers[" + number_text(int64_t{i}) + "]";
    error = check_iteration_or_none(path + ".iteration", record.iteration(), next_iteration);
    if (!error && record.iteration() < 0) error = path + ".iteration: must be >= 0 (got -1)";
    if (!error) error = check_finite(path + ".score", record.score());
    if (error) return Unexpected{*error};
    pair.transfers.push_back({record.iteration(), record.source_pair(), record.proposal(), record.score()});
  }

  pair.created_iteration = message.created_iteration();
  pair.parent_id = message.parent_id();
  pair.initial_source_pair = message.initial_source_pair();
  pair.initial_by_proposal = message.initial_by_proposal();
  pair.admission_score = message.admission_score();
  pair.theta = values(message.theta());
  pair.latest_score = message.latest_score();
  pair.latest_finished = message.latest_finished();
  pair.best_score = message.best_score();
  pair.best_theta = values(message.best_theta());
  pair.best_iteration = message.best_iteration();
  pair.first_solved_iteration = message.first_solved_iteration();
  pair.retired_iteration = message.retired_iteration();
  pair.es_steps = message.es_steps();
  pair.es_env_steps = message.es_env_steps();
  pair.transfer_attempts = message.transfer_attempts();
  pair.recent_scores = values(message.recent_scores());
  return pair;
}

// Lineage and transfers name pairs of the archive; the engine looks them up, so a dangling id is refused here.
Error check_references(const std::vector<Pair>& pairs) {
  std::set<int> ids;
  for (const Pair& p : pairs) ids.insert(p.id);
  auto dangling = [&](int id) { return id != kNone && !ids.contains(id); };
  for (size_t i = 0; i < pairs.size(); ++i) {
    const Pair& p = pairs[i];
    const std::string field = "pairs[" + std::to_string(i) + "]";
    if (dangling(p.parent_id)) return field + ".parent_id: no pair has id " + number_text(int64_t{p.parent_id});
    if (dangling(p.initial_source_pair))
      return field + ".initial_source_pair: no pair has id " + number_text(int64_t{p.initial_source_pair});
    for (size_t k = 0; k < p.transfers.size(); ++k) {
      if (p.transfers[k].source_pair == kNone || dangling(p.transfers[k].source_pair))
        return field + ".transfers[" + std::to_string(k) + "].source_pair: no pair has id " +
               number_text(int64_t{p.transfers[k].source_pair});
    }
  }
  return std::nullopt;
}

Expected<RunCounters> read_counters(const pb::RunCounters& message) {
  const std::pair<const char*, int64_t> fields[] = {
      {"rollouts", message.rollouts()},
      {"env_steps", message.env_steps()},
      {"transfer_attempts", message.transfer_attempts()},
      {"transfer_successes", message.transfer_successes()},
      {"children_tried", message.children_tried()},
      {"children_passed_mc", message.children_passed_mc()},
      {"children_admitted", message.children_admitted()},
  };
  for (const auto& [name, value] : fields) {
    if (Error error = check_at_least(std::string("counters.") + name, value, 0)) return Unexpected{*error};
  }
  RunCounters counters;
  counters.rollouts = message.rollouts();
  counters.env_steps = message.env_steps();
  counters.transfer_attempts = message.transfer_attempts();
  counters.transfer_successes = message.transfer_successes();
  counters.children_tried = message.children_tried();
  counters.children_passed_mc = message.children_passed_mc();
  counters.children_admitted = message.children_admitted();
  return counters;
}

}  // namespace

pb::Checkpoint to_checkpoint(const pb::RunConfig& config, const RunState& state) {
  pb::Checkpoint out;
  *out.mutable_config() = config;
  out.set_next_iteration(state.next_iteration);
  out.set_next_pair_id(state.next_pair_id);
  for (const Pair& pair : state.pairs) *out.add_pairs() = to_proto(pair);
  *out.mutable_counters() = to_proto(state.counters);
  for (const CurriculumStage& stage : state.stages) {
    pb::DirectPathStage* s = out.add_stages();
    *s->mutable_env() = to_proto(stage.env);
    s->set_started_iteration(stage.started_iteration);
    s->set_solved_iteration(stage.solved_iteration);
  }
  out.set_finished(state.finished);
  out.set_arithmetic_digest(arithmetic_digest());
  return out;
}

Expected<RunState> from_checkpoint(const pb::Checkpoint& checkpoint) {
  RunState state;

  // the config and the counters of the loop; an empty message (an empty file) fails here
  if (!checkpoint.has_config()) return Unexpected{"config: missing"};
  if (Error error = validate(checkpoint.config())) return Unexpected{"config." + *error};
  state.settings = run_settings(checkpoint.config());
  if (!checkpoint.has_next_iteration()) return Unexpected{"next_iteration: missing"};
  if (checkpoint.next_iteration() < 0 || checkpoint.next_iteration() > kMaxIterations)
    return Unexpected{"next_iteration: must be in [0, " + number_text(int64_t{kMaxIterations}) + "] (got " +
                      number_text(int64_t{checkpoint.next_iteration()}) + ")"};
  state.next_iteration = checkpoint.next_iteration();
  if (!checkpoint.has_next_pair_id()) return Unexpected{"next_pair_id: missing"};
  state.next_pair_id = checkpoint.next_pair_id();
  state.finished = checkpoint.finished();

  // the archive: ids strictly increasing (creation order), all below next_pair_id
  if (checkpoint.pairs_size() == 0) return Unexpected{"pairs: none (a run always holds its first pair)"};
  for (int i = 0; i < checkpoint.pairs_size(); ++i) {
    const std::string field = "pairs[" + std::to_string(i) + "]";
    Expected<Pair> pair = read_pair(field, checkpoint.pairs(i), state.next_iteration);
    if (!pair) return Unexpected{pair.error()};
    if (pair->id < 0) return Unexpected{field + ".id: must be >= 0 (got " + std::to_string(pair->id) + ")"};
    if (!state.pairs.empty() && pair->id <= state.pairs.back().id)
      return Unexpected{field + ".id: " + std::to_string(pair->id) + " does not follow the previous pair's id " +
                        std::to_string(state.pairs.back().id) + " (ids are unique and increasing)"};
    state.pairs.push_back(std::move(*pair));
  }
  if (state.next_pair_id <= state.pairs.back().id)
    return Unexpected{"next_pair_id: " + std::to_string(state.next_pair_id) + " must exceed every pair id (largest " +
                      std::to_string(state.pairs.back().id) + ")"};
  if (Error error = check_references(state.pairs)) return Unexpected{*error};

  Expected<RunCounters> counters = read_counters(checkpoint.counters());
  if (!counters) return Unexpected{counters.error()};
  state.counters = *counters;

  for (int i = 0; i < checkpoint.stages_size(); ++i) {
    const pb::DirectPathStage& message = checkpoint.stages(i);
    const std::string field = "stages[" + std::to_string(i) + "]";
    Expected<EnvDef> env = read_env(field + ".env", message.has_env(), message.env());
    if (!env) return Unexpected{env.error()};
    Error error =
        check_iteration_or_none(field + ".started_iteration", message.started_iteration(), state.next_iteration);
    if (!error && message.started_iteration() < 0) error = field + ".started_iteration: must be >= 0 (got -1)";
    if (!error)
      error = check_iteration_or_none(field + ".solved_iteration", message.solved_iteration(), state.next_iteration);
    if (error) return Unexpected{*error};
    state.stages.push_back({std::move(*env), message.started_iteration(), message.solved_iteration()});
  }
  if (Error error = check_state_consistency(state)) return Unexpected{*error};
  return state;
}

namespace {

// The paths of the unknown fields in message and the messages it holds: "field 13", "pairs[0] field 22".
void collect_unknown_fields(const google::protobuf::Message& message, const std::string& path,
                            std::vector<std::string>& out) {
  const google::protobuf::Reflection* reflection = message.GetReflection();
  const google::protobuf::UnknownFieldSet& unknown = reflection->GetUnknownFields(message);
  std::set<int> numbers;  // a repeated field comes once per value
  for (int i = 0; i < unknown.field_count(); ++i) numbers.insert(unknown.field(i).number());
  for (int number : numbers) out.push_back((path.empty() ? "" : path + " ") + "field " + std::to_string(number));
  std::vector<const google::protobuf::FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);
  for (const google::protobuf::FieldDescriptor* field : fields) {
    if (field->cpp_type() != google::protobuf::FieldDescriptor::CPPTYPE_MESSAGE) continue;
    const std::string name = (path.empty() ? "" : path + ".") + std::string(field->name());
    if (!field->is_repeated()) {
      collect_unknown_fields(reflection->GetMessage(message, field), name, out);
      continue;
    }
    for (int i = 0; i < reflection->FieldSize(message, field); ++i)
      collect_unknown_fields(reflection->GetRepeatedMessage(message, field, i), name + "[" + std::to_string(i) + "]",
                             out);
  }
}

}  // namespace

std::optional<std::string> unknown_fields_refusal(const pb::Checkpoint& checkpoint) {
  std::vector<std::string> paths;
  collect_unknown_fields(checkpoint, "", paths);
  if (paths.empty()) return std::nullopt;
  constexpr size_t kNamed = 5;
  std::string named;
  for (size_t i = 0; i < std::min(paths.size(), kNamed); ++i) named += (i == 0 ? "" : ", ") + paths[i];
  if (paths.size() > kNamed) named += " and " + std::to_string(paths.size() - kNamed) + " more";
  const std::string ours = std::string("poet ") + project_version();
  const std::string writer = checkpoint.has_written_by()
                                 ? "poet " + printable_text(checkpoint.written_by().substr(0, 40))
                                 : std::string("a later build");
  return "the checkpoint holds fields this build does not know (" + named + "): it was written by " + writer +
         ", this build is " + ours + ". Resumed here the run would drop them and go on as another run: go on with " +
         (checkpoint.has_written_by() ? writer + " or later" : std::string("the build that wrote it"));
}

std::optional<std::string> arithmetic_refusal(std::optional<uint64_t> written_by) {
  if (!written_by)
    return "the checkpoint was written by a build before the project computed its own exp, log, sin and cos (it "
           "used the C library's, whose last bits vary between processors and C libraries): resumed by this build "
           "it would go on as another run. Finish it with the build that wrote it, or start it again";
  if (*written_by != arithmetic_digest())
    return "this machine computes differently from the one that wrote the checkpoint: arithmetic digest " +
           hex_text(arithmetic_digest()) + " (" + arithmetic_text() + "), the checkpoint's " + hex_text(*written_by) +
           ": resumed here it would go on as another run (compare the arithmetic line of --fingerprint)";
  return std::nullopt;
}

}  // namespace poet
