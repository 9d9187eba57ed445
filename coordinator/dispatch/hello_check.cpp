#include "coordinator/dispatch/hello_check.h"

#include <algorithm>
#include <string_view>
#include <utility>
#include <vector>

#include "common/text/text_format.h"

namespace poet {

namespace {

// "name H" parts of an arithmetic text; empty when the text is not of that form (it comes from the network).
std::vector<std::pair<std::string, std::string>> arithmetic_parts(std::string_view text) {
  std::vector<std::pair<std::string, std::string>> parts;
  if (text.size() > 200) return {};
  while (!text.empty()) {
    const size_t end = std::min(text.find(", "), text.size());
    const std::string_view part = text.substr(0, end);
    const size_t space = part.find(' ');
    const auto plain = [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); };
    if (space == std::string_view::npos || part.size() - space - 1 != 16 ||
        !std::all_of(part.begin(), part.begin() + static_cast<std::ptrdiff_t>(space), plain) ||
        !std::all_of(part.begin() + static_cast<std::ptrdiff_t>(space) + 1, part.end(), plain))
      return {};
    parts.emplace_back(std::string(part.substr(0, space)), std::string(part.substr(space + 1)));
    text.remove_prefix(std::min(end + 2, text.size()));
  }
  return parts;
}

// Which of the coordinator's parts the worker's differ in: "math, walker"; empty when the worker named none.
std::string differing_parts(std::string_view theirs, std::string_view ours) {
  const auto their_parts = arithmetic_parts(theirs);
  std::string names;
  for (const auto& [name, value] : arithmetic_parts(ours)) {
    const auto it =
        std::find_if(their_parts.begin(), their_parts.end(), [&](const auto& p) { return p.first == name; });
    if (it != their_parts.end() && it->second != value) names += (names.empty() ? "" : ", ") + name;
  }
  return names;
}

}  // namespace

std::optional<HelloRefusal> hello_refusal(const wire::Hello& hello, const HelloExpectation& expected) {
  if (hello.protocol_version() != wire::PROTOCOL_VERSION)
    return HelloRefusal{DropReason::kWrongVersion, "protocol version " + std::to_string(hello.protocol_version()) +
                                                       ", the coordinator speaks " +
                                                       std::to_string(wire::PROTOCOL_VERSION)};
  // the arithmetic first: a machine that computes differently is told so, not that it runs another build
  if (expected.arithmetic_digest != 0 && hello.arithmetic_digest() != expected.arithmetic_digest) {
    const std::string parts = differing_parts(hello.arithmetic(), expected.arithmetic);
    return HelloRefusal{
        DropReason::kWrongArithmetic,
        "this machine computes differently from the coordinator: arithmetic digest " +
            (hello.has_arithmetic_digest() ? hex_text(hello.arithmetic_digest()) : std::string("missing")) +
            ", the coordinator's " + hex_text(expected.arithmetic_digest) +
            (parts.empty() ? std::string() : " (" + parts + " differ)") +
            ": its results would differ from the coordinator's for the same job (compare the arithmetic line of "
            "--fingerprint on both machines)"};
  }
  if (expected.fingerprint_digest != 0 && hello.fingerprint_digest() != expected.fingerprint_digest)
    return HelloRefusal{DropReason::kWrongFingerprint,
                        "build fingerprint " + hex_text(hello.fingerprint_digest()) +
                            " differs from the coordinator's " + hex_text(expected.fingerprint_digest) +
                            ": its returns would differ (compare --fingerprint of both binaries)"};
  return std::nullopt;
}

WorkerFacts facts_of_hello(const WorkerId& id, const wire::Hello& hello) {
  WorkerFacts facts;
  facts.id = id;
  facts.name = hello.name().substr(0, 200);
  facts.threads = static_cast<int>(std::clamp<uint32_t>(hello.threads(), 1, 4096));
  facts.fingerprint_digest = hello.fingerprint_digest();
  facts.arithmetic_digest = hello.arithmetic_digest();
  return facts;
}

}  // namespace poet
