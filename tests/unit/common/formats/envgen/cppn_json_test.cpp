#include "common/formats/envgen/cppn_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/formats/envgen/env_json.h"
#include "common/formats/envgen/env_proto.h"
#include "common/text/text_format.h"

namespace poet {
namespace {

using nlohmann::json;

// input → hidden(sin) → output and input → output, with awkward doubles.
CppnGenome sample_genome() {
  CppnGenome g = cppn_seed_genome(0.1 + 0.2, -1.0 / 3.0);
  g.nodes.push_back({2, CppnRole::kHidden, CppnActivation::kSin, std::nextafter(0.2, 1.0)});
  g.connections.push_back({0, 2, 1e-17});
  g.connections.push_back({2, 1, -9.999999999999998});
  g.scale = 3.7e-5;
  canonicalize(g);
  return g;
}

EnvDef cppn_def(const CppnGenome& genome) {
  EnvDef def;
  def.encoding.cppn = std::make_shared<const CppnGenome>(genome);
  def.encoding.name = cppn_name(genome);
  def.seed = 4242;
  return def;
}

TEST(CppnJson, EnvironmentFileRoundTripIsExact) {
  const EnvDef def = cppn_def(sample_genome());
  const std::string text = env_def_json_text(def);
  EXPECT_NE(text.find("\"activation\": \"sin\""), std::string::npos);
  const Expected<EnvDef> back = parse_env_def(text);
  ASSERT_TRUE(back) << back.error();
  ASSERT_TRUE(back->encoding.is_cppn());
  EXPECT_EQ(*back->encoding.cppn, sample_genome());
  EXPECT_TRUE(back->encoding.same_genes(def.encoding));
  EXPECT_EQ(back->encoding.name, def.encoding.name);
  EXPECT_EQ(back->seed, 4242u);
}

TEST(CppnJson, ProtoRoundTripIsExact) {
  const EnvDef def = cppn_def(sample_genome());
  const Expected<EnvDef> back = env_def_from_proto(to_proto(def));
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(*back->encoding.cppn, sample_genome());
  EXPECT_EQ(back->encoding.name, def.encoding.name);
}

TEST(CppnJson, NodesAndConnectionsAreListedInTheCanonicalOrder) {
  json j = cppn_to_json(sample_genome());
  std::swap(j["nodes"][1], j["nodes"][2]);
  const Expected<CppnGenome> nodes = cppn_from_json(j);
  ASSERT_FALSE(nodes);
  EXPECT_EQ(nodes.error(), "cppn.nodes[2].id: ids must be unique and in ascending order");
  j = cppn_to_json(sample_genome());
  std::swap(j["connections"][0], j["connections"][2]);
  const Expected<CppnGenome> connections = cppn_from_json(j);
  ASSERT_FALSE(connections);
  EXPECT_EQ(connections.error(), "cppn.connections[1]: connections must be unique and ordered by (from, to)");
}

// Each hostile genome is refused with the field named.
TEST(CppnJson, BadGenomesAreRefusedNamingTheField) {
  const json good = cppn_to_json(sample_genome());
  struct Case {
    std::function<void(json&)> spoil;
    std::string error;
  };
  const Case cases[] = {
      {[](json& j) {
         j["connections"].push_back({{"from", 2}, {"to", 3}, {"weight", 1}});
         j["connections"].push_back({{"from", 3}, {"to", 2}, {"weight", 1}});
         j["nodes"].push_back({{"id", 3}, {"role", "hidden"}, {"activation", "tanh"}, {"bias", 0}});
       },
       "cppn.connections: they form a cycle"},
      {[](json& j) { j["connections"][2]["to"] = 9; }, "cppn.connections[2].to: no node 9"},
      {[](json& j) { j["connections"][1]["weight"] = 1e308; },
       "cppn.connections[1].weight: must be a finite number within ±10"},
      {[](json& j) { j["nodes"][2]["activation"] = "relu"; },
       "cppn.nodes[2].activation: must be one of identity, sin, sigmoid, square, tanh"},
      {[](json& j) { j["nodes"][2]["role"] = "bias"; },
       "cppn.nodes[2].role: must be \"input\", \"output\" or \"hidden\""},
      {[](json& j) { j["nodes"][0]["bias"] = 0.5; }, "cppn.nodes[0]: the input has no activation and no bias"},
      {[](json& j) { j["nodes"][1].erase("bias"); }, "cppn.nodes[1].bias: missing"},
      {[](json& j) { j["nodes"][1]["bias"] = "0"; }, "cppn.nodes[1].bias: must be a number, got string"},
      {[](json& j) { j["nodes"][1]["id"] = 1.5; }, "cppn.nodes[1].id: must be an integer node id"},
      {[](json& j) { j["nodes"][1]["id"] = -4; }, "cppn.nodes[1].id: must be in [0, 1000000]"},
      {[](json& j) { j["connections"][0]["gain"] = 1; }, "cppn.connections[0].gain: unknown key"},
      {[](json& j) { j.erase("scale"); }, "cppn.scale: missing"},
      {[](json& j) { j["scale"] = -1; }, "cppn.scale: must be a finite number in (0, 1e12]"},
      {[](json& j) { j["nodes"] = json::object(); }, "cppn.nodes: must be a list"},
      {[](json& j) {
         j["connections"] = json::array({{{"from", 0}, {"to", 2}, {"weight", 1}}});
       },
       "cppn.connections: no path from the input to the output"},
      {[](json& j) {
         j["nodes"] = json::array();
         for (int i = 0; i < 1'000'000; ++i) j["nodes"].push_back(i);
       },
       "cppn.nodes: 1000000 nodes; at most 256"},
  };
  for (const Case& c : cases) {
    json j = good;
    c.spoil(j);
    const Expected<CppnGenome> genome = cppn_from_json(j);
    ASSERT_FALSE(genome) << c.error;
    EXPECT_EQ(genome.error(), c.error);
  }
}

TEST(CppnJson, BadNumbersInTextAreRefused) {
  const std::string text = env_def_json_text(cppn_def(sample_genome()));
  const auto with = [&](std::string_view from, std::string_view to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return parse_env_def(t);
  };
  const Expected<EnvDef> nan = with("\"scale\": ", "\"scale\": NaN, \"x\": ");
  ASSERT_FALSE(nan);
  EXPECT_NE(nan.error().find("malformed JSON (after key \"scale\")"), std::string::npos) << nan.error();
  const Expected<EnvDef> overflow = with("\"scale\": ", "\"scale\": 1e999, \"x\": ");
  ASSERT_FALSE(overflow);
  EXPECT_NE(overflow.error().find("scale: number out of range"), std::string::npos) << overflow.error();
  // a CPPN course carries no obstacle genes
  const Expected<EnvDef> mixed = with("\"ground_roughness\": 0.0", "\"ground_roughness\": 1.0");
  ASSERT_FALSE(mixed);
  EXPECT_EQ(mixed.error(), "cppn: a CPPN course has ground_roughness 0 and no obstacle intervals");
}

TEST(CppnJson, OversizedWireGenomesAreRefusedBeforeCopying) {
  pb::EnvDef message = to_proto(cppn_def(sample_genome()));
  for (int i = 0; i < 100'000; ++i) message.mutable_encoding()->mutable_cppn()->add_nodes()->set_id(i + 3);
  const Expected<EnvDef> def = env_def_from_proto(message);
  ASSERT_FALSE(def);
  EXPECT_EQ(def.error(), "encoding.cppn.nodes: 100003 nodes; at most 256");
  pb::EnvDef nan = to_proto(cppn_def(sample_genome()));
  nan.mutable_encoding()->mutable_cppn()->mutable_connections(0)->set_weight(std::nan(""));
  const Expected<EnvDef> bad = env_def_from_proto(nan);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error(), "encoding.cppn.connections[0].weight: must be a finite number within ±10");
}

}  // namespace
}  // namespace poet
