#include "common/formats/envgen/env_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>
#include <vector>

#include "common/formats/envgen/cppn_json.h"
#include "common/plumbing/text_file.h"

namespace poet {
namespace {

using nlohmann::json;

constexpr std::array<std::string_view, 7> kIntervalKeys = {"pit_gap",      "stump_width", "stump_height", "stump_float",
                                                           "stair_height", "stair_width", "stair_steps"};

using IntervalMember = std::optional<Interval> EnvEncoding::*;

IntervalMember interval_member(std::string_view key) {
  if (key == "pit_gap") return &EnvEncoding::pit_gap;
  if (key == "stump_width") return &EnvEncoding::stump_width;
  if (key == "stump_height") return &EnvEncoding::stump_height;
  if (key == "stump_float") return &EnvEncoding::stump_float;
  if (key == "stair_height") return &EnvEncoding::stair_height;
  if (key == "stair_width") return &EnvEncoding::stair_width;
  return &EnvEncoding::stair_steps;
}

// Integer genes are written as JSON integers, like the reference's Python lists.
bool is_integer_gene(std::string_view key) {
  return key == "stump_width" || key == "stump_float" || key == "stair_width" || key == "stair_steps";
}

Unexpected fail(std::string message) { return Unexpected{std::move(message)}; }

// A JSON number as a double; booleans are not numbers here (nlohmann agrees).
std::optional<double> number(const json& j) {
  if (!j.is_number()) return std::nullopt;
  return j.get<double>();
}

std::optional<std::string> read_interval(const json& j, std::string_view key, std::optional<Interval>& out) {
  const std::string k(key);
  if (!j.is_array()) return k + ": must be [] or a list [lo, hi] of two numbers, got " + j.type_name();
  if (j.empty()) {
    out.reset();
    return std::nullopt;
  }
  if (j.size() != 2) return k + ": must be [] or [lo, hi], got a list of " + std::to_string(j.size());
  const std::optional<double> lo = number(j[0]);
  const std::optional<double> hi = number(j[1]);
  if (!lo || !hi) return k + ": bounds must be numbers";
  if (!std::isfinite(*lo) || !std::isfinite(*hi)) return k + ": bounds must be finite numbers";
  out = Interval{*lo, *hi};
  return std::nullopt;
}

json interval_json(const std::optional<Interval>& iv, bool integer) {
  if (!iv) return json::array();
  if (integer) return json::array({static_cast<int64_t>(iv->lo), static_cast<int64_t>(iv->hi)});
  return json::array({iv->lo, iv->hi});
}

// Parses text, reporting a duplicate key (nlohmann keeps the last silently) and naming the key whose value a
// syntax or range error (1e999 overflows a double) interrupted.
Expected<json> parse_json(std::string_view text) {
  if (text.size() > kMaxEnvDefBytes) {
    return fail("text of " + std::to_string(text.size()) + " bytes exceeds the limit of " +
                std::to_string(kMaxEnvDefBytes));
  }
  std::vector<std::set<std::string>> keys_by_object;
  std::string last_key;
  std::string duplicate;
  auto track = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) keys_by_object.emplace_back();
    if (event == json::parse_event_t::object_end && !keys_by_object.empty()) keys_by_object.pop_back();
    if (event == json::parse_event_t::key) {
      last_key = parsed.get<std::string>();
      if (!keys_by_object.empty() && !keys_by_object.back().insert(last_key).second && duplicate.empty())
        duplicate = last_key;
    }
    return true;
  };
  json doc;
  try {
    doc = json::parse(text.begin(), text.end(), track);
  } catch (const json::out_of_range& e) {
    const std::string where = last_key.empty() ? "" : last_key + ": ";
    return fail(where + "number out of range of a double: " + e.what());
  } catch (const json::exception& e) {
    const std::string where = last_key.empty() ? "" : " (after key \"" + last_key + "\")";
    return fail("malformed JSON" + where + ": " + e.what());
  }
  if (!duplicate.empty()) return fail(duplicate + ": duplicate key");
  return doc;
}

// Reads the whole of a regular file no larger than kMaxEnvDefBytes.
}  // namespace

json encoding_to_json(const EnvEncoding& e) {
  json config = json::object();
  config["name"] = e.name;
  config["ground_roughness"] = e.roughness;
  for (std::string_view key : kIntervalKeys)
    config[std::string(key)] = interval_json(e.*interval_member(key), is_integer_gene(key));
  if (e.cppn) config["cppn"] = cppn_to_json(*e.cppn);
  return config;
}

Expected<EnvEncoding> encoding_from_json(const json& config) {
  if (!config.is_object()) return fail(std::string("config: must be an object, got ") + config.type_name());
  for (const auto& [key, value] : config.items()) {
    const bool known = key == "name" || key == "ground_roughness" || key == "cppn" ||
                       std::find(kIntervalKeys.begin(), kIntervalKeys.end(), key) != kIntervalKeys.end();
    if (!known) return fail(key + ": unknown key in config");
  }

  EnvEncoding e;
  if (!config.contains("ground_roughness")) return fail("ground_roughness: missing from config");
  const std::optional<double> roughness = number(config["ground_roughness"]);
  if (!roughness) return fail("ground_roughness: must be a number");
  e.roughness = *roughness;
  for (std::string_view key : kIntervalKeys) {
    const std::string k(key);
    if (!config.contains(k)) return fail(k + ": missing from config (use [] for an absent type)");
    if (auto err = read_interval(config[k], key, e.*interval_member(key))) return fail(*err);
  }
  if (config.contains("cppn")) {
    Expected<CppnGenome> genome = cppn_from_json(config["cppn"]);
    if (!genome) return fail(genome.error());
    e.cppn = std::make_shared<const CppnGenome>(std::move(*genome));
  }
  if (auto err = validate(e)) return fail(*err);

  if (config.contains("name")) {
    if (!config["name"].is_string()) return fail("name: must be a string");
    e.name = config["name"].get<std::string>();
  } else {
    e.name = reference_name(e);
  }
  return e;
}

json to_json(const EnvDef& def) {
  json object = json::object();
  object["config"] = encoding_to_json(def.encoding);
  object["seed"] = def.seed;
  return object;
}

Expected<EnvDef> env_def_from_json(const json& object) {
  if (!object.is_object())
    return fail(std::string("expected a JSON object {\"config\", \"seed\"}, got ") + object.type_name());
  for (const auto& [key, value] : object.items())
    if (key != "config" && key != "seed") return fail(key + ": unknown key (expected \"config\" and \"seed\")");
  if (!object.contains("config")) return fail("config: missing");
  if (!object.contains("seed")) return fail("seed: missing");

  Expected<EnvEncoding> encoding = encoding_from_json(object["config"]);
  if (!encoding) return fail(encoding.error());

  // a seed may be written 7 or 7.0, but must be a whole number in [0, 10^6)
  const json& seed = object["seed"];
  const std::optional<double> s = number(seed);
  if (!s) return fail(std::string("seed: must be an integer, got ") + seed.type_name());
  if (!std::isfinite(*s) || *s != std::floor(*s)) return fail("seed: must be an integer");
  if (*s < 0 || *s >= kMaxEnvSeed) return fail("seed: must be in [0, " + std::to_string(kMaxEnvSeed) + ")");
  return EnvDef{std::move(encoding).value(), static_cast<uint32_t>(*s)};
}

std::string env_def_json_text(const EnvDef& def) { return to_json(def).dump(2) + "\n"; }

Expected<EnvDef> parse_env_def(std::string_view text) {
  Expected<json> doc = parse_json(text);
  if (!doc) return fail(doc.error());
  return env_def_from_json(*doc);
}

Expected<EnvDef> load_env_def(const std::filesystem::path& path) {
  Expected<std::string> text = read_text_file(path, kMaxEnvDefBytes);
  if (!text) return fail(path.string() + ": " + text.error());
  Expected<EnvDef> def = parse_env_def(*text);
  if (!def) return fail(path.string() + ": " + def.error());
  return def;
}

std::optional<std::string> save_env_def(const std::filesystem::path& path, const EnvDef& def) {
  const std::string prefix = "cannot save environment to " + path.string() + ": ";
  if (auto err = validate(def.encoding)) return prefix + *err;
  if (def.seed >= kMaxEnvSeed) return prefix + "seed: must be in [0, " + std::to_string(kMaxEnvSeed) + ")";
  if (auto err = write_file_atomically(path, env_def_json_text(def))) return prefix + *err;
  return std::nullopt;
}

}  // namespace poet
