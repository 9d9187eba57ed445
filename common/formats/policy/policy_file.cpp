#include "common/formats/policy/policy_file.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "common/plumbing/text_file.h"
#include "simulation/policy/mlp.h"

namespace poet {
namespace {

using nlohmann::json;

Unexpected fail(std::string message) { return {std::move(message)}; }

// Empty when params and score may be written; else what is wrong with them.
std::string invalid_contents(const std::vector<double>& params, std::optional<double> score) {
  if (params.size() != static_cast<size_t>(kParamCount)) {
    return "expected " + std::to_string(kParamCount) + " parameters, got " + std::to_string(params.size());
  }
  for (size_t i = 0; i < params.size(); ++i) {
    if (!std::isfinite(params[i])) return "parameter " + std::to_string(i) + " is not finite";
  }
  if (score && !std::isfinite(*score)) return "score is not finite";
  return {};
}

}  // namespace

Expected<PolicyFile> parse_policy(std::string_view text) {
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::out_of_range& e) {
    // nlohmann refuses numbers such as 1e999 that would be infinite as a double
    return fail(std::string("number not finite as a double: ") + e.what());
  } catch (const json::exception& e) {
    return fail(std::string("malformed JSON: ") + e.what());
  }

  // shape: [[p...], score] or [[p...]]
  if (!doc.is_array()) {
    return fail(std::string("expected a top-level array [[params...], score], got ") + doc.type_name());
  }
  if (doc.size() != 1 && doc.size() != 2) {
    return fail("expected a top-level array of 1 or 2 elements ([[params...], score]), got " +
                std::to_string(doc.size()) + " elements");
  }
  const json& list = doc[0];
  if (!list.is_array()) {
    return fail(std::string("expected the parameter array as element 0, got ") + list.type_name());
  }
  if (list.size() != static_cast<size_t>(kParamCount)) {
    return fail("expected " + std::to_string(kParamCount) + " parameters, got " + std::to_string(list.size()));
  }

  // the parameters, each a finite number
  PolicyFile policy;
  policy.params.reserve(kParamCount);
  for (size_t i = 0; i < list.size(); ++i) {
    const json& p = list[i];
    if (!p.is_number()) {
      return fail("parameter " + std::to_string(i) + " is not a number (got " + p.type_name() + ")");
    }
    const double value = p.get<double>();
    if (!std::isfinite(value)) return fail("parameter " + std::to_string(i) + " is not finite");
    policy.params.push_back(value);
  }

  // the optional score
  if (doc.size() == 2) {
    const json& s = doc[1];
    if (!s.is_number()) return fail(std::string("score is not a number (got ") + s.type_name() + ")");
    const double score = s.get<double>();
    if (!std::isfinite(score)) return fail("score is not finite");
    policy.score = score;
  }
  return policy;
}

Expected<PolicyFile> load_policy(const std::filesystem::path& path) {
  Expected<std::string> text = read_text_file(path, kMaxPolicyFileBytes);
  if (!text) return fail("policy file " + path.string() + ": " + text.error());
  Expected<PolicyFile> result = parse_policy(*text);
  if (!result) return fail(path.string() + ": " + result.error());
  return result;
}

std::string policy_json_text(const std::vector<double>& params, std::optional<double> score) {
  if (std::string problem = invalid_contents(params, score); !problem.empty()) {
    throw std::invalid_argument("policy_json_text: " + problem);
  }
  // nlohmann writes each double as a short text that parses back to the same bits (Grisu2)
  json doc = json::array({json(params)});
  if (score) doc.push_back(*score);
  return doc.dump() + "\n";
}

std::optional<std::string> save_policy(const std::filesystem::path& path, const std::vector<double>& params,
                                       std::optional<double> score) {
  if (std::string problem = invalid_contents(params, score); !problem.empty()) {
    return "cannot save policy to " + path.string() + ": " + problem;
  }
  if (auto err = write_file_atomically(path, policy_json_text(params, score)))
    return "cannot save policy to " + path.string() + ": " + *err;
  return std::nullopt;
}

}  // namespace poet
