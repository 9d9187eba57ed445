#include "tools/reference/config_reference.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "common/formats/envgen/env_proto.h"
#include "common/text/text_format.h"
#include "poet.pb.h"
#include "run_directory/config/config_rules.h"
#include "run_directory/config/run_config.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
namespace protobuf = google::protobuf;

const fs::path kConfigs = fs::path(POET_SOURCE_DIR) / "deploy" / "configs";

const std::string& page() {
  static const std::string text = [] {
    const Expected<std::string> made = config_reference_page(kConfigs);
    EXPECT_TRUE(made.has_value()) << made.error();
    return made.has_value() ? *made : std::string();
  }();
  return text;
}

// The cells of a table row, split at the pipes the page does not escape, without the cell padding.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string current;
  for (size_t i = 1; i < row.size(); ++i) {  // row[0] is the leading pipe
    if (row[i] == '|' && row[i - 1] != '\\') {
      out.push_back(current.size() >= 2 ? current.substr(1, current.size() - 2) : current);
      current.clear();
    } else {
      current += row[i];
    }
  }
  return out;
}

// The row of a field, by its dotted path as the page writes it.
std::optional<std::vector<std::string>> row_of(const std::string& path) {
  const std::string start = "| `" + path + "` |";
  for (size_t at = page().find(start); at != std::string::npos; at = page().find(start, at + 1)) {
    if (at != 0 && page()[at - 1] != '\n') continue;
    return cells(page().substr(at, page().find('\n', at) - at));
  }
  return std::nullopt;
}

// A cell's text as the reader sees it (the page escapes what Markdown would take for markup).
std::string unescaped(std::string text) {
  for (const auto& [from, to] : {std::pair{"&lt;", "<"}, {"&gt;", ">"}, {"\\|", "|"}, {"\\*", "*"}}) {
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + std::strlen(to)))
      text.replace(at, std::strlen(from), to);
  }
  return text;
}

// The dotted path of every field of the run config as the page names it: an environment target's fields under
// `target`, an interval gene's under `target.encoding.<interval>`, a repeated message's elements as `[i]`.
void collect_paths(const protobuf::Descriptor& message, const std::string& prefix,
                   std::vector<const protobuf::FieldDescriptor*>& fields, std::vector<std::string>& paths) {
  for (int i = 0; i < message.field_count(); ++i) {
    const protobuf::FieldDescriptor* field = message.field(i);
    const std::string path = prefix.empty() ? field->name() : prefix + "." + field->name();
    fields.push_back(field);
    paths.push_back(path);
    const protobuf::Descriptor* part = field->message_type();
    if (!part) continue;
    if (part == pb::EnvDef::descriptor()) {
      if (prefix != "es_alone") continue;  // both targets are one section; walk it once
      collect_paths(*part, "target", fields, paths);
    } else if (part == pb::Interval::descriptor()) {
      if (field->name() != "pit_gap") continue;  // every interval gene is one section; walk it once
      collect_paths(*part, "target.encoding.<interval>", fields, paths);
    } else {
      collect_paths(*part, field->is_repeated() ? path + "[i]" : path, fields, paths);
    }
  }
}

TEST(ConfigReferenceTest, EveryFieldOfTheRunConfigHasARowWithItsTypeDefaultAndMeaning) {
  ASSERT_FALSE(page().empty());
  std::vector<const protobuf::FieldDescriptor*> fields;
  std::vector<std::string> paths;
  collect_paths(*pb::RunConfig::descriptor(), "", fields, paths);
  ASSERT_GT(paths.size(), 80u);  // the run config's fields, its parts' and a target's
  for (size_t i = 0; i < paths.size(); ++i) {
    const protobuf::FieldDescriptor& field = *fields[i];
    const std::optional<std::vector<std::string>> row = row_of(paths[i]);
    ASSERT_TRUE(row.has_value()) << paths[i] << " has no row";
    ASSERT_EQ(row->size(), 6u) << paths[i];
    EXPECT_NE((*row)[5], "") << paths[i] << ": no meaning";
    if (field.is_repeated() || field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_MESSAGE) continue;
    // the default as the schema declares it
    std::string expected;
    switch (field.cpp_type()) {
      case protobuf::FieldDescriptor::CPPTYPE_DOUBLE:
        expected = number_text(field.default_value_double());
        break;
      case protobuf::FieldDescriptor::CPPTYPE_INT32:
        expected = std::to_string(field.default_value_int32());
        break;
      case protobuf::FieldDescriptor::CPPTYPE_INT64:
        expected = std::to_string(field.default_value_int64());
        break;
      case protobuf::FieldDescriptor::CPPTYPE_UINT32:
        expected = std::to_string(field.default_value_uint32());
        break;
      case protobuf::FieldDescriptor::CPPTYPE_UINT64:
        expected = std::to_string(field.default_value_uint64());
        break;
      case protobuf::FieldDescriptor::CPPTYPE_BOOL:
        expected = field.default_value_bool() ? "true" : "false";
        break;
      case protobuf::FieldDescriptor::CPPTYPE_ENUM:
        expected = field.default_value_enum()->name();
        break;
      case protobuf::FieldDescriptor::CPPTYPE_STRING:
        expected = "\"" + field.default_value_string() + "\"";
        break;
      default:
        FAIL() << paths[i] << ": a type the test does not know";
    }
    EXPECT_EQ((*row)[2], "`" + expected + "`") << paths[i];
  }
}

TEST(ConfigReferenceTest, EveryEnumValueOfAConfigFieldIsListed) {
  for (const protobuf::EnumDescriptor* e :
       {pb::RunConfig::Mode_descriptor(), pb::ChildRanking_descriptor(), pb::ProposalKind_descriptor(),
        pb::TransferTest_descriptor(), pb::EnvironmentKind_descriptor(), pb::NoveltyMeasure_descriptor(),
        pb::ReproductionAgent_descriptor(), pb::WalkerConfig::LidarRule_descriptor(),
        pb::EsAloneConfig::RandomCourses_descriptor(), pb::CppnNode::Role_descriptor(),
        pb::CppnNode::Activation_descriptor()})
    for (int v = 0; v < e->value_count(); ++v)
      EXPECT_NE(page().find("\n- `" + e->value(v)->name() + "` — "), std::string::npos) << e->value(v)->full_name();
}

// Whether `text` holds `word` not as part of a longer name (POET inside POET_WITHOUT_TRANSFER).
size_t word_at(const std::string& text, const std::string& word) {
  const std::regex pattern("(^|[^A-Z_])" + word + "($|[^A-Z_])");
  std::smatch match;
  if (!std::regex_search(text, match, pattern)) return std::string::npos;
  return static_cast<size_t>(match.position(0)) + match[1].length();
}

TEST(ConfigReferenceTest, EveryRuleTheValidatorRecordsIsInItsFieldsBoundsCell) {
  const std::vector<ConfigRule> rules = config_rules();
  ASSERT_GT(rules.size(), 50u);
  for (const ConfigRule& rule : rules) {
    const std::optional<std::vector<std::string>> row = row_of(rule.path);
    ASSERT_TRUE(row.has_value()) << rule.path << " (rule " << rule.rule << ") has no row";
    const std::string bounds = unescaped((*row)[4]);
    // a rule of one mode that names it may be shown merged with its like in other modes: the words around the
    // mode's name are shown
    const std::string mode = pb::RunConfig::Mode_Name(rule.modes.front());
    const size_t at = rule.modes.size() == 1 ? word_at(rule.rule, mode) : std::string::npos;
    if (at == std::string::npos) {
      EXPECT_NE(bounds.find(rule.rule), std::string::npos) << rule.path << ": " << rule.rule << " not in " << bounds;
    } else {
      EXPECT_NE(bounds.find(rule.rule.substr(0, at)), std::string::npos) << rule.path << ": " << rule.rule;
      EXPECT_NE(bounds.find(rule.rule.substr(at + mode.size())), std::string::npos) << rule.path << ": " << rule.rule;
      EXPECT_NE(word_at(bounds, mode), std::string::npos) << rule.path << ": " << rule.rule;
    }
  }
}

TEST(ConfigReferenceTest, TheRulesOfEveryModeAreRecorded) {
  const std::vector<ConfigRule> rules = config_rules();
  const auto find = [&](const std::string& path, const std::string& text) -> const ConfigRule* {
    for (const ConfigRule& r : rules)
      if (r.path == path && r.rule == text) return &r;
    return nullptr;
  };
  const ConfigRule* l2 = find("es.l2_coeff", "must be in [0, 1]");
  ASSERT_NE(l2, nullptr);
  EXPECT_EQ(l2->modes.size(), 4u);
  ASSERT_NE(find("poet.mc_low", "<= poet.mc_high"), nullptr);
  const ConfigRule* target = find("es_alone.target", "required in mode ES_ALONE");
  ASSERT_NE(target, nullptr);
  EXPECT_EQ(target->modes, std::vector<pb::RunConfig::Mode>{pb::RunConfig::ES_ALONE});
  ASSERT_NE(find("direct_path.budget_es_steps", "required in mode DIRECT_PATH"), nullptr);
  ASSERT_NE(find("poet.keep_admission_selection",
                 "true contradicts mode DIRECT_PATH (it applies to mode POET_WITHOUT_TRANSFER only)"),
            nullptr);
  const ConfigRule* batch =
      find("es.perturbations", "2 · es.perturbations · poet.active_cap rollouts in one batch, more than 10000000");
  ASSERT_NE(batch, nullptr);
  const std::vector<pb::RunConfig::Mode> several_pairs{pb::RunConfig::POET, pb::RunConfig::POET_WITHOUT_TRANSFER};
  EXPECT_EQ(batch->modes, several_pairs);
}

// A config of the mode that validate() accepts, so that one bad field is the only problem.
pb::RunConfig runnable(pb::RunConfig::Mode mode) {
  pb::RunConfig config;
  config.set_mode(mode);
  if (mode == pb::RunConfig::ES_ALONE) config.mutable_es_alone()->mutable_target()->set_seed(1);
  if (mode == pb::RunConfig::DIRECT_PATH) {
    config.mutable_direct_path()->mutable_target()->set_seed(1);
    config.mutable_direct_path()->set_budget_es_steps(10);
  }
  return config;
}

// Sets a numeric field by its dotted path; false when the path is no numeric field.
bool set_number(protobuf::Message& config, const std::string& path, double value) {
  protobuf::Message* message = &config;
  std::string rest = path;
  for (size_t dot = rest.find('.'); dot != std::string::npos; dot = rest.find('.')) {
    const protobuf::FieldDescriptor* part = message->GetDescriptor()->FindFieldByName(rest.substr(0, dot));
    if (!part || !part->message_type()) return false;
    message = message->GetReflection()->MutableMessage(message, part);
    rest = rest.substr(dot + 1);
  }
  const protobuf::FieldDescriptor* field = message->GetDescriptor()->FindFieldByName(rest);
  if (!field) return false;
  const protobuf::Reflection& r = *message->GetReflection();
  switch (field->cpp_type()) {
    case protobuf::FieldDescriptor::CPPTYPE_DOUBLE:
      r.SetDouble(message, field, value);
      return true;
    case protobuf::FieldDescriptor::CPPTYPE_INT32:
      r.SetInt32(message, field, static_cast<int32_t>(value));
      return true;
    case protobuf::FieldDescriptor::CPPTYPE_INT64:
      r.SetInt64(message, field, static_cast<int64_t>(value));
      return true;
    default:
      return false;
  }
}

// Reads a numeric field by its dotted path (a field of the same forms set_number sets).
double get_number(const protobuf::Message& config, const std::string& path) {
  const protobuf::Message* message = &config;
  std::string rest = path;
  for (size_t dot = rest.find('.'); dot != std::string::npos; dot = rest.find('.')) {
    const protobuf::FieldDescriptor* part = message->GetDescriptor()->FindFieldByName(rest.substr(0, dot));
    message = &message->GetReflection()->GetMessage(*message, part);
    rest = rest.substr(dot + 1);
  }
  const protobuf::FieldDescriptor* field = message->GetDescriptor()->FindFieldByName(rest);
  const protobuf::Reflection& r = *message->GetReflection();
  if (field->cpp_type() == protobuf::FieldDescriptor::CPPTYPE_DOUBLE) return r.GetDouble(*message, field);
  if (field->cpp_type() == protobuf::FieldDescriptor::CPPTYPE_INT32) return r.GetInt32(*message, field);
  return static_cast<double>(r.GetInt64(*message, field));
}

// The rules of a bound's form ("must be ...", "<= other") that no generic value provokes. Keep it short: a bound
// of a new form belongs in violations() below, not here. (Rules worded as prose, a mode's or several fields'
// rule such as "required in mode ES_ALONE", are no bound: run_config_test.cpp provokes them one by one.)
const std::vector<std::string> kNotProvokedGenerically = {
    // proto2 enums are closed: parsing and reflection keep an unknown number out of the field, so no config holds
    // one (the check guards the C++ setters)
    "must be one of the enum's values",
    // a target's fields: env_def_from_proto's rules, provoked by the EveryRuleShownForATarget tests below
    "must be a valid environment definition (an error names the field inside it)",
};

// A value that breaks a recorded rule, and the message validate() must then give.
struct Violation {
  std::string path;   // the field set
  double value;       // its value
  std::string other;  // for a rule between two fields: the other field's path ("" otherwise)
};

// The values that break a rule of one of the validator's generic forms: both ends of a range ("[lo, hi]": lo − 1
// and hi + 1; an open end, the end itself), past a one-sided bound, and above the other field of an order rule.
// Empty when the rule has none of those forms.
std::vector<Violation> violations(const ConfigRule& rule, const pb::RunConfig& config) {
  const std::regex range(R"(must be in ([\[(])(\S+), (\S+)([\])]))");
  const std::regex one_sided(R"(must be (>=|>|<=|<) (\S+))");
  const std::regex order(R"(<= (\S+))");
  const auto number = [](const std::string& text) { return std::strtod(text.c_str(), nullptr); };
  std::smatch m;
  if (std::regex_match(rule.rule, m, range)) {
    const double lo = number(m[2]), hi = number(m[3]);
    return {{rule.path, m[1] == "(" ? lo : lo - 1, ""}, {rule.path, m[4] == ")" ? hi : hi + 1, ""}};
  }
  if (std::regex_match(rule.rule, m, one_sided)) {
    const double bound = number(m[2]);
    if (m[1] == ">=") return {{rule.path, bound - 1, ""}};
    if (m[1] == ">") return {{rule.path, bound, ""}};
    if (m[1] == "<=") return {{rule.path, bound + 1, ""}};
    return {{rule.path, bound, ""}};
  }
  if (std::regex_match(rule.rule, m, order)) return {{rule.path, get_number(config, m[1]) + 1, m[1]}};
  if (rule.rule == "must be a finite number") return {{rule.path, std::nan(""), ""}};
  return {};
}

// Each recorded rule of a generic form is the validator's: a config that breaks it, the only problem in a config
// of the rule's mode, is refused naming the field, in the words the page shows.
TEST(ConfigReferenceTest, EveryRecordedBoundIsTheOneTheValidatorRefusesWith) {
  int checked = 0;
  std::vector<std::string> unprovoked;
  for (const ConfigRule& rule : config_rules()) {
    pb::RunConfig config = runnable(rule.modes.front());
    ASSERT_EQ(validate(config), std::nullopt) << rule.path;
    const std::vector<Violation> breaking = violations(rule, config);
    const bool bound_form = rule.rule.starts_with("must be ") || rule.rule.starts_with("<= ");
    if (breaking.empty() && bound_form) {
      const bool listed = std::find(kNotProvokedGenerically.begin(), kNotProvokedGenerically.end(), rule.rule) !=
                          kNotProvokedGenerically.end();
      if (!listed) unprovoked.push_back(rule.path + ": " + rule.rule);
    }
    if (breaking.empty()) continue;
    // the page shows the rule in the field's bounds cell
    const std::optional<std::vector<std::string>> row = row_of(rule.path);
    ASSERT_TRUE(row.has_value()) << rule.path;
    EXPECT_NE(unescaped((*row)[4]).find(rule.rule), std::string::npos) << rule.path << ": " << rule.rule;
    for (const Violation& v : breaking) {
      pb::RunConfig bad = config;
      ASSERT_TRUE(set_number(bad, v.path, v.value)) << v.path;
      const std::optional<std::string> problem = validate(bad);
      ASSERT_TRUE(problem.has_value()) << v.path << " = " << v.value << " is accepted (rule " << rule.rule << ")";
      if (v.other.empty()) {
        EXPECT_EQ(problem->rfind(rule.path + ": " + rule.rule + " (got ", 0), 0u) << v.value << ": " << *problem;
      } else {
        // "<= es.init_sigma" is refused as "es.sigma_floor: 1.1 exceeds es.init_sigma 0.1"
        EXPECT_EQ(*problem, rule.path + ": " + number_text(get_number(bad, v.path)) + " exceeds " + v.other + " " +
                                number_text(get_number(bad, v.other)));
      }
      ++checked;
    }
  }
  EXPECT_TRUE(unprovoked.empty()) << "bounds neither provoked nor listed as such: "
                                  << ::testing::PrintToString(unprovoked);
  EXPECT_GT(checked, 40);
}

// A target's fields are checked by env_def_from_proto, not by recorded rules: each bound and rule the page states
// for them is provoked through it, and the number the page gives is the one the refusal gives.

// The bounds cell of a target's field, as the reader sees it.
std::string target_bounds(const std::string& path) {
  const std::optional<std::vector<std::string>> row = row_of(path);
  EXPECT_TRUE(row.has_value()) << path;
  return row.has_value() && row->size() == 6 ? unescaped((*row)[4]) : std::string();
}

// The number a pattern's first group captures in text; NaN (and a failure) when it does not match.
double number_in(const std::string& text, const std::string& pattern) {
  std::smatch match;
  if (!std::regex_search(text, match, std::regex(pattern))) {
    ADD_FAILURE() << "/" << pattern << "/ not in: " << text;
    return std::nan("");
  }
  return std::strtod(match[1].str().c_str(), nullptr);
}

// env_def_from_proto's refusal ("" when it accepts).
std::string refusal(const pb::EnvDef& def) {
  const Expected<EnvDef> checked = env_def_from_proto(def);
  return checked.has_value() ? std::string() : checked.error();
}

// The smallest CPPN course: the input, the output and one connection.
pb::EnvDef cppn_course() {
  pb::EnvDef def;
  pb::CppnGenome& genome = *def.mutable_encoding()->mutable_cppn();
  pb::CppnNode& input = *genome.add_nodes();
  input.set_id(0);
  input.set_role(pb::CppnNode::INPUT);
  pb::CppnNode& output = *genome.add_nodes();
  output.set_id(1);
  output.set_role(pb::CppnNode::OUTPUT);
  pb::CppnConnection& link = *genome.add_connections();
  link.set_from_node(0);
  link.set_to_node(1);
  link.set_weight(1);
  return def;
}

pb::Interval& gene(pb::EnvDef& def, const std::string& name) {
  const protobuf::FieldDescriptor* field = pb::EnvEncoding::descriptor()->FindFieldByName(name);
  return static_cast<pb::Interval&>(
      *def.mutable_encoding()->GetReflection()->MutableMessage(def.mutable_encoding(), field));
}

// The interval genes of the encoding, by the schema.
std::vector<std::string> interval_genes() {
  std::vector<std::string> out;
  const protobuf::Descriptor& encoding = *pb::EnvEncoding::descriptor();
  for (int i = 0; i < encoding.field_count(); ++i)
    if (encoding.field(i)->message_type() == pb::Interval::descriptor()) out.push_back(encoding.field(i)->name());
  return out;
}

TEST(ConfigReferenceTest, EveryBoundShownForATargetsFieldIsTheEnvironmentValidators) {
  // target.seed: must be < N
  const double seeds = number_in(target_bounds("target.seed"), R"(^must be < (\d+)$)");
  pb::EnvDef def;
  def.set_seed(static_cast<uint32_t>(seeds - 1));
  EXPECT_EQ(refusal(def), "");
  def.set_seed(static_cast<uint32_t>(seeds));
  EXPECT_EQ(refusal(def).rfind("seed: must be < " + std::to_string(def.seed()) + " (got ", 0), 0u) << refusal(def);

  // target.encoding.roughness: must be in [0, R]
  const std::string roughness = target_bounds("target.encoding.roughness");
  const double rough_lo = number_in(roughness, R"(^must be in \[(\S+), \S+\]$)");
  const double rough_hi = number_in(roughness, R"(^must be in \[\S+, (\S+)\]$)");
  for (const double ok : {rough_lo, rough_hi}) {
    def = {};
    def.mutable_encoding()->set_roughness(ok);
    EXPECT_EQ(refusal(def), "") << ok;
  }
  def.mutable_encoding()->set_roughness(rough_hi + 0.5);
  EXPECT_EQ(refusal(def).rfind("encoding.roughness: exceeds " + number_text(rough_hi) + " (got ", 0), 0u)
      << refusal(def);
  def.mutable_encoding()->set_roughness(rough_lo - 0.5);
  EXPECT_EQ(refusal(def).rfind("encoding.roughness: must be >= " + number_text(rough_lo) + " (got ", 0), 0u)
      << refusal(def);

  // target.encoding.<interval>.lo: must be in [0, hi], given with hi; .hi: must be in [lo, H], given with lo
  const std::string lo_bounds = target_bounds("target.encoding.<interval>.lo");
  const std::string hi_bounds = target_bounds("target.encoding.<interval>.hi");
  const double least = number_in(lo_bounds, R"(must be in \[(\S+), hi\])");
  const double most = number_in(hi_bounds, R"(must be in \[lo, (\S+)\])");
  EXPECT_NE(lo_bounds.find("given with hi"), std::string::npos) << lo_bounds;
  EXPECT_NE(hi_bounds.find("given with lo"), std::string::npos) << hi_bounds;
  def = {};
  gene(def, "pit_gap").set_lo(least);
  gene(def, "pit_gap").set_hi(most);
  EXPECT_EQ(refusal(def), "");
  const std::vector<std::string> genes = interval_genes();
  ASSERT_EQ(genes.size(), 7u);
  for (const std::string& name : genes) {
    const auto refused = [&](double lo, double hi) {
      pb::EnvDef bad;
      gene(bad, name).set_lo(lo);
      gene(bad, name).set_hi(hi);
      return refusal(bad);
    };
    EXPECT_EQ(refused(least - 1, 2).rfind("encoding." + name + ": bounds must be >= " + number_text(least), 0), 0u)
        << refused(least - 1, 2);
    EXPECT_EQ(refused(3, 2).rfind("encoding." + name + ": inverted interval (lo > hi)", 0), 0u) << refused(3, 2);
    EXPECT_EQ(refused(1, most + 1).rfind("encoding." + name + ": upper bound exceeds " + number_text(most), 0), 0u)
        << refused(1, most + 1);
    pb::EnvDef half;
    gene(half, name).set_lo(1);
    EXPECT_EQ(refusal(half).rfind("encoding." + name + ".hi: missing", 0), 0u) << refusal(half);
    half = {};
    gene(half, name).set_hi(1);
    EXPECT_EQ(refusal(half).rfind("encoding." + name + ".lo: missing", 0), 0u) << refusal(half);
  }

  // target.encoding.cppn.nodes: at most N; connections: at most M (the sizes are checked first)
  const double nodes = number_in(target_bounds("target.encoding.cppn.nodes"), R"(^at most (\d+)$)");
  def = cppn_course();
  for (int id = 2; id <= static_cast<int>(nodes); ++id) def.mutable_encoding()->mutable_cppn()->add_nodes()->set_id(id);
  EXPECT_EQ(refusal(def), "encoding.cppn.nodes: " + number_text(nodes + 1) + " nodes; at most " + number_text(nodes));
  const double connections = number_in(target_bounds("target.encoding.cppn.connections"), R"(^at most (\d+)$)");
  def = cppn_course();
  for (int i = 1; i <= static_cast<int>(connections); ++i) def.mutable_encoding()->mutable_cppn()->add_connections();
  EXPECT_EQ(refusal(def), "encoding.cppn.connections: " + number_text(connections + 1) + " connections; at most " +
                              number_text(connections));

  // target.encoding.cppn.scale: must be a finite number in (0, S]; the refusal gives the same range
  const std::string scale = target_bounds("target.encoding.cppn.scale");
  const double scale_max = number_in(scale, R"(^must be a finite number in \(0, (\S+)\]$)");
  def = cppn_course();
  def.mutable_encoding()->mutable_cppn()->mutable_connections(0)->set_weight(0);  // a flat course at any scale
  def.mutable_encoding()->mutable_cppn()->set_scale(scale_max);
  EXPECT_EQ(refusal(def), "");
  for (const double bad : {0.0, scale_max * 2, std::nan("")}) {
    def.mutable_encoding()->mutable_cppn()->set_scale(bad);
    const std::string error = refusal(def);
    EXPECT_EQ(error.rfind("encoding.cppn.scale: must be a finite number in (0, ", 0), 0u) << bad << ": " << error;
    EXPECT_EQ(number_in(error, R"(in \(0, (\S+)\]$)"), scale_max) << error;
  }

  // target.encoding.cppn.nodes[i].id: must be in [0, I] (a hidden node, unconnected, is allowed)
  const double ids = number_in(target_bounds("target.encoding.cppn.nodes[i].id"), R"(^must be in \[0, (\d+)\]$)");
  def = cppn_course();
  def.mutable_encoding()->mutable_cppn()->add_nodes()->set_id(static_cast<int32_t>(ids));
  EXPECT_EQ(refusal(def), "");
  def.mutable_encoding()->mutable_cppn()->mutable_nodes(2)->set_id(static_cast<int32_t>(ids + 1));
  EXPECT_EQ(refusal(def).rfind("encoding.cppn.nodes[2].id: must be in [0, ", 0), 0u) << refusal(def);
  EXPECT_EQ(number_in(refusal(def), R"(must be in \[0, (\d+)\]$)"), ids) << refusal(def);

  // target.encoding.cppn.nodes[i].bias and connections[i].weight: within ±B
  for (const std::string path : {"target.encoding.cppn.nodes[i].bias", "target.encoding.cppn.connections[i].weight"}) {
    const double limit = number_in(target_bounds(path), "^within ±(\\S+)$");
    const bool bias = path.ends_with("bias");
    for (const double sign : {1.0, -1.0}) {
      def = cppn_course();
      pb::CppnGenome& genome = *def.mutable_encoding()->mutable_cppn();
      const auto set = [&](double v) {
        if (bias)
          genome.mutable_nodes(1)->set_bias(v);
        else
          genome.mutable_connections(0)->set_weight(v);
      };
      set(sign * limit);
      EXPECT_EQ(refusal(def), "") << path;
      set(sign * (limit + 0.5));
      const std::string field = bias ? "encoding.cppn.nodes[1].bias" : "encoding.cppn.connections[0].weight";
      EXPECT_EQ(refusal(def).rfind(field + ": must be a finite number within ±", 0), 0u) << refusal(def);
      EXPECT_EQ(number_in(refusal(def), "within ±(\\S+)$"), limit) << refusal(def);
    }
  }

  // target: an error names the field inside the target, as the run's validator gives it
  pb::RunConfig config = runnable(pb::RunConfig::ES_ALONE);
  gene(*config.mutable_es_alone()->mutable_target(), "pit_gap").set_lo(1);
  const std::optional<std::string> problem = validate(config);
  ASSERT_TRUE(problem.has_value());
  const std::string named = problem->substr(0, problem->find(':'));
  EXPECT_EQ(named, "es_alone.target.encoding.pit_gap.hi");
  // the section's example error is that refusal, word for word
  EXPECT_NE(page().find("An error names the field inside the target: `" + *problem + "`"), std::string::npos)
      << *problem;
}

// The rules the environments section states in prose, each provoked through env_def_from_proto.
TEST(ConfigReferenceTest, EveryRuleTheEnvironmentsSectionStatesIsTheEnvironmentValidators) {
  const size_t start = page().find("\n## Environments — the targets\n");
  ASSERT_NE(start, std::string::npos);
  const std::string text = page().substr(start, page().find("\n### ", start) - start);

  // "<interval> for any interval gene of the encoding (`pit_gap`, ...)": the schema's interval genes
  std::string listed;
  for (const std::string& name : interval_genes()) listed += (listed.empty() ? "`" : ", `") + name + "`";
  EXPECT_NE(text.find("any interval gene of the encoding (" + listed + ")"), std::string::npos) << listed;

  // "counts and widths (`stump_width`, ...) are whole numbers with lo < hi": exactly those genes
  std::smatch match;
  ASSERT_TRUE(
      std::regex_search(text, match, std::regex(R"(counts and widths \(([^)]*)\) are whole numbers with lo < hi)")));
  const std::string whole = match[1];
  for (const std::string& name : interval_genes()) {
    pb::EnvDef fractional;
    gene(fractional, name).set_lo(1.5);
    gene(fractional, name).set_hi(3);
    pb::EnvDef empty;
    gene(empty, name).set_lo(2);
    gene(empty, name).set_hi(2);
    if (whole.find("`" + name + "`") != std::string::npos) {
      EXPECT_EQ(refusal(fractional).rfind("encoding." + name + ": bounds must be whole numbers", 0), 0u)
          << refusal(fractional);
      EXPECT_EQ(refusal(empty).rfind("encoding." + name + ": integer interval [lo, hi) must hold a value (lo < hi)", 0),
                0u)
          << refusal(empty);
    } else {
      EXPECT_EQ(refusal(fractional).find("whole numbers"), std::string::npos) << name << ": " << refusal(fractional);
      EXPECT_EQ(refusal(empty).find("lo < hi"), std::string::npos) << name << ": " << refusal(empty);
    }
  }

  // "a type's intervals are all given or none"
  EXPECT_NE(text.find("a type's intervals are all given or none"), std::string::npos);
  for (const auto& [given, missing] : {std::pair{"stump_width", "stump_height"}, {"stair_height", "stair_width"}}) {
    pb::EnvDef partial;
    gene(partial, given).set_lo(1);
    gene(partial, given).set_hi(2);
    EXPECT_EQ(refusal(partial).rfind("encoding." + std::string(missing) + ": missing while other ", 0), 0u)
        << refusal(partial);
  }

  // "a stump or stair is at least W terrain step wide and a staircase has at least S step": the same numbers
  const double wide = number_in(text, R"(a stump or stair is at least (\d+) terrain step wide)");
  const double steps = number_in(text, R"(a staircase has at least (\d+) step)");
  const auto complete = [](const std::string& type, const std::string& name, double lo) {
    pb::EnvDef def;
    for (const std::string& other : interval_genes()) {
      if (!other.starts_with(type)) continue;
      gene(def, other).set_lo(other == name ? lo : 1);
      gene(def, other).set_hi(other == name ? lo + 1 : 2);
    }
    return def;
  };
  for (const auto& [type, name, least] :
       {std::tuple{"stump", "stump_width", wide}, {"stair", "stair_width", wide}, {"stair", "stair_steps", steps}}) {
    EXPECT_EQ(refusal(complete(type, name, least)), "") << name;
    const std::string error = refusal(complete(type, name, least - 1));
    EXPECT_EQ(error.rfind("encoding." + std::string(name) + ": ", 0), 0u) << error;
    EXPECT_EQ(number_in(error, R"(at least (\d+) )"), least) << error;
  }

  // "a CPPN course has roughness 0 and no intervals"
  EXPECT_NE(text.find("a CPPN course has roughness 0 and no intervals"), std::string::npos);
  pb::EnvDef def = cppn_course();
  EXPECT_EQ(refusal(def), "");
  def.mutable_encoding()->set_roughness(1);
  EXPECT_EQ(refusal(def).rfind("encoding.cppn: a CPPN course has ground_roughness 0 and no obstacle intervals", 0), 0u)
      << refusal(def);
  def = cppn_course();
  gene(def, "pit_gap").set_lo(0);
  gene(def, "pit_gap").set_hi(1);
  EXPECT_EQ(refusal(def).rfind("encoding.cppn: a CPPN course has ground_roughness 0 and no obstacle intervals", 0), 0u)
      << refusal(def);

  // "its genome is a connected, acyclic network from the input (node I) to the output (node O)"
  ASSERT_TRUE(std::regex_search(
      text, match,
      std::regex(R"(a connected, acyclic network from the input \(node (\d+)\) to the output \(node (\d+)\))")));
  const int input = std::stoi(match[1]), output = std::stoi(match[2]);
  def = cppn_course();
  def.mutable_encoding()->mutable_cppn()->clear_connections();
  EXPECT_EQ(refusal(def), "encoding.cppn.connections: no path from the input to the output");
  def = cppn_course();  // 0 → 1 → 2 → 1
  pb::CppnGenome& genome = *def.mutable_encoding()->mutable_cppn();
  genome.add_nodes()->set_id(2);
  for (const auto& [from, to] : {std::pair{1, 2}, {2, 1}}) {
    pb::CppnConnection& c = *genome.add_connections();
    c.set_from_node(from);
    c.set_to_node(to);
  }
  EXPECT_EQ(refusal(def), "encoding.cppn.connections: they form a cycle");
  pb::EnvDef moved = cppn_course();
  pb::CppnGenome& g = *moved.mutable_encoding()->mutable_cppn();
  g.mutable_nodes(0)->set_id(output);  // ascending ids: the output first, then the input moved to 2
  g.mutable_nodes(0)->set_role(pb::CppnNode::OUTPUT);
  g.mutable_nodes(1)->set_id(input + 2);
  g.mutable_nodes(1)->set_role(pb::CppnNode::INPUT);
  EXPECT_EQ(number_in(refusal(moved), R"(the input is node (\d+)$)"), input) << refusal(moved);
  moved = cppn_course();
  moved.mutable_encoding()->mutable_cppn()->mutable_nodes(1)->set_id(output + 2);
  EXPECT_EQ(number_in(refusal(moved), R"(the output is node (\d+)$)"), output) << refusal(moved);
}

TEST(ConfigReferenceTest, ThePaperColumnIsThePaperPresetsValue) {
  // paper.textproto sets poet.mc_low 50 against the default 25, and writes es.perturbations as the default
  const std::optional<std::vector<std::string>> mc_low = row_of("poet.mc_low");
  ASSERT_TRUE(mc_low.has_value());
  EXPECT_EQ((*mc_low)[2], "`25`");
  EXPECT_EQ((*mc_low)[3], "**`50`**");
  const std::optional<std::vector<std::string>> perturbations = row_of("es.perturbations");
  ASSERT_TRUE(perturbations.has_value());
  EXPECT_EQ((*perturbations)[3], "`256`");
}

TEST(ConfigReferenceTest, EveryPresetHasASectionWithWhatItChanges) {
  for (const auto& entry : fs::directory_iterator(kConfigs)) {
    if (entry.path().extension() != ".textproto") continue;
    EXPECT_NE(page().find("\n### " + entry.path().filename().string() + "\n"), std::string::npos) << entry.path();
  }
  // quick.textproto's iterations are the first row of its table
  const size_t quick = page().find("\n### quick.textproto\n");
  ASSERT_NE(quick, std::string::npos);
  const Expected<pb::RunConfig> config = load_run_config((kConfigs / "quick.textproto").string());
  ASSERT_TRUE(config.has_value()) << config.error();
  EXPECT_NE(page().find("| `iterations` | `" + std::to_string(config->iterations()) + "` | `50000` |", quick),
            std::string::npos);
}

TEST(ConfigReferenceTest, ADirectoryWithoutThePaperPresetOrWithABadPresetIsAnErrorNamingIt) {
  testing::ScratchDir dir;
  const Expected<std::string> empty = config_reference_page(dir.path());
  ASSERT_FALSE(empty.has_value());
  EXPECT_NE(empty.error().find("paper.textproto"), std::string::npos) << empty.error();

  std::ofstream(dir.path() / "bad.textproto") << "mode: POET\nes { l2_coeff: 2 }\n";
  const Expected<std::string> bad = config_reference_page(dir.path());
  ASSERT_FALSE(bad.has_value());
  EXPECT_NE(bad.error().find("bad.textproto: es.l2_coeff: must be in [0, 1] (got 2)"), std::string::npos)
      << bad.error();

  const Expected<std::string> missing = config_reference_page(dir.path() / "absent");
  ASSERT_FALSE(missing.has_value());
  EXPECT_NE(missing.error().find("absent"), std::string::npos) << missing.error();
}

}  // namespace
}  // namespace poet
