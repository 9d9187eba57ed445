#include "common/formats/envgen/env_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "awkward_env_def.h"
#include "scratch_dir.h"
#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

using testing::awkward_def;
using testing::expect_same;

TEST(EnvJson, TextRoundTripIsExact) {
  const EnvDef def = awkward_def();
  const Expected<EnvDef> back = parse_env_def(env_def_json_text(def));
  ASSERT_TRUE(back) << back.error();
  expect_same(*back, def);
  EXPECT_EQ(back->encoding.stump_height->lo, 5e-324);
  EXPECT_EQ(back->encoding.roughness, 0.1 + 0.2);
}

TEST(EnvJson, NamedCoursesRoundTrip) {
  for (std::string_view name : course_names()) {
    const EnvDef def{*named_course(name), 7};
    const Expected<EnvDef> back = env_def_from_json(to_json(def));
    ASSERT_TRUE(back) << name << ": " << back.error();
    expect_same(*back, def);
  }
}

TEST(EnvJson, WritesTheReferenceForm) {
  EnvDef def{*named_course("hard"), 12};
  def.encoding.stair_height.reset();
  const json j = to_json(def);
  EXPECT_EQ(j["seed"], 12);
  EXPECT_EQ(j["config"]["name"], "hard");
  EXPECT_EQ(j["config"]["ground_roughness"], 3.0);
  EXPECT_EQ(j["config"]["pit_gap"], json::array({2.0, 4.0}));
  EXPECT_TRUE(j["config"]["stump_width"][0].is_number_integer());  // integer genes as ints, like Python
  EXPECT_EQ(j["config"]["stump_width"], json::array({1, 2}));
  EXPECT_EQ(j["config"]["stair_width"], json::array());  // absent type
  EXPECT_EQ(j["config"].size(), 9u);
  EXPECT_EQ(j.size(), 2u);
  EXPECT_EQ(env_def_json_text(def).back(), '\n');
}

constexpr const char* kReferenceInts = R"({"config": {"name": "r0.3.p0_0.8.b1_0_0.4", "ground_roughness": 0.3,
  "pit_gap": [0, 0.8], "stump_width": [1, 2], "stump_height": [0, 0.4], "stump_float": [0, 1],
  "stair_height": [], "stair_width": [], "stair_steps": []}, "seed": 123456})";

constexpr const char* kReferenceFloats = R"({"seed": 123456.0, "config": {"ground_roughness": 0.3,
  "pit_gap": [0.0, 0.8], "stump_width": [1.0, 2.0], "stump_height": [0.0, 0.4], "stump_float": [0.0, 1.0],
  "stair_height": [0.2, 0.6], "stair_width": [4.0, 5.0], "stair_steps": [1.0, 2.0]}})";

TEST(EnvJson, ReadsTheReferenceFormWithInts) {
  const Expected<EnvDef> def = parse_env_def(kReferenceInts);
  ASSERT_TRUE(def) << def.error();
  const EnvEncoding& e = def->encoding;
  EXPECT_EQ(e.name, "r0.3.p0_0.8.b1_0_0.4");  // kept as written
  EXPECT_EQ(e.roughness, 0.3);
  EXPECT_EQ(e.pit_gap, (Interval{0.0, 0.8}));
  EXPECT_EQ(e.stump_width, (Interval{1.0, 2.0}));
  EXPECT_EQ(e.stump_height, (Interval{0.0, 0.4}));
  EXPECT_EQ(e.stump_float, (Interval{0.0, 1.0}));
  EXPECT_FALSE(e.stair_height || e.stair_width || e.stair_steps);
  EXPECT_EQ(def->seed, 123456u);
}

TEST(EnvJson, ReadsFloatsForIntegerGenesAndDefaultsTheName) {
  const Expected<EnvDef> def = parse_env_def(kReferenceFloats);
  ASSERT_TRUE(def) << def.error();
  EXPECT_EQ(def->encoding.stair_steps, (Interval{1.0, 2.0}));
  EXPECT_EQ(def->encoding.stair_height, (Interval{0.2, 0.6}));
  EXPECT_EQ(def->encoding.name, "r0.3.p0.0_0.8.b1.0_0.0_0.4.s1.0_0.6");  // reference_name of the genes
  EXPECT_EQ(def->seed, 123456u);
}

// Each case sets the value at a JSON pointer to the given JSON text (or removes it when the text is null), in a
// valid document; the error must name the field.
struct BadDoc {
  const char* pointer;
  const char* value;
  const char* field;
};

TEST(EnvJson, EveryBadFieldIsNamed) {
  const BadDoc cases[] = {
      {"/config", nullptr, "config"},
      {"/seed", nullptr, "seed"},
      {"/extra", "1", "extra"},
      {"/config", "5", "config"},
      {"/config", "[]", "config"},
      {"/config/colour", R"("red")", "colour"},
      {"/config/name", "5", "name"},
      {"/config/ground_roughness", nullptr, "ground_roughness"},
      {"/config/ground_roughness", R"("1")", "ground_roughness"},
      {"/config/ground_roughness", "true", "ground_roughness"},
      {"/config/ground_roughness", "null", "ground_roughness"},
      {"/config/ground_roughness", "-1", "ground_roughness"},
      {"/config/ground_roughness", "1e300", "ground_roughness"},
      {"/config/pit_gap", nullptr, "pit_gap"},
      {"/config/pit_gap", "[1]", "pit_gap"},
      {"/config/pit_gap", "[1, 2, 3]", "pit_gap"},
      {"/config/pit_gap", R"("0-0.8")", "pit_gap"},
      {"/config/pit_gap", "0.8", "pit_gap"},
      {"/config/pit_gap", "null", "pit_gap"},
      {"/config/pit_gap", R"({"lo": 0, "hi": 1})", "pit_gap"},
      {"/config/pit_gap", R"([1, "2"])", "pit_gap"},
      {"/config/pit_gap", "[true, 2]", "pit_gap"},
      {"/config/pit_gap", "[null, 2]", "pit_gap"},
      {"/config/pit_gap", "[[1], [2]]", "pit_gap"},
      {"/config/pit_gap", "[-1, 2]", "pit_gap"},
      {"/config/pit_gap", "[3, 2]", "pit_gap"},
      {"/config/stump_width", "[1.5, 2]", "stump_width"},
      {"/config/stump_float", "[]", "stump_float"},       // a type given in part
      {"/config/stair_steps", "[1, 2]", "stair_height"},  // likewise: the first missing interval is named
      {"/seed", "-1", "seed"},
      {"/seed", "1000000", "seed"},
      {"/seed", "1e300", "seed"},
      {"/seed", "1.5", "seed"},
      {"/seed", R"("7")", "seed"},
      {"/seed", "true", "seed"},
      {"/seed", "null", "seed"},
      {"/seed", "[7]", "seed"},
  };
  const json valid = json::parse(kReferenceInts);
  ASSERT_TRUE(env_def_from_json(valid));
  for (const BadDoc& c : cases) {
    json j = valid;
    const json::json_pointer pointer(c.pointer);
    if (c.value) {
      j[pointer] = json::parse(c.value);
    } else {
      j[pointer.parent_pointer()].erase(pointer.back());
    }
    const std::string what = std::string(c.pointer) + " = " + (c.value ? c.value : "(removed)");
    const Expected<EnvDef> from_json = env_def_from_json(j);
    ASSERT_FALSE(from_json) << what;
    EXPECT_TRUE(contains(from_json.error(), c.field)) << what << ": " << from_json.error();
    const Expected<EnvDef> from_text = parse_env_def(j.dump());
    ASSERT_FALSE(from_text) << what;
    EXPECT_EQ(from_text.error(), from_json.error());
  }
}

// Texts nlohmann would not produce: malformed JSON, out-of-range numbers, duplicate keys.
TEST(EnvJson, BadTextGivesAnErrorNamingTheField) {
  std::string base = kReferenceInts;
  auto replaced = [&](std::string_view from, std::string_view to) {
    std::string s = base;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const struct {
    std::string text;
    const char* mention;
  } cases[] = {
      {"", "JSON"},
      {"{", "JSON"},
      {"not json", "JSON"},
      {"[1, 2]", "object"},
      {"null", "object"},
      {replaced("\"seed\": 123456}", "\"seed\": 123456,}"), "JSON"},
      {replaced("\"ground_roughness\": 0.3", "\"ground_roughness\": NaN"), "ground_roughness"},
      {replaced("\"ground_roughness\": 0.3", "\"ground_roughness\": Infinity"), "ground_roughness"},
      {replaced("\"ground_roughness\": 0.3", "\"ground_roughness\": 1e999"), "ground_roughness"},
      {replaced("[0, 0.8]", "[0, 1e999]"), "pit_gap"},
      {replaced("[0, 0.8]", "[0, -1e999]"), "pit_gap"},
      {replaced("\"seed\": 123456", "\"seed\": 1e999"), "seed"},
      {replaced("\"seed\": 123456", "\"seed\": 1, \"seed\": 2"), "seed"},
      {replaced("\"pit_gap\": [0, 0.8]", "\"pit_gap\": [], \"pit_gap\": [0, 0.8]"), "pit_gap"},
      {replaced("\"seed\": 123456}", "\"seed\": 123456} trailing"), "JSON"},
  };
  for (const auto& c : cases) {
    Expected<EnvDef> def = Unexpected{"not run"};
    EXPECT_NO_THROW(def = parse_env_def(c.text)) << c.text;
    ASSERT_FALSE(def) << c.text;
    EXPECT_TRUE(contains(def.error(), c.mention)) << c.text << "\n-> " << def.error();
  }
}

TEST(EnvJson, RefusesOversizedText) {
  const std::string huge(kMaxEnvDefBytes + 1, ' ');
  const Expected<EnvDef> def = parse_env_def(huge);
  ASSERT_FALSE(def);
  EXPECT_TRUE(contains(def.error(), "limit"));
}

TEST(EnvJson, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = "{\"config\": " + std::string(100000, '[') + std::string(100000, ']') + ", \"seed\": 1}";
  const Expected<EnvDef> def = parse_env_def(deep);
  ASSERT_FALSE(def);
  EXPECT_TRUE(contains(def.error(), "config"));
}

class EnvJsonFile : public ::testing::Test {
 protected:
  std::vector<fs::path> entries() const {
    std::vector<fs::path> out;
    for (const auto& entry : fs::directory_iterator(dir_)) out.push_back(entry.path().filename());
    return out;
  }

  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
};

TEST_F(EnvJsonFile, SaveThenLoadLeavesOnlyTheFile) {
  const fs::path path = dir_ / "env.json";
  ASSERT_EQ(save_env_def(path, awkward_def()), std::nullopt);
  EXPECT_EQ(entries(), std::vector<fs::path>{"env.json"});
  const Expected<EnvDef> back = load_env_def(path);
  ASSERT_TRUE(back) << back.error();
  expect_same(*back, awkward_def());

  // overwriting replaces the file and still leaves no temporary behind
  const EnvDef flat{*named_course("flat"), 3};
  ASSERT_EQ(save_env_def(path, flat), std::nullopt);
  EXPECT_EQ(entries(), std::vector<fs::path>{"env.json"});
  const Expected<EnvDef> again = load_env_def(path);
  ASSERT_TRUE(again) << again.error();
  expect_same(*again, flat);
}

TEST_F(EnvJsonFile, SaveRefusesAnInvalidDefinition) {
  EnvDef def = awkward_def();
  def.encoding.pit_gap = Interval{2.0, 1.0};
  const std::optional<std::string> err = save_env_def(dir_ / "env.json", def);
  ASSERT_TRUE(err);
  EXPECT_TRUE(contains(*err, "pit_gap")) << *err;
  def = awkward_def();
  def.seed = kMaxEnvSeed;
  const std::optional<std::string> seed_err = save_env_def(dir_ / "env.json", def);
  ASSERT_TRUE(seed_err);
  EXPECT_TRUE(contains(*seed_err, "seed")) << *seed_err;
  EXPECT_TRUE(entries().empty());
}

TEST_F(EnvJsonFile, SaveIntoAMissingDirectoryIsAnError) {
  const fs::path path = dir_ / "no" / "such" / "env.json";
  std::optional<std::string> err;
  EXPECT_NO_THROW(err = save_env_def(path, awkward_def()));
  ASSERT_TRUE(err);
  EXPECT_TRUE(contains(*err, path.string())) << *err;
}

TEST_F(EnvJsonFile, LoadingAMissingFileIsAnError) {
  const fs::path path = dir_ / "missing.json";
  Expected<EnvDef> def = Unexpected{"not run"};
  EXPECT_NO_THROW(def = load_env_def(path));
  ASSERT_FALSE(def);
  EXPECT_TRUE(contains(def.error(), path.string())) << def.error();
}

TEST_F(EnvJsonFile, LoadingADirectoryOrAHugeFileIsAnError) {
  const Expected<EnvDef> from_dir = load_env_def(dir_);
  ASSERT_FALSE(from_dir);
  EXPECT_TRUE(contains(from_dir.error(), "is a directory")) << from_dir.error();

  const fs::path big = dir_ / "big.json";
  std::ofstream(big) << std::string(kMaxEnvDefBytes + 1, ' ');
  const Expected<EnvDef> from_big = load_env_def(big);
  ASSERT_FALSE(from_big);
  EXPECT_TRUE(contains(from_big.error(), "larger than")) << from_big.error();
}

TEST_F(EnvJsonFile, LoadErrorsStartWithThePath) {
  const fs::path path = dir_ / "bad.json";
  std::ofstream(path) << R"({"config": {"ground_roughness": 0.3}, "seed": 1})";
  const Expected<EnvDef> def = load_env_def(path);
  ASSERT_FALSE(def);
  EXPECT_EQ(def.error().rfind(path.string() + ": ", 0), 0u) << def.error();
  EXPECT_TRUE(contains(def.error(), "pit_gap")) << def.error();
}

}  // namespace
}  // namespace poet
