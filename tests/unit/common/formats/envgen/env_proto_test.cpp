#include "common/formats/envgen/env_proto.h"

#include <google/protobuf/text_format.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "awkward_env_def.h"
#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

using google::protobuf::util::MessageDifferencer;

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

pb::EnvDef def_from_text(const std::string& text) {
  pb::EnvDef message;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &message)) << text;
  return message;
}

using testing::awkward_def;
using testing::expect_same;

TEST(EnvProto, RoundTripIsExact) {
  const EnvDef def = awkward_def();
  const pb::EnvDef message = to_proto(def);
  const Expected<EnvDef> back = env_def_from_proto(message);
  ASSERT_TRUE(back) << back.error();
  expect_same(*back, def);
  EXPECT_EQ(back->encoding.stump_height->lo, 5e-324);
  EXPECT_EQ(back->encoding.roughness, 0.1 + 0.2);
  EXPECT_TRUE(MessageDifferencer::Equals(to_proto(*back), message));
}

TEST(EnvProto, RoundTripThroughTextFormatIsExact) {
  const pb::EnvDef message = to_proto(awkward_def());
  std::string text;
  ASSERT_TRUE(google::protobuf::TextFormat::PrintToString(message, &text));
  const Expected<EnvDef> back = env_def_from_proto(def_from_text(text));
  ASSERT_TRUE(back) << back.error();
  expect_same(*back, awkward_def());
}

TEST(EnvProto, AbsentTypesStayAbsent) {
  EnvDef def;
  def.encoding.roughness = 2.5;
  def.encoding.stump_width = Interval{1, 2};
  def.encoding.stump_height = Interval{0, 0.4};
  def.encoding.stump_float = Interval{0, 1};
  def.seed = 17;
  const pb::EnvDef message = to_proto(def);
  EXPECT_FALSE(message.encoding().has_pit_gap());
  EXPECT_FALSE(message.encoding().has_stair_height());
  EXPECT_FALSE(message.encoding().has_stair_width());
  EXPECT_FALSE(message.encoding().has_stair_steps());
  EXPECT_TRUE(message.encoding().has_stump_height());
  const Expected<EnvDef> back = env_def_from_proto(message);
  ASSERT_TRUE(back) << back.error();
  expect_same(*back, def);
  EXPECT_FALSE(back->encoding.has_pits());
  EXPECT_FALSE(back->encoding.has_stairs());
  EXPECT_TRUE(back->encoding.has_stumps());
}

TEST(EnvProto, FlatRoundTrips) {
  const EnvDef flat;  // every type absent, roughness 0, name "flat"
  const Expected<EnvDef> back = env_def_from_proto(to_proto(flat));
  ASSERT_TRUE(back) << back.error();
  expect_same(*back, flat);
  EXPECT_EQ(back->encoding.name, "flat");
}

TEST(EnvProto, NamedCoursesRoundTrip) {
  for (std::string_view name : course_names()) {
    const EnvDef def{*named_course(name), 123'456};
    const Expected<EnvDef> back = env_def_from_proto(to_proto(def));
    ASSERT_TRUE(back) << name << ": " << back.error();
    expect_same(*back, def);
  }
}

TEST(EnvProto, EncodingPairRoundTrips) {
  const EnvEncoding encoding = awkward_def().encoding;
  const Expected<EnvEncoding> back = encoding_from_proto(to_proto(encoding));
  ASSERT_TRUE(back) << back.error();
  EXPECT_TRUE(back->same_genes(encoding));
  EXPECT_EQ(back->name, encoding.name);
}

TEST(EnvProto, AbsentEncodingIsFlat) {
  const Expected<EnvDef> def = env_def_from_proto(def_from_text("seed: 5"));
  ASSERT_TRUE(def) << def.error();
  EXPECT_TRUE(def->encoding.same_genes(EnvEncoding{}));
  EXPECT_EQ(def->seed, 5u);
}

TEST(EnvProto, EmptyNameBecomesReferenceName) {
  const Expected<EnvDef> def =
      env_def_from_proto(def_from_text("encoding { roughness: 0.3 pit_gap { lo: 0 hi: 0.8 } }"));
  ASSERT_TRUE(def) << def.error();
  EXPECT_EQ(def->encoding.name, reference_name(def->encoding));
  EXPECT_FALSE(def->encoding.name.empty());

  const Expected<EnvDef> named = env_def_from_proto(def_from_text("encoding { name: \"mine\" roughness: 0.3 }"));
  ASSERT_TRUE(named) << named.error();
  EXPECT_EQ(named->encoding.name, "mine");
}

TEST(EnvProto, InvalidEncodingNamesTheField) {
  const struct {
    const char* text;
    const char* prefix;
  } cases[] = {
      {"encoding { pit_gap { lo: 2 hi: 1 } }", "encoding.pit_gap:"},
      {"encoding { roughness: -1 }", "encoding.roughness:"},
      {"encoding { roughness: nan }", "encoding.roughness:"},
      {"encoding { stump_height { lo: 0 hi: 1 } stump_width { lo: 1 hi: 2 } }", "encoding.stump_float:"},
      {"encoding { stair_steps { lo: 1.5 hi: 3 } stair_width { lo: 4 hi: 5 } stair_height { lo: 0 hi: 1 } }",
       "encoding.stair_steps:"},
      {"encoding { pit_gap { lo: 1 } }", "encoding.pit_gap.hi: missing"},
      {"encoding { stump_width { hi: 2 } }", "encoding.stump_width.lo: missing"},
  };
  for (const auto& c : cases) {
    const Expected<EnvDef> def = env_def_from_proto(def_from_text(c.text));
    ASSERT_FALSE(def) << c.text;
    EXPECT_TRUE(def.error().starts_with(c.prefix)) << c.text << " -> " << def.error();
  }
}

TEST(EnvProto, ErrorQuotesTheValue) {
  EXPECT_EQ(env_def_from_proto(def_from_text("encoding { roughness: -1 }")).error(),
            "encoding.roughness: must be >= 0 (got -1)");
  EXPECT_TRUE(
      contains(env_def_from_proto(def_from_text("encoding { pit_gap { lo: 2 hi: 1.5 } }")).error(), "(got [2, 1.5])"));
}

TEST(EnvProto, SeedMustBeBelowTheMaximum) {
  const Expected<EnvDef> too_big = env_def_from_proto(def_from_text("seed: 1000000"));
  ASSERT_FALSE(too_big);
  EXPECT_EQ(too_big.error(), "seed: must be < 1000000 (got 1000000)");
  EXPECT_TRUE(contains(env_def_from_proto(def_from_text("seed: 4294967295")).error(), "seed:"));
  const Expected<EnvDef> largest = env_def_from_proto(def_from_text("seed: 999999"));
  ASSERT_TRUE(largest) << largest.error();
  EXPECT_EQ(largest->seed, 999'999u);
}

}  // namespace
}  // namespace poet
