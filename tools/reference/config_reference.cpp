#include "tools/reference/config_reference.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/formats/envgen/env_proto.h"
#include "common/plumbing/text_file.h"
#include "common/text/text_format.h"
#include "proto/schema_comments.h"
#include "run_directory/config/config_rules.h"
#include "run_directory/config/run_config.h"
#include "simulation/envgen/cppn_genome.h"
#include "simulation/envgen/env_encoding.h"

namespace poet {
namespace {

namespace protobuf = google::protobuf;

// A message's fields as one table, under a heading whose slug is the section's anchor.
struct Section {
  std::string_view prefix;   // the dotted path of the message in a config ("" for the config itself)
  std::string_view message;  // its full name in the schema
  std::string_view heading;  // "es — the evolution strategy"
  int level;                 // 2 for ##, 3 for ###
};

// In the order a user meets them: the run, its parts, then what a target is made of.
constexpr Section kSections[] = {
    {"", "poet.pb.RunConfig", "run — the run as a whole", 2},
    {"es", "poet.pb.EsConfig", "es — the evolution strategy", 2},
    {"poet", "poet.pb.PoetConfig", "poet — the POET loop", 2},
    {"poet.mutation", "poet.pb.MutationConfig", "poet.mutation — the genes mutation may change", 2},
    {"walker", "poet.pb.WalkerConfig", "walker — the walker and its episodes", 2},
    {"es_alone", "poet.pb.EsAloneConfig", "es_alone — the ES-alone control", 2},
    {"direct_path", "poet.pb.DirectPathConfig", "direct_path — the direct-path curriculum", 2},
    {"target", "poet.pb.EnvDef", "target — an environment", 3},
    {"target.encoding", "poet.pb.EnvEncoding", "target.encoding — the course's genes", 3},
    {"target.encoding.<interval>", "poet.pb.Interval", "interval — a gene's range", 3},
    {"target.encoding.cppn", "poet.pb.CppnGenome", "target.encoding.cppn — a CPPN course's genome", 3},
    {"target.encoding.cppn.nodes[i]", "poet.pb.CppnNode", "cppn.nodes — a node of the genome", 3},
    {"target.encoding.cppn.connections[i]", "poet.pb.CppnConnection", "cppn.connections — a connection", 3},
};

constexpr std::string_view kModeNames[] = {"POET", "POET_WITHOUT_TRANSFER", "ES_ALONE", "DIRECT_PATH"};

// Python-Markdown's slugify (MkDocs' anchors): ASCII only, word characters, spaces and hyphens kept, lower case,
// each run of spaces and hyphens one hyphen.
std::string slug(std::string_view heading) {
  std::string kept;
  for (const char ch : heading) {
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x80) continue;
    if (std::isalnum(u) || ch == '_' || ch == '-' || ch == ' ') kept += static_cast<char>(std::tolower(u));
  }
  std::string out;
  for (const char ch : kept) {
    const bool dash = ch == ' ' || ch == '-';
    if (dash && (out.empty() || out.back() == '-')) continue;
    out += dash ? '-' : ch;
  }
  while (!out.empty() && out.back() == '-') out.pop_back();
  return out;
}

const Section* section_of(std::string_view message) {
  for (const Section& s : kSections)
    if (s.message == message) return &s;
  return nullptr;
}

// The schema's comments cite the behavioural specification the project was written from ("spec §3.1"), which is no
// page of the site: the page cites the paper instead, Table 1 by name (spec §1.4 is the paper's §4.3, Table 1).
std::string cited(std::string_view text) {
  constexpr std::string_view kSpec = "spec §";
  std::string out;
  size_t at = 0;
  for (size_t found = text.find(kSpec); found != std::string_view::npos; found = text.find(kSpec, at)) {
    out += text.substr(at, found - at);
    size_t end = found + kSpec.size();
    const auto alnum = [&](size_t i) { return i < text.size() && std::isalnum(static_cast<unsigned char>(text[i])); };
    while (alnum(end)) ++end;
    while (end < text.size() && text[end] == '.' && alnum(end + 1)) {
      ++end;
      while (alnum(end)) ++end;
    }
    const std::string_view section = text.substr(found + kSpec.size(), end - found - kSpec.size());
    if (text.substr(end).starts_with(" step ") && alnum(end + 6)) {
      end += 6;
      while (alnum(end)) ++end;
    }
    out += section == "1.4" ? "the paper's Table 1" : "the paper";
    at = end;
  }
  out += text.substr(at);
  return out;
}

// Text of a paragraph: angle brackets would open HTML, asterisks emphasis.
std::string prose(std::string_view text) {
  std::string out;
  for (const char ch : text) {
    if (ch == '<')
      out += "&lt;";
    else if (ch == '>')
      out += "&gt;";
    else if (ch == '*')
      out += "\\*";
    else
      out += ch;
  }
  return out;
}

// Text inside a table cell: a paragraph's, and a pipe would end the cell.
std::string cell(std::string_view text) {
  std::string out;
  for (const char ch : prose(text)) {
    if (ch == '|') out += '\\';
    out += ch;
  }
  return out;
}

// A sentence as a paragraph ends it: with its own stop, or a full stop.
std::string sentence(std::string text) {
  if (!text.empty() && !text.ends_with(".") && !text.ends_with(")") && !text.ends_with(":")) text += ".";
  if (text.ends_with(")") && !text.ends_with(".)")) text += ".";
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  return text;
}

std::string code(std::string_view text) { return "`" + std::string(text) + "`"; }

std::string join_path(std::string_view prefix, std::string_view name) {
  return prefix.empty() ? std::string(name) : std::string(prefix) + "." + std::string(name);
}

std::string type_text(const protobuf::FieldDescriptor& field) {
  std::string type;
  if (field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_ENUM)
    type = field.enum_type()->name();
  else if (field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_MESSAGE)
    type = field.message_type()->name();
  else
    type = field.type_name();
  return field.is_repeated() ? "repeated " + type : type;
}

// The default as a config file would write it; nothing for messages and repeated fields.
std::optional<std::string> default_text(const protobuf::FieldDescriptor& field) {
  if (field.is_repeated() || field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_MESSAGE) return std::nullopt;
  switch (field.cpp_type()) {
    case protobuf::FieldDescriptor::CPPTYPE_INT32:
      return number_text(int64_t{field.default_value_int32()});
    case protobuf::FieldDescriptor::CPPTYPE_INT64:
      return number_text(int64_t{field.default_value_int64()});
    case protobuf::FieldDescriptor::CPPTYPE_UINT32:
      return std::to_string(field.default_value_uint32());
    case protobuf::FieldDescriptor::CPPTYPE_UINT64:
      return std::to_string(field.default_value_uint64());
    case protobuf::FieldDescriptor::CPPTYPE_DOUBLE:
      return number_text(field.default_value_double());
    case protobuf::FieldDescriptor::CPPTYPE_FLOAT:
      return number_text(double{field.default_value_float()});
    case protobuf::FieldDescriptor::CPPTYPE_BOOL:
      return field.default_value_bool() ? "true" : "false";
    case protobuf::FieldDescriptor::CPPTYPE_ENUM:
      return field.default_value_enum()->name();
    case protobuf::FieldDescriptor::CPPTYPE_STRING:
      return "\"" + field.default_value_string() + "\"";
    default:
      return std::nullopt;
  }
}

// A set field's value in a message, as a config file writes it.
std::string value_text(const protobuf::Message& message, const protobuf::FieldDescriptor& field, int index) {
  const protobuf::Reflection& r = *message.GetReflection();
  const bool rep = field.is_repeated();
  switch (field.cpp_type()) {
    case protobuf::FieldDescriptor::CPPTYPE_INT32:
      return number_text(int64_t{rep ? r.GetRepeatedInt32(message, &field, index) : r.GetInt32(message, &field)});
    case protobuf::FieldDescriptor::CPPTYPE_INT64:
      return number_text(int64_t{rep ? r.GetRepeatedInt64(message, &field, index) : r.GetInt64(message, &field)});
    case protobuf::FieldDescriptor::CPPTYPE_UINT32:
      return std::to_string(rep ? r.GetRepeatedUInt32(message, &field, index) : r.GetUInt32(message, &field));
    case protobuf::FieldDescriptor::CPPTYPE_UINT64:
      return std::to_string(rep ? r.GetRepeatedUInt64(message, &field, index) : r.GetUInt64(message, &field));
    case protobuf::FieldDescriptor::CPPTYPE_DOUBLE:
      return number_text(rep ? r.GetRepeatedDouble(message, &field, index) : r.GetDouble(message, &field));
    case protobuf::FieldDescriptor::CPPTYPE_FLOAT:
      return number_text(double{rep ? r.GetRepeatedFloat(message, &field, index) : r.GetFloat(message, &field)});
    case protobuf::FieldDescriptor::CPPTYPE_BOOL:
      return (rep ? r.GetRepeatedBool(message, &field, index) : r.GetBool(message, &field)) ? "true" : "false";
    case protobuf::FieldDescriptor::CPPTYPE_ENUM:
      return (rep ? r.GetRepeatedEnum(message, &field, index) : r.GetEnum(message, &field))->name();
    case protobuf::FieldDescriptor::CPPTYPE_STRING:
      return "\"" + (rep ? r.GetRepeatedString(message, &field, index) : r.GetString(message, &field)) + "\"";
    default:
      return "";
  }
}

// The leaves a config sets, by dotted path ("poet.mc_low"; "…nodes[0].id" inside repeated messages).
void set_leaves(const protobuf::Message& message, const std::string& prefix,
                std::vector<std::pair<std::string, std::string>>& out) {
  std::vector<const protobuf::FieldDescriptor*> fields;
  message.GetReflection()->ListFields(message, &fields);
  for (const protobuf::FieldDescriptor* field : fields) {
    const std::string path = join_path(prefix, field->name());
    const protobuf::Reflection& r = *message.GetReflection();
    if (field->cpp_type() == protobuf::FieldDescriptor::CPPTYPE_MESSAGE) {
      if (!field->is_repeated()) {
        set_leaves(r.GetMessage(message, field), path, out);
        continue;
      }
      for (int i = 0; i < r.FieldSize(message, field); ++i)
        set_leaves(r.GetRepeatedMessage(message, field, i), path + "[" + std::to_string(i) + "]", out);
      continue;
    }
    if (!field->is_repeated()) {
      out.emplace_back(path, value_text(message, *field, -1));
      continue;
    }
    for (int i = 0; i < r.FieldSize(message, field); ++i)
      out.emplace_back(path + "[" + std::to_string(i) + "]", value_text(message, *field, i));
  }
}

// A leaf's default, by the path set_leaves gives; nullopt for a path that is no scalar field.
std::optional<std::string> default_at(std::string_view path) {
  const protobuf::Descriptor* message = schema_message("poet.pb.RunConfig");
  const protobuf::FieldDescriptor* field = nullptr;
  while (message && !path.empty()) {
    const size_t dot = path.find('.');
    std::string_view name = path.substr(0, dot);
    name = name.substr(0, name.find('['));
    field = message->FindFieldByName(std::string(name));
    if (!field) return std::nullopt;
    message = field->message_type();
    path = dot == std::string_view::npos ? std::string_view{} : path.substr(dot + 1);
  }
  return field && path.empty() ? default_text(*field) : std::nullopt;
}

// "POET, ES_ALONE or DIRECT_PATH"
std::string mode_list(const std::vector<std::string_view>& modes) {
  std::string out;
  for (size_t i = 0; i < modes.size(); ++i) {
    if (i > 0) out += i + 1 == modes.size() ? " or " : ", ";
    out += modes[i];
  }
  return out;
}

// Where `word` stands alone in `text` (not inside a longer name such as POET_WITHOUT_TRANSFER).
size_t find_word(std::string_view text, std::string_view word) {
  const auto name_char = [](char ch) { return std::isupper(static_cast<unsigned char>(ch)) || ch == '_'; };
  for (size_t at = text.find(word); at != std::string_view::npos; at = text.find(word, at + 1)) {
    const bool starts = at == 0 || !name_char(text[at - 1]);
    const bool ends = at + word.size() == text.size() || !name_char(text[at + word.size()]);
    if (starts && ends) return at;
  }
  return std::string_view::npos;
}

// A field's rules as the bounds cell shows them. A rule recorded in one mode whose text names that mode
// ("true contradicts mode ES_ALONE (…)") is merged with its like in other modes ("… mode POET_WITHOUT_TRANSFER,
// ES_ALONE or DIRECT_PATH (…)"); a rule of some modes only, whose text does not say so, ends with them.
std::vector<std::string> shown_rules(const std::vector<ConfigRule>& rules, std::string_view path) {
  struct Merged {
    std::string before, after;  // around the mode's name; `after` unused when no name was cut
    bool cut;
    std::vector<std::string_view> modes;
  };
  std::vector<Merged> merged;
  for (const ConfigRule& rule : rules) {
    if (rule.path != path) continue;
    Merged m{rule.rule, "", false, {}};
    for (const pb::RunConfig::Mode mode : rule.modes) m.modes.push_back(kModeNames[mode]);
    if (rule.modes.size() == 1) {
      const std::string_view name = kModeNames[rule.modes.front()];
      const size_t at = find_word(rule.rule, name);
      if (at != std::string::npos) m = {rule.rule.substr(0, at), rule.rule.substr(at + name.size()), true, m.modes};
    }
    auto like = std::find_if(merged.begin(), merged.end(), [&](const Merged& o) {
      return o.cut && m.cut && o.before == m.before && o.after == m.after;
    });
    if (like != merged.end())
      like->modes.push_back(m.modes.front());
    else
      merged.push_back(std::move(m));
  }
  std::vector<std::string> shown;
  for (const Merged& m : merged) {
    if (m.cut) {
      shown.push_back(m.before + mode_list(m.modes) + m.after);
    } else if (m.modes.size() == std::size(kModeNames)) {
      shown.push_back(m.before);
    } else {
      shown.push_back(m.before + " (mode " + mode_list(m.modes) + ")");
    }
  }
  return shown;
}

// The rules of the fields inside a target, which env_def_from_proto checks: its limits, which are data.
std::vector<std::string> target_rules(std::string_view path) {
  const std::string max_interval = number_text(kMaxIntervalValue);
  if (path == "target.seed") return {"must be < " + std::to_string(kMaxEnvSeed)};
  if (path == "target.encoding.roughness") return {"must be in [0, " + number_text(kMaxRoughness) + "]"};
  if (path == "target.encoding.<interval>.lo") return {"must be in [0, hi]", "given with hi"};
  if (path == "target.encoding.<interval>.hi") return {"must be in [lo, " + max_interval + "]", "given with lo"};
  if (path == "target.encoding.cppn.nodes") return {"at most " + std::to_string(kMaxCppnNodes)};
  if (path == "target.encoding.cppn.connections") return {"at most " + std::to_string(kMaxCppnConnections)};
  if (path == "target.encoding.cppn.scale")
    return {"must be a finite number in (0, " + number_text(kMaxCppnScale) + "]"};
  if (path == "target.encoding.cppn.nodes[i].id") return {"must be in [0, " + std::to_string(kMaxCppnNodeId) + "]"};
  if (path == "target.encoding.cppn.nodes[i].bias" || path == "target.encoding.cppn.connections[i].weight")
    return {"within ±" + number_text(kCppnParamLimit)};
  return {};
}

std::string heading_line(const Section& s) {
  return std::string(static_cast<size_t>(s.level), '#') + " " + std::string(s.heading);
}

struct Inputs {
  std::vector<ConfigRule> rules;
  std::map<std::string, std::string> paper;  // the paper preset's leaves
};

// The table of one section, then the values of its enum fields.
Expected<std::string> section_text(const Section& section, const Inputs& in) {
  const protobuf::Descriptor* message = schema_message(section.message);
  if (!message) return Unexpected{std::string(section.message) + ": not in the schema's descriptor set"};
  std::string out = heading_line(section) + "\n\n";
  const std::string about = cited(schema_comment(*message));
  if (!about.empty()) out += prose(about) + "\n\n";
  out += "| field | type | default (reference) | paper | bounds | meaning |\n";
  out += "|---|---|---|---|---|---|\n";
  std::string enums;
  for (int i = 0; i < message->field_count(); ++i) {
    const protobuf::FieldDescriptor& field = *message->field(i);
    const std::string path = join_path(section.prefix, field.name());
    std::string meaning = cited(schema_comment(field));
    if (meaning.empty())
      return Unexpected{"proto/poet.proto: " + field.full_name() + " has no comment (the page gives its meaning)"};
    meaning = cell(meaning);
    std::string default_cell = "—", paper_cell = "—";
    if (const std::optional<std::string> def = default_text(field)) {
      default_cell = code(*def);
      const auto paper = in.paper.find(path);
      paper_cell = paper == in.paper.end() ? code(*def)
                   : paper->second == *def ? code(paper->second)
                                           : "**" + code(paper->second) + "**";
    }
    if (field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_MESSAGE) {
      const Section* part = section_of(field.message_type()->full_name());
      if (part) meaning += "; see [" + std::string(part->heading) + "](#" + slug(part->heading) + ")";
    }
    std::vector<std::string> bounds = path.starts_with("target") ? target_rules(path) : shown_rules(in.rules, path);
    std::string bounds_cell;
    for (const std::string& b : bounds) bounds_cell += (bounds_cell.empty() ? "" : "<br>") + cell(b);
    if (bounds_cell.empty()) bounds_cell = "—";
    out += "| " + code(path) + " | " + type_text(field) + " | " + default_cell + " | " + paper_cell + " | " +
           bounds_cell + " | " + meaning + " |\n";
    if (field.cpp_type() == protobuf::FieldDescriptor::CPPTYPE_ENUM) {
      const protobuf::EnumDescriptor& e = *field.enum_type();
      enums += "\n" + code(path) + " is a " + e.name() + ".";
      const std::string enum_about = cited(schema_comment(e));
      if (!enum_about.empty()) enums += " " + prose(sentence(enum_about));
      enums += " Its values:\n\n";
      for (int v = 0; v < e.value_count(); ++v) {
        const protobuf::EnumValueDescriptor& value = *e.value(v);
        const std::string what = cited(schema_comment(value));
        if (what.empty())
          return Unexpected{"proto/poet.proto: " + value.full_name() + " has no comment (the page gives its meaning)"};
        enums += "- " + code(value.name()) + " — " + prose(what) + "\n";
      }
    }
  }
  return out + enums + "\n";
}

std::string intro() {
  return R"(# Run config reference

<!-- Generated by `poet-reference config --configs deploy/configs` from proto/poet.proto (the fields, their
defaults and comments), the validator (run_directory/config/run_config.cpp) and the presets. Do not edit:
tests/docs/check_reference_pages.py fails when this page is not what poet-reference prints. -->

A run config is a file in protobuf text format (the message `RunConfig` of `proto/poet.proto`) that
`poet-coordinator --config` reads. It names only what it changes: every other field keeps its default, the
reference implementation's value. A config is checked whole before a run starts: an unknown field, a value out of
its bounds or two fields that contradict each other is refused with the field's dotted path, and the process
exits with code 2. The presets in `deploy/configs/` are such files; [Presets](#presets-what-each-file-changes)
lists what each changes.

Each section below is one message of the config. Its table gives, for every field, the type, the default
(the reference implementation's value), the paper's value (the preset `paper.textproto`, in bold where it differs
from the default), the bounds the validator applies (in the words of its error message: a rule worded as a
refusal, "true contradicts mode ES_ALONE", says what is refused) and the meaning (the field's comment in
`proto/poet.proto`). "The paper" is the POET paper (Wang, Lehman, Clune and Stanley, GECCO 2019, arXiv:1901.01753,
with its supplement); "the reference" is the authors' implementation (uber-research/poet, branch `original_poet`).

)";
}

// A config that names what it changes, and a typo it refuses, with the refusal the validator really gives.
Expected<std::string> example() {
  const std::string good = "mode: POET\niterations: 200\nes { perturbations: 64 }\npoet { active_cap: 5 }\n";
  const std::string bad = "mode: POET\nes { l2_coeff: 1e300 }\n";
  const Expected<pb::RunConfig> accepted = parse_run_config(good);
  if (!accepted) return Unexpected{"the page's example config is refused: " + accepted.error()};
  const Expected<pb::RunConfig> refused = parse_run_config(bad);
  if (refused) return Unexpected{"the page's example of a refused config is accepted"};
  return "For example, a short run of POET with fewer perturbations and pairs than the reference's:\n\n"
         "```\n" +
         good +
         "```\n\n"
         "A value out of its bounds,\n\n"
         "```\n" +
         bad +
         "```\n\n"
         "is refused with the field's path and the value (`poet-coordinator --config FILE` prints this after the "
         "file's path, and exits with code 2):\n\n```\n" +
         refused.error() + "\n```\n\n";
}

// The interval genes of an encoding, in the schema's order: `pit_gap`, `stump_width`, ...
std::string interval_genes() {
  const protobuf::Descriptor* encoding = schema_message("poet.pb.EnvEncoding");
  std::string out;
  for (int i = 0; encoding && i < encoding->field_count(); ++i) {
    const protobuf::FieldDescriptor& field = *encoding->field(i);
    if (field.message_type() && field.message_type()->full_name() == "poet.pb.Interval")
      out += (out.empty() ? "" : ", ") + code(field.name());
  }
  return out;
}

// The rules of a target that are no single field's bound, and an error the validator really gives for one.
Expected<std::string> environments_intro() {
  pb::EnvDef half_given;
  half_given.mutable_encoding()->mutable_pit_gap()->set_lo(1);
  const Expected<EnvDef> refused = env_def_from_proto(half_given);
  if (refused) return Unexpected{"the page's example of a refused target is accepted"};
  return "## Environments — the targets\n\n"
         "`es_alone.target` and `direct_path.target` are environments (`EnvDef`); below, `target` stands for "
         "either, and `<interval>` for any interval gene of the encoding (" +
         interval_genes() +
         "). `env_def_from_proto` "
         "(`common/formats/envgen/env_proto.h`) checks a target as it checks an environment read from a file; the "
         "bounds shown are its limits, which are data (`simulation/envgen/env_encoding.h`, "
         "`simulation/envgen/cppn_genome.h`). Its other rules are the encoding's own, in "
         "`validate()` of `simulation/envgen/env_encoding.h`: counts and widths (`stump_width`, `stump_float`, "
         "`stair_width`, `stair_steps`) are whole numbers with lo < hi; a type's intervals are all given or none; "
         "a stump or stair is at least 1 terrain step wide and a staircase has at least 1 step; a CPPN course "
         "has roughness 0 and no intervals, and its genome is a connected, acyclic network from the input (node " +
         std::to_string(kCppnInputId) + ") to the output (node " + std::to_string(kCppnOutputId) +
         "). An error names the field inside the target: `es_alone.target." + refused.error() + "`.\n\n";
}

// A preset made from another says so in a header line, "# derives-from: quick.textproto"; the page then lists the
// fields where the two differ, computed from both files, so that what the comment says of the pair can be checked.
constexpr std::string_view kDerivesFrom = "derives-from:";

// The lines of the comment block at the head of a preset, each without its "#" and one space after it.
std::vector<std::string_view> header_lines(const std::string& text) {
  std::vector<std::string_view> lines;
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    start = end + 1;
    if (!line.starts_with("#")) break;
    line.remove_prefix(1);
    if (line.starts_with(" ")) line.remove_prefix(1);
    lines.push_back(line);
  }
  return lines;
}

// The preset a preset's header names in its derives-from line ("" when none).
std::string derived_from(const std::string& text) {
  for (std::string_view line : header_lines(text)) {
    while (line.starts_with(" ")) line.remove_prefix(1);
    if (!line.starts_with(kDerivesFrom)) continue;
    line.remove_prefix(kDerivesFrom.size());
    while (line.starts_with(" ")) line.remove_prefix(1);
    while (line.ends_with(" ")) line.remove_suffix(1);
    return std::string(line);
  }
  return "";
}

// The comment block at the head of a preset, without the proto-file, proto-message and derives-from lines.
std::string preset_comment(const std::string& text) {
  std::string out;
  for (std::string_view line : header_lines(text)) {
    if (line.starts_with("proto-file:") || line.starts_with("proto-message:") || line.starts_with(kDerivesFrom))
      continue;
    if (line.empty()) {
      if (!out.empty() && !out.ends_with("\n\n")) out += "\n\n";
      continue;
    }
    if (!out.empty() && !out.ends_with("\n")) out += " ";
    out += line;
  }
  while (out.ends_with("\n")) out.pop_back();
  return out;
}

struct Preset {
  std::string name;  // file name
  std::string comment;
  std::string base;  // the preset it derives from ("" when none)
  std::vector<std::pair<std::string, std::string>> leaves;
};

Expected<std::vector<Preset>> read_presets(const std::filesystem::path& dir) {
  std::error_code ec;
  std::vector<std::filesystem::path> files;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".textproto") files.push_back(it->path());
  if (ec) return Unexpected{dir.string() + ": " + ec.message()};
  std::sort(files.begin(), files.end());
  std::vector<Preset> presets;
  for (const std::filesystem::path& file : files) {
    const Expected<pb::RunConfig> config = load_run_config(file.string());
    if (!config) return Unexpected{config.error()};
    const Expected<std::string> text = read_text_file(file, kMaxRunConfigBytes);
    if (!text) return Unexpected{file.string() + ": " + text.error()};
    Preset preset{file.filename().string(), preset_comment(*text), derived_from(*text), {}};
    set_leaves(*config, "", preset.leaves);
    presets.push_back(std::move(preset));
  }
  for (const Preset& preset : presets) {
    if (preset.base.empty()) continue;
    const bool known =
        std::any_of(presets.begin(), presets.end(), [&](const Preset& p) { return p.name == preset.base; });
    if (!known || preset.base == preset.name)
      return Unexpected{(dir / preset.name).string() + ": derives-from names " + preset.base +
                        ", which is no other preset of " + dir.string()};
  }
  return presets;
}

// A preset's value of every leaf either sets, the default where it sets none ("—" for a target's gene it lacks).
std::map<std::string, std::string> values_with_defaults(const Preset& preset,
                                                        const std::vector<std::pair<std::string, std::string>>& other) {
  std::map<std::string, std::string> values(preset.leaves.begin(), preset.leaves.end());
  for (const auto& [path, value] : other)
    if (!values.contains(path)) values[path] = default_at(path).value_or("—");
  return values;
}

// The fields where a preset differs from the one it derives from, as a table: computed, never written by hand.
std::string differences_text(const Preset& preset, const Preset& base) {
  const std::map<std::string, std::string> ours = values_with_defaults(preset, base.leaves);
  const std::map<std::string, std::string> theirs = values_with_defaults(base, preset.leaves);
  std::string rows;
  for (const auto& [path, value] : ours) {
    const std::string& other = theirs.at(path);
    if (value != other) rows += "| " + code(path) + " | " + code(value) + " | " + code(other) + " |\n";
  }
  const std::string head = "It derives from [" + base.name + "](#" + slug(base.name) + ")";
  if (rows.empty()) return head + " and differs from it in no field.\n\n";
  return head + "; where the two differ (computed from both files):\n\n| field | " + preset.name + " | " + base.name +
         " |\n|---|---|---|\n" + rows + "\n";
}

std::string presets_text(const std::vector<Preset>& presets) {
  std::string out =
      "## Presets — what each file changes\n\n"
      "The presets of `deploy/configs/`, each with its own comment and the fields whose value differs from the "
      "default (a preset may write out more, as `paper.textproto` writes every field), and a target's every gene. A "
      "preset made from another (its header's `derives-from:` line) lists the fields where the two differ, "
      "computed from both files.\n\n";
  for (const Preset& preset : presets) {
    out += "### " + preset.name + "\n\n";
    // the file's own comment, quoted: it speaks of the file ("each difference is named below" means its lines)
    for (size_t at = 0; at < preset.comment.size();) {
      size_t end = preset.comment.find("\n\n", at);
      if (end == std::string::npos) end = preset.comment.size();
      out += "> " + prose(preset.comment.substr(at, end - at)) + "\n>\n";
      at = end + 2;
    }
    if (!preset.comment.empty()) out.replace(out.size() - 2, 2, "\n");
    std::string rows;
    for (const auto& [path, value] : preset.leaves) {
      // a target's genes are shown whole: an interval given as [0, 1] is a gene, not a default
      if (path.find(".target.") != std::string::npos) {
        rows += "| " + code(path) + " | " + code(value) + " | — |\n";
        continue;
      }
      const std::optional<std::string> def = default_at(path);
      if (def && *def == value) continue;
      rows += "| " + code(path) + " | " + code(value) + " | " + (def ? code(*def) : "—") + " |\n";
    }
    if (rows.empty()) {
      out += "It changes no default.\n\n";
    } else {
      out += "| field | value | default |\n|---|---|---|\n" + rows + "\n";
    }
    if (!preset.base.empty()) {
      const auto base =
          std::find_if(presets.begin(), presets.end(), [&](const Preset& p) { return p.name == preset.base; });
      out += differences_text(preset, *base);
    }
  }
  return out;
}

}  // namespace

Expected<std::string> config_reference_page(const std::filesystem::path& configs_dir) {
  // the presets, and among them the paper's
  const Expected<std::vector<Preset>> presets = read_presets(configs_dir);
  if (!presets) return Unexpected{presets.error()};
  const auto paper =
      std::find_if(presets->begin(), presets->end(), [](const Preset& p) { return p.name == "paper.textproto"; });
  if (paper == presets->end()) return Unexpected{(configs_dir / "paper.textproto").string() + ": does not exist"};
  Inputs in{config_rules(), {paper->leaves.begin(), paper->leaves.end()}};

  // the page: what a config is, a section per message, then the presets
  std::string page = intro();
  const Expected<std::string> shown = example();
  if (!shown) return Unexpected{shown.error()};
  page += *shown;
  for (const Section& section : kSections) {
    if (section.prefix == "target") {
      const Expected<std::string> environments = environments_intro();
      if (!environments) return Unexpected{environments.error()};
      page += *environments;
    }
    const Expected<std::string> text = section_text(section, in);
    if (!text) return Unexpected{text.error()};
    page += *text;
  }
  page += presets_text(*presets);
  while (page.ends_with("\n\n")) page.pop_back();
  // the specification the project was written from is no page of the site: the page cites the paper (cited())
  for (const std::string_view off_site : {"spec §", "spec/"})
    if (const size_t at = page.find(off_site); at != std::string::npos)
      return Unexpected{"the page cites " + std::string(off_site) + "… (\"" + page.substr(at, 40) +
                        "\"), which is no page of the site: cite the paper or a page (a preset's comment, or the "
                        "schema's through cited())"};
  return page;
}

}  // namespace poet
