#include "common/formats/envgen/env_proto.h"

#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "common/text/text_format.h"
#include "common/text/utf8.h"

namespace poet {
namespace {

// The genes in schema order, with accessors for both forms, so each conversion is one loop.
struct IntervalField {
  std::string_view name;
  const pb::Interval& (pb::EnvEncoding::*get)() const;
  bool (pb::EnvEncoding::*has)() const;
  pb::Interval* (pb::EnvEncoding::*mutable_field)();
  std::optional<Interval> EnvEncoding::*member;
};

constexpr IntervalField kIntervalFields[] = {
    {"pit_gap", &pb::EnvEncoding::pit_gap, &pb::EnvEncoding::has_pit_gap, &pb::EnvEncoding::mutable_pit_gap,
     &EnvEncoding::pit_gap},
    {"stump_width", &pb::EnvEncoding::stump_width, &pb::EnvEncoding::has_stump_width,
     &pb::EnvEncoding::mutable_stump_width, &EnvEncoding::stump_width},
    {"stump_height", &pb::EnvEncoding::stump_height, &pb::EnvEncoding::has_stump_height,
     &pb::EnvEncoding::mutable_stump_height, &EnvEncoding::stump_height},
    {"stump_float", &pb::EnvEncoding::stump_float, &pb::EnvEncoding::has_stump_float,
     &pb::EnvEncoding::mutable_stump_float, &EnvEncoding::stump_float},
    {"stair_height", &pb::EnvEncoding::stair_height, &pb::EnvEncoding::has_stair_height,
     &pb::EnvEncoding::mutable_stair_height, &EnvEncoding::stair_height},
    {"stair_width", &pb::EnvEncoding::stair_width, &pb::EnvEncoding::has_stair_width,
     &pb::EnvEncoding::mutable_stair_width, &EnvEncoding::stair_width},
    {"stair_steps", &pb::EnvEncoding::stair_steps, &pb::EnvEncoding::has_stair_steps,
     &pb::EnvEncoding::mutable_stair_steps, &EnvEncoding::stair_steps},
};

// validate()'s message in the schema's terms: it speaks the reference's JSON key for roughness, and it does not
// quote the value, which a reader of a config file needs to find the mistake.
std::string schema_message(std::string message, const EnvEncoding& encoding) {
  constexpr std::string_view kJsonName = "ground_roughness";
  if (message.starts_with(kJsonName)) message.replace(0, kJsonName.size(), "roughness");
  const std::string_view field = std::string_view(message).substr(0, message.find(':'));
  if (field == "roughness") return message + " (got " + number_text(encoding.roughness) + ")";
  for (const IntervalField& f : kIntervalFields) {
    const std::optional<Interval>& interval = encoding.*f.member;
    if (field == f.name && interval)
      return message + " (got [" + number_text(interval->lo) + ", " + number_text(interval->hi) + "])";
  }
  return message;
}

CppnRole role_from_proto(pb::CppnNode::Role role) {
  if (role == pb::CppnNode::INPUT) return CppnRole::kInput;
  if (role == pb::CppnNode::OUTPUT) return CppnRole::kOutput;
  return CppnRole::kHidden;
}

pb::CppnNode::Role role_to_proto(CppnRole role) {
  if (role == CppnRole::kInput) return pb::CppnNode::INPUT;
  if (role == CppnRole::kOutput) return pb::CppnNode::OUTPUT;
  return pb::CppnNode::HIDDEN;
}

// The schema's activation numbers are the enum's order.
static_assert(pb::CppnNode::TANH == static_cast<int>(CppnActivation::kTanh));

// Sizes are checked before anything is copied: a message may hold far more than a genome may.
Expected<CppnGenome> cppn_from_proto(const pb::CppnGenome& message) {
  if (static_cast<size_t>(message.nodes_size()) > kMaxCppnNodes)
    return Unexpected{"cppn.nodes: " + std::to_string(message.nodes_size()) + " nodes; at most " +
                      std::to_string(kMaxCppnNodes)};
  if (static_cast<size_t>(message.connections_size()) > kMaxCppnConnections)
    return Unexpected{"cppn.connections: " + std::to_string(message.connections_size()) + " connections; at most " +
                      std::to_string(kMaxCppnConnections)};
  CppnGenome genome;
  for (const pb::CppnNode& n : message.nodes())
    genome.nodes.push_back({n.id(), role_from_proto(n.role()), static_cast<CppnActivation>(n.activation()), n.bias()});
  for (const pb::CppnConnection& c : message.connections())
    genome.connections.push_back({c.from_node(), c.to_node(), c.weight()});
  genome.scale = message.scale();
  return genome;
}

void cppn_to_proto(const CppnGenome& genome, pb::CppnGenome& message) {
  for (const CppnNode& n : genome.nodes) {
    pb::CppnNode* out = message.add_nodes();
    out->set_id(n.id);
    out->set_role(role_to_proto(n.role));
    out->set_activation(static_cast<pb::CppnNode::Activation>(n.activation));
    out->set_bias(n.bias);
  }
  for (const CppnConnection& c : genome.connections) {
    pb::CppnConnection* out = message.add_connections();
    out->set_from_node(c.from);
    out->set_to_node(c.to);
    out->set_weight(c.weight);
  }
  message.set_scale(genome.scale);
}

}  // namespace

Expected<EnvEncoding> encoding_from_proto(const pb::EnvEncoding& message) {
  EnvEncoding encoding;
  encoding.roughness = message.roughness();
  for (const IntervalField& field : kIntervalFields) {
    if (!(message.*field.has)()) continue;
    const pb::Interval& interval = (message.*field.get)();
    // A half-given interval would otherwise read its missing bound as 0 and pass silently.
    if (!interval.has_lo()) return Unexpected{std::string(field.name) + ".lo: missing (an interval gives both bounds)"};
    if (!interval.has_hi()) return Unexpected{std::string(field.name) + ".hi: missing (an interval gives both bounds)"};
    encoding.*field.member = Interval{interval.lo(), interval.hi()};
  }
  if (message.has_cppn()) {
    Expected<CppnGenome> genome = cppn_from_proto(message.cppn());
    if (!genome) return Unexpected{genome.error()};
    encoding.cppn = std::make_shared<const CppnGenome>(std::move(*genome));
  }
  if (auto error = validate(encoding)) return Unexpected{schema_message(*error, encoding)};
  if (!is_valid_utf8(message.name())) return Unexpected{std::string("name: must be UTF-8 text")};
  encoding.name = message.name().empty() ? reference_name(encoding) : message.name();
  return encoding;
}

pb::EnvEncoding to_proto(const EnvEncoding& encoding) {
  pb::EnvEncoding message;
  message.set_name(encoding.name);
  message.set_roughness(encoding.roughness);
  for (const IntervalField& field : kIntervalFields) {
    const std::optional<Interval>& interval = encoding.*field.member;
    if (!interval) continue;
    pb::Interval* out = (message.*field.mutable_field)();
    out->set_lo(interval->lo);
    out->set_hi(interval->hi);
  }
  if (encoding.cppn) cppn_to_proto(*encoding.cppn, *message.mutable_cppn());
  return message;
}

Expected<EnvDef> env_def_from_proto(const pb::EnvDef& message) {
  EnvDef def;
  Expected<EnvEncoding> encoding = encoding_from_proto(message.encoding());
  if (!encoding) return Unexpected{"encoding." + encoding.error()};
  def.encoding = std::move(*encoding);
  if (message.seed() >= kMaxEnvSeed)
    return Unexpected{"seed: must be < " + std::to_string(kMaxEnvSeed) + " (got " + std::to_string(message.seed()) +
                      ")"};
  def.seed = message.seed();
  return def;
}

pb::EnvDef to_proto(const EnvDef& def) {
  pb::EnvDef message;
  *message.mutable_encoding() = to_proto(def.encoding);
  message.set_seed(def.seed);
  return message;
}

}  // namespace poet
