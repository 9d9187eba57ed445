#include "run_directory/config/config_reference.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "common/text_format.h"
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

// Each recorded range is the validator's: a value just past its upper bound is refused with the rule's words.
TEST(ConfigReferenceTest, ARecordedRangeIsTheOneTheValidatorRefusesWith) {
  const std::regex range(R"(must be in [\[(](.+), (.+)[\])])");
  int checked = 0;
  for (const ConfigRule& rule : config_rules()) {
    std::smatch match;
    if (!std::regex_match(rule.rule, match, range)) continue;
    const double hi = std::strtod(match[2].str().c_str(), nullptr);
    pb::RunConfig config = runnable(rule.modes.front());
    ASSERT_EQ(validate(config), std::nullopt) << rule.path;
    ASSERT_TRUE(set_number(config, rule.path, hi + 1)) << rule.path;
    const std::optional<std::string> problem = validate(config);
    ASSERT_TRUE(problem.has_value()) << rule.path << " = " << hi + 1 << " is accepted";
    EXPECT_EQ(problem->rfind(rule.path + ": " + rule.rule + " (got ", 0), 0u) << *problem;
    ++checked;
  }
  EXPECT_GT(checked, 15);
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
