#include "run_directory/config/run_config.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/message.h>
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/formats/envgen/env_proto.h"
#include "common/plumbing/text_file.h"
#include "common/text/text_format.h"
#include "run_directory/config/config_rules.h"

namespace poet {
namespace {

namespace protobuf = google::protobuf;

// Keeps the parser's first error with its position; later errors are usually consequences of the first.
class FirstErrorCollector : public protobuf::io::ErrorCollector {
 public:
  void AddError(int line, protobuf::io::ColumnNumber column, const std::string& message) override {
    if (error_) return;
    // At the end of the text the parser names an empty token ("Expected identifier, got: ").
    const std::string what = message.ends_with("got: ") ? message + "end of text" : message;
    // The parser counts from 0 and gives -1 for errors not tied to a place in the text.
    if (line < 0) {
      error_ = what;
    } else {
      error_ = "line " + std::to_string(line + 1) + ":" + std::to_string(column + 1) + ": " + what;
    }
  }
  void AddWarning(int, protobuf::io::ColumnNumber, const std::string&) override {}

  const std::optional<std::string>& error() const { return error_; }

 private:
  std::optional<std::string> error_;
};

// Shortest form that reads back to the same double, so a message shows exactly the value that was refused.

constexpr double kInf = std::numeric_limits<double>::infinity();

// A range of a real field; an infinite bound is no bound.
struct Range {
  double lo = -kInf;
  double hi = kInf;
  bool lo_open = false;
  bool hi_open = false;

  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi); }
  std::string describe() const {
    if (hi == kInf)
      return lo == -kInf ? "must be a finite number" : (lo_open ? "must be > " : "must be >= ") + number_text(lo);
    if (lo == -kInf) return (hi_open ? "must be < " : "must be <= ") + number_text(hi);
    return std::string("must be in ") + (lo_open ? "(" : "[") + number_text(lo) + ", " + number_text(hi) +
           (hi_open ? ")" : "]");
  }
};

constexpr Range kNonNegative{0, kInf, false, false};
constexpr Range kDecay{0, 1, true, false};  // (0, 1]: 1 turns the decay off
constexpr Range kBeta{0, 1, false, true};   // [0, 1): Adam divides by 1 − βᵗ
// Scores are episode returns: the shaping telescopes to 130·Δx/SCALE (about 360 over a finished course), a fall
// scores −100 and the torque cost is at most 0.112 a step (224 over 2000 steps), so a return lies within a few
// hundred of zero (spec §1); a threshold beyond ±10^4 is a typo.
constexpr Range kScore{-1e4, 1e4};

// Collects the first problem; later checks are skipped once one is found, so the message names the first bad
// field in the order the checks run (the schema's order). In recording mode (config_rules()) each check records
// its rule, in the text its message gives without the value, and none fails.
class Checks {
 public:
  Checks() = default;
  Checks(std::vector<ConfigRule>* rules, pb::RunConfig::Mode mode) : rules_(rules), mode_(mode) {}

  void real(std::string_view path, double value, Range range) {
    if (recorded(path, range.describe()) || problem_) return;
    if (!std::isfinite(value)) {
      fail(path, "must be a finite number (got " + number_text(value) + ")");
    } else if (!range.contains(value)) {
      fail(path, range.describe() + " (got " + number_text(value) + ")");
    }
  }
  void integer(std::string_view path, int64_t value, int64_t lo, int64_t hi = std::numeric_limits<int64_t>::max()) {
    const std::string rule = hi == std::numeric_limits<int64_t>::max()
                                 ? "must be >= " + number_text(lo)
                                 : "must be in [" + number_text(lo) + ", " + number_text(hi) + "]";
    if (recorded(path, rule) || problem_ || (value >= lo && value <= hi)) return;
    fail(path, rule + " (got " + number_text(value) + ")");
  }
  // Two fields that must be ordered (a decay's floor and its starting value; mc_low and mc_high): a config that
  // breaks the order contradicts itself, so the message names both fields.
  void at_most(std::string_view path, double value, std::string_view other_path, double other) {
    if (recorded(path, "<= " + std::string(other_path)) || problem_ || value <= other) return;
    fail(path, number_text(value) + " exceeds " + std::string(other_path) + " " + number_text(other));
  }
  template <class IsValid>
  void known_enum(std::string_view path, int value, IsValid is_valid) {
    if (recorded(path, "must be one of the enum's values") || problem_ || is_valid(value)) return;
    fail(path, "unknown value " + number_text(int64_t{value}));
  }
  // A rule between fields or with the mode: `applies` is the part the mode decides (a rule of that mode's
  // configs), `bad` the part the fields decide; `message` is `rule` with the values when they differ.
  void refuse_if(bool applies, bool bad, std::string_view path, const std::string& rule) {
    refuse_if(applies, bad, path, rule, rule);
  }
  void refuse_if(bool applies, bool bad, std::string_view path, const std::string& rule, const std::string& message) {
    if (!applies || recorded(path, rule) || !bad) return;
    fail(path, message);
  }
  // The fields inside an environment target, which env_def_from_proto checks; its message names them.
  void target(std::string_view path, const pb::EnvDef& def) {
    if (recorded(path, "must be a valid environment definition (an error names the field inside it)") || problem_)
      return;
    const Expected<EnvDef> checked = env_def_from_proto(def);
    // checked.error() already starts with the field inside the EnvDef ("encoding.pit_gap: ...").
    if (!checked) fail_message(std::string(path) + "." + checked.error());
  }
  bool failed() const { return problem_.has_value(); }
  std::optional<std::string> result() && { return std::move(problem_); }

 private:
  void fail(std::string_view path, const std::string& what) { fail_message(std::string(path) + ": " + what); }
  void fail_message(std::string message) {
    if (!problem_) problem_ = std::move(message);
  }
  // In recording mode, records the rule and says so (the check then does nothing else).
  bool recorded(std::string_view path, const std::string& rule) {
    if (!rules_) return false;
    rules_->push_back({std::string(path), rule, {mode_}});
    return true;
  }

  std::optional<std::string> problem_;
  std::vector<ConfigRule>* rules_ = nullptr;
  pb::RunConfig::Mode mode_ = pb::RunConfig::POET;
};

void check_es(Checks& c, const pb::EsConfig& es) {
  // 400× the reference's 256 mirrored pairs (2n rollouts per ES step); more is a typo, not a bigger run
  c.integer("es.perturbations", es.perturbations(), 1, 100'000);
  // noise on the parameters of a tanh network (θ₀ ~ N(0, 0.1²), the reference's σ 0.1): beyond 10 every unit of
  // θ ± σε saturates and the rollouts say nothing about θ
  c.real("es.init_sigma", es.init_sigma(), Range{0, 10, true, false});
  c.real("es.sigma_decay", es.sigma_decay(), kDecay);
  c.real("es.sigma_floor", es.sigma_floor(), kNonNegative);
  c.at_most("es.sigma_floor", es.sigma_floor(), "es.init_sigma", es.init_sigma());
  // Adam's step moves each parameter by about lr, and θ's entries are of order 0.1 (the reference uses 0.01)
  c.real("es.init_lr", es.init_lr(), Range{0, 1, true, false});
  c.real("es.lr_decay", es.lr_decay(), kDecay);
  c.real("es.lr_floor", es.lr_floor(), kNonNegative);
  c.at_most("es.lr_floor", es.lr_floor(), "es.init_lr", es.init_lr());
  // with lr ≤ 1, lr·λ ≤ 1 keeps the decay θ ← θ − lr·λθ (the SGD proposal's) from overshooting past zero
  c.real("es.l2_coeff", es.l2_coeff(), Range{0, 1});
  c.real("es.adam_beta1", es.adam_beta1(), kBeta);
  c.real("es.adam_beta2", es.adam_beta2(), kBeta);
  // added to √v to keep the division finite (reference 1e-8); at 1 it already dwarfs any gradient's scale
  c.real("es.adam_epsilon", es.adam_epsilon(), Range{0, 1, true, false});
}

void check_poet(Checks& c, const pb::PoetConfig& poet, pb::RunConfig::Mode mode) {
  // iterations between reproductions (reference 200) and transfers (25); beyond 10^6 they never come
  c.integer("poet.mutation_interval", poet.mutation_interval(), 1, 1'000'000);
  c.integer("poet.transfer_interval", poet.transfer_interval(), 1, 1'000'000);
  c.real("poet.repro_threshold", poet.repro_threshold(), kScore);
  // mutation attempts per reproduction (the paper's text 512, the reference 8), all evaluated in one batch
  c.integer("poet.max_children", poet.max_children(), 0, 10'000);
  // admissions per reproduction (reference 1); it cannot exceed the attempts
  c.integer("poet.max_admitted", poet.max_admitted(), 0, 10'000);
  c.real("poet.mc_low", poet.mc_low(), kScore);
  c.real("poet.mc_high", poet.mc_high(), kScore);
  c.at_most("poet.mc_low", poet.mc_low(), "poet.mc_high", poet.mc_high());
  // active pairs (paper 20, reference 25); a transfer round holds N(N−1) proposals of 22 KB each (0.2 GB at 100)
  c.integer("poet.active_cap", poet.active_cap(), 1, 100);
  // neighbours of the novelty score (reference 5); the archive rarely holds more than a few thousand
  c.integer("poet.novelty_k", poet.novelty_k(), 1, 1000);
  c.known_enum("poet.child_ranking", poet.child_ranking(), pb::ChildRanking_IsValid);
  c.known_enum("poet.admission_proposal", poet.admission_proposal(), pb::ProposalKind_IsValid);
  c.known_enum("poet.transfer_proposal", poet.transfer_proposal(), pb::ProposalKind_IsValid);
  c.known_enum("poet.transfer_test", poet.transfer_test(), pb::TransferTest_IsValid);
  c.known_enum("poet.environments", poet.environments(), pb::EnvironmentKind_IsValid);
  const pb::MutationConfig& m = poet.mutation();
  const bool evolves = mode == pb::RunConfig::POET || mode == pb::RunConfig::POET_WITHOUT_TRANSFER;
  // With nothing to mutate every child equals its parent and is dropped: the run could never grow. (A CPPN
  // genome's mutation does not read these switches.)
  c.refuse_if(evolves,
              poet.environments() == pb::OBSTACLE_COURSES && !m.roughness() && !m.pits() && !m.stumps() && !m.stairs(),
              "poet.mutation",
              "no gene type enabled (roughness, pits, stumps and stairs are all false) in mode " +
                  pb::RunConfig::Mode_Name(mode));
  c.real("poet.solved_score", poet.solved_score(), kScore);
  c.refuse_if(
      mode != pb::RunConfig::POET_WITHOUT_TRANSFER, poet.keep_admission_selection(), "poet.keep_admission_selection",
      "true contradicts mode " + pb::RunConfig::Mode_Name(mode) + " (it applies to mode POET_WITHOUT_TRANSFER only)");
  c.known_enum("poet.novelty", poet.novelty(), pb::NoveltyMeasure_IsValid);
  c.known_enum("poet.reproduction_agent", poet.reproduction_agent(), pb::ReproductionAgent_IsValid);
  // a normalisation of the 5-vectors means nothing to PATA-EC; taking it silently would hide a mistaken config
  // A CPPN course's 5-vector is all zeros: the encoding distance would give every child novelty 0.
  c.refuse_if(true,
              poet.environments() == pb::CPPN_TERRAIN && poet.novelty() == pb::ENCODING_DISTANCE &&
                  poet.child_ranking() == pb::NOVELTY,
              "poet.environments",
              "CPPN_TERRAIN with novelty ENCODING_DISTANCE ranks every child alike (a CPPN "
              "course has no obstacle genes); set poet.novelty: PATA_EC or poet.child_ranking: "
              "LOWEST_SCORE_FIRST");
  // PATA-EC evaluates every θ on every archived environment at each reproduction, for a ranking by novelty only
  c.refuse_if(true, poet.novelty() == pb::PATA_EC && poet.child_ranking() == pb::LOWEST_SCORE_FIRST, "poet.novelty",
              "PATA_EC pays for evaluations that poet.child_ranking LOWEST_SCORE_FIRST never reads");
  c.refuse_if(true, poet.novelty_normalized() && poet.novelty() == pb::PATA_EC, "poet.novelty_normalized",
              "true contradicts poet.novelty PATA_EC (it applies to ENCODING_DISTANCE only)");
}

// The tasks of one batch are held in memory together (poet/rollout_batch.h), so the largest batch an iteration
// builds is bounded; the bounds of the single fields alone would allow 2·10^5·10^3 rollouts in one ES batch.
constexpr int64_t kMaxBatchRollouts = 10'000'000;

// Only the POET modes run several pairs at once; ES alone and the direct path run one.
void check_batch_size(Checks& c, const pb::RunConfig& config) {
  const pb::RunConfig::Mode mode = config.mode();
  if (c.failed()) return;
  const int64_t n = config.es().perturbations();  // both within their bounds here, so no product overflows
  const int64_t pairs = config.poet().active_cap();
  const std::string too_many = " rollouts in one batch, more than " + number_text(kMaxBatchRollouts);
  // step 2: one ES step of 2n rollouts for every active pair
  const std::string es_batch_rule = "2 · es.perturbations · poet.active_cap";
  const int64_t es_batch = 2 * n * pairs;
  c.refuse_if(mode == pb::RunConfig::POET || mode == pb::RunConfig::POET_WITHOUT_TRANSFER, es_batch > kMaxBatchRollouts,
              "es.perturbations", es_batch_rule + too_many,
              es_batch_rule + " = 2 · " + number_text(n) + " · " + number_text(pairs) + " = " + number_text(es_batch) +
                  too_many);
  // step 3 (mode POET only): every ordered pair of active pairs gets a proposal's ES step and a direct
  // evaluation, all in the round's first batch (spec §3: N(N−1) ES steps and N(N−1) evaluations)
  const int64_t episodes = config.walker().stochastic_envs() ? config.walker().eval_episodes() : 1;
  const int64_t transfer_batch = pairs * (pairs - 1) * (2 * n + episodes);
  const std::string transfer_rule =
      "a transfer round of poet.active_cap · (poet.active_cap − 1) · (2 · es.perturbations + evaluation episodes)";
  c.refuse_if(mode == pb::RunConfig::POET, transfer_batch > kMaxBatchRollouts, "poet.active_cap",
              transfer_rule + too_many,
              transfer_rule + " = " + number_text(pairs) + " · " + number_text(pairs - 1) + " · (2 · " +
                  number_text(n) + " + " + number_text(episodes) + ") = " + number_text(transfer_batch) + too_many);
}

void check_walker(Checks& c, const pb::WalkerConfig& walker) {
  // the initial push U[−S, S) N on the hull (reference 5); far beyond 1000 N the walker is thrown, not pushed
  c.real("walker.push_scale", walker.push_scale(), Range{0, 1000});
  c.known_enum("walker.lidar", walker.lidar(), pb::WalkerConfig::LidarRule_IsValid);
  // 50× the reference's 2000-step episode
  c.integer("walker.max_steps", walker.max_steps(), 1, 100'000);
  // episodes per evaluation with stochastic courses (reference 5)
  c.integer("walker.eval_episodes", walker.eval_episodes(), 1, 1000);
}

void check_mode(Checks& c, const pb::RunConfig& config) {
  const pb::RunConfig::Mode mode = config.mode();
  const std::string mode_name = pb::RunConfig::Mode_Name(mode);
  c.refuse_if(mode != pb::RunConfig::ES_ALONE, config.has_es_alone(), "es_alone",
              "given, but mode is " + mode_name + " (es_alone applies to mode ES_ALONE only)");
  c.refuse_if(mode != pb::RunConfig::DIRECT_PATH, config.has_direct_path(), "direct_path",
              "given, but mode is " + mode_name + " (direct_path applies to mode DIRECT_PATH only)");
  if (mode == pb::RunConfig::ES_ALONE) {
    c.refuse_if(true, !config.es_alone().has_target(), "es_alone.target", "required in mode ES_ALONE");
    c.target("es_alone.target", config.es_alone().target());
    c.known_enum("es_alone.random_courses", config.es_alone().random_courses(),
                 pb::EsAloneConfig::RandomCourses_IsValid);
    c.refuse_if(true,
                config.es_alone().stop_when_solved() &&
                    config.es_alone().random_courses() != pb::EsAloneConfig::NO_RANDOM_COURSES,
                "es_alone.stop_when_solved", "not with random_courses: the run has no course of its own to solve");
  }
  // a budget beyond any machine's reach is a typing error: 10^15 steps are some 500 years of this walker on a core
  c.integer("env_step_budget", config.env_step_budget(), 0, 1'000'000'000'000'000);
  if (mode == pb::RunConfig::DIRECT_PATH) {
    const pb::DirectPathConfig& direct = config.direct_path();
    c.refuse_if(true, !direct.has_target(), "direct_path.target", "required in mode DIRECT_PATH");
    c.target("direct_path.target", direct.target());
    // the curriculum moves obstacle genes one step at a time; a CPPN genome has no such path from flat
    c.refuse_if(true, direct.target().encoding().has_cppn(), "direct_path.target",
                "a CPPN course has no direct path from flat (use an obstacle encoding)");
    c.real("direct_path.advance_threshold", direct.advance_threshold(), kScore);
    c.refuse_if(true, !direct.has_budget_es_steps(), "direct_path.budget_es_steps", "required in mode DIRECT_PATH");
    // POET's spend along a lineage: at most iterations (10^7) × active pairs (10^3) ES steps
    c.integer("direct_path.budget_es_steps", direct.budget_es_steps(), 1, 10'000'000'000);
  }
}

// Whether the text set any value: an empty section (`es { }`) sets nothing, as it changes no default.
bool sets_any_value(const protobuf::Message& message) {
  const protobuf::Reflection* reflection = message.GetReflection();
  std::vector<const protobuf::FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);  // the fields that are set
  for (const protobuf::FieldDescriptor* field : fields) {
    if (field->cpp_type() != protobuf::FieldDescriptor::CPPTYPE_MESSAGE || field->is_repeated()) return true;
    if (sets_any_value(reflection->GetMessage(message, field))) return true;
  }
  return false;
}

// Every check, in the schema's order: validate() stops at the first problem, config_rules() records each rule.
void run_checks(Checks& c, const pb::RunConfig& config) {
  c.known_enum("mode", config.mode(), pb::RunConfig::Mode_IsValid);
  if (c.failed()) return;  // the mode rules below need a known mode
  c.integer("iterations", config.iterations(), 0, kMaxIterations);
  // at least one checkpoint every 10^6 iterations, so a crash never loses more
  c.integer("checkpoint_interval", config.checkpoint_interval(), 1, 1'000'000);
  // θ₀ ~ N(0, init_stddev²) for a tanh network (reference 0.1); beyond 10 every unit starts saturated
  c.real("init_stddev", config.init_stddev(), Range{0, 10});
  check_es(c, config.es());
  check_poet(c, config.poet(), config.mode());
  // on a fixed course a second evaluation repeats the first: a confirmation would cost episodes and change nothing
  // (a config refused by the first rule never reaches the second: the second is a rule of mode POET)
  c.refuse_if(config.mode() != pb::RunConfig::POET, config.poet().confirm_transfers(), "poet.confirm_transfers",
              "true contradicts mode " + pb::RunConfig::Mode_Name(config.mode()) +
                  " (it applies to mode POET only, the one with transfer rounds)");
  c.refuse_if(config.mode() == pb::RunConfig::POET,
              config.poet().confirm_transfers() && !config.walker().stochastic_envs(), "poet.confirm_transfers",
              "true needs walker.stochastic_envs: true (on a fixed course a score is exact)");
  check_walker(c, config.walker());
  check_batch_size(c, config);
  check_mode(c, config);
}

}  // namespace

std::optional<std::string> validate(const pb::RunConfig& config) {
  Checks c;
  run_checks(c, config);
  return std::move(c).result();
}

std::vector<ConfigRule> config_rules() {
  std::vector<ConfigRule> recorded;
  for (int m = pb::RunConfig::Mode_MIN; m <= pb::RunConfig::Mode_MAX; ++m) {
    if (!pb::RunConfig::Mode_IsValid(m)) continue;
    pb::RunConfig config;
    config.set_mode(static_cast<pb::RunConfig::Mode>(m));
    Checks c(&recorded, config.mode());
    run_checks(c, config);
  }
  // one entry per (path, rule), with every mode it was recorded in, in the order first recorded
  std::vector<ConfigRule> rules;
  for (ConfigRule& rule : recorded) {
    auto same = std::find_if(rules.begin(), rules.end(),
                             [&](const ConfigRule& r) { return r.path == rule.path && r.rule == rule.rule; });
    if (same == rules.end())
      rules.push_back(std::move(rule));
    else if (std::find(same->modes.begin(), same->modes.end(), rule.modes.front()) == same->modes.end())
      same->modes.push_back(rule.modes.front());
  }
  return rules;
}

Expected<pb::RunConfig> parse_run_config(std::string_view text) {
  // The stream below takes an int size; a real config is far smaller anyway.
  if (text.size() > kMaxRunConfigBytes)
    return Unexpected{"text is larger than " + std::to_string(kMaxRunConfigBytes) + " bytes"};
  FirstErrorCollector errors;
  protobuf::TextFormat::Parser parser;  // refuses unknown fields and repeated singular fields by default
  parser.RecordErrorsTo(&errors);
  protobuf::io::ArrayInputStream input(text.data(), static_cast<int>(text.size()));
  pb::RunConfig config;
  if (!parser.Parse(&input, &config)) return Unexpected{errors.error().value_or("not a valid RunConfig text")};
  if (auto problem = validate(config)) return Unexpected{std::move(*problem)};
  // A file that came out empty (a wrong path to a blank file, a truncated copy) would otherwise start the longest
  // run there is; an explicit `mode:` says the defaults are meant.
  if (!sets_any_value(config)) {
    const pb::RunConfig defaults;
    const std::string mode = pb::RunConfig::Mode_Name(defaults.mode());
    return Unexpected{"sets no field; an empty config would run every default (mode " + mode + ", " +
                      std::to_string(defaults.iterations()) +
                      " iterations of the reference's settings) — write `mode: " + mode + "` to mean that"};
  }
  return config;
}

Expected<pb::RunConfig> load_run_config(const std::string& path) {
  const Expected<std::string> text = read_text_file(path, kMaxRunConfigBytes);
  if (!text) return Unexpected{path + ": " + text.error()};
  Expected<pb::RunConfig> config = parse_run_config(*text);
  if (!config) return Unexpected{path + ": " + config.error()};
  return config;
}

namespace {

EsSettings es_settings(const pb::EsConfig& es) {
  EsSettings s;
  s.perturbations = es.perturbations();
  s.init_sigma = es.init_sigma();
  s.sigma_decay = es.sigma_decay();
  s.sigma_floor = es.sigma_floor();
  s.init_lr = es.init_lr();
  s.lr_decay = es.lr_decay();
  s.lr_floor = es.lr_floor();
  s.l2_coeff = es.l2_coeff();
  s.adam_beta1 = es.adam_beta1();
  s.adam_beta2 = es.adam_beta2();
  s.adam_epsilon = es.adam_epsilon();
  s.normalize_grads_by_sigma = es.normalize_grads_by_sigma();
  return s;
}

MutationOptions mutation_options(const pb::MutationConfig& m) {
  MutationOptions o;
  o.roughness = m.roughness();
  o.pits = m.pits();
  o.stumps = m.stumps();
  o.stairs = m.stairs();
  o.mutate_stair_steps = m.mutate_stair_steps();
  o.all_types = m.all_types();
  return o;
}

static_assert(static_cast<int>(LidarRule::kNearest) == pb::WalkerConfig::NEAREST &&
              static_cast<int>(LidarRule::kFirst) == pb::WalkerConfig::FIRST);

// The walker's settings, and ES alone's domain randomisation, which makes every course a fresh one too.
EpisodeSettings episode_settings(const pb::RunConfig& config) {
  const pb::WalkerConfig& w = config.walker();
  EpisodeSettings s;
  s.walker.push_scale = w.push_scale();
  s.walker.lidar = static_cast<LidarRule>(w.lidar());
  s.max_steps = w.max_steps();
  const auto random = config.es_alone().random_courses();
  if (config.mode() == pb::RunConfig::ES_ALONE && random != pb::EsAloneConfig::NO_RANDOM_COURSES)
    s.random_courses = static_cast<Difficulty>(random - 1);  // the levels in order: EASY_COURSES (1) is kEasy (0)
  s.stochastic = w.stochastic_envs() || s.random_courses.has_value();
  s.eval_episodes = s.stochastic ? w.eval_episodes() : 1;
  return s;
}

RunMode run_mode(pb::RunConfig::Mode mode) {
  switch (mode) {
    case pb::RunConfig::POET_WITHOUT_TRANSFER:
      return RunMode::kPoetWithoutTransfer;
    case pb::RunConfig::ES_ALONE:
      return RunMode::kEsAlone;
    case pb::RunConfig::DIRECT_PATH:
      return RunMode::kDirectPath;
    default:
      return RunMode::kPoet;
  }
}

ProposalKind proposal_kind(pb::ProposalKind kind) {
  return kind == pb::ADAM_PROPOSAL ? ProposalKind::kAdam : ProposalKind::kSgd;
}

PoetSettings poet_settings(const pb::PoetConfig& p) {
  PoetSettings s;
  s.mutation_interval = p.mutation_interval();
  s.transfer_interval = p.transfer_interval();
  s.repro_threshold = p.repro_threshold();
  s.max_children = p.max_children();
  s.max_admitted = p.max_admitted();
  s.mc_low = p.mc_low();
  s.mc_high = p.mc_high();
  s.active_cap = p.active_cap();
  s.novelty_k = p.novelty_k();
  s.novelty_normalized = p.novelty_normalized();
  s.novelty = p.novelty() == pb::PATA_EC ? NoveltyMeasure::kPataEc : NoveltyMeasure::kEncodingDistance;
  s.reproduction_agent =
      p.reproduction_agent() == pb::BEST_THETA ? ReproductionAgent::kBestTheta : ReproductionAgent::kCurrentTheta;
  s.confirm_transfers = p.confirm_transfers();
  s.child_ranking =
      p.child_ranking() == pb::LOWEST_SCORE_FIRST ? ChildRanking::kLowestScoreFirst : ChildRanking::kNovelty;
  s.admission_proposal = proposal_kind(p.admission_proposal());
  s.transfer_proposal = proposal_kind(p.transfer_proposal());
  s.solved_score = p.solved_score();
  s.keep_admission_selection = p.keep_admission_selection();
  s.transfer_test = p.transfer_test() == pb::THRESHOLD_TRANSFER_TEST ? TransferTest::kThreshold : TransferTest::kFull;
  s.environments =
      p.environments() == pb::CPPN_TERRAIN ? EnvironmentKind::kCppnTerrain : EnvironmentKind::kObstacleCourses;
  s.mutation = mutation_options(p.mutation());
  return s;
}

}  // namespace

RunSettings run_settings(const pb::RunConfig& config) {
  RunSettings s;
  s.mode = run_mode(config.mode());
  s.seed = config.seed();
  s.iterations = config.iterations();
  s.checkpoint_interval = config.checkpoint_interval();
  s.init_zero = config.init_zero();
  s.init_stddev = config.init_stddev();
  s.es = es_settings(config.es());
  s.episodes = episode_settings(config);
  s.poet = poet_settings(config.poet());
  if (s.mode == RunMode::kEsAlone) s.target = env_def_from_proto(config.es_alone().target()).value();
  if (s.mode == RunMode::kDirectPath) s.target = env_def_from_proto(config.direct_path().target()).value();
  s.stop_when_solved = config.es_alone().stop_when_solved();
  s.advance_threshold = config.direct_path().advance_threshold();
  s.budget_es_steps = config.direct_path().budget_es_steps();
  s.env_step_budget = config.env_step_budget();
  return s;
}

std::string run_config_text(const pb::RunConfig& config) {
  // The printer writes doubles with 15 significant digits when those read back exactly and 17 otherwise
  // (protobuf's SimpleDtoa), so the text round-trips bit for bit; the tests hold it to that.
  protobuf::TextFormat::Printer printer;
  std::string text;
  printer.PrintToString(config, &text);
  return text;
}

}  // namespace poet
