#include "engine/run_settings.h"

#include <array>

#include "simulation/enum_names.h"

namespace poet {

std::string_view mode_name(RunMode mode) {
  static constexpr std::array<std::string_view, 4> kNames = {"POET", "POET_WITHOUT_TRANSFER", "ES_ALONE",
                                                             "DIRECT_PATH"};
  return enum_name(mode, kNames, "?");
}

std::string_view mode_words(RunMode mode) {
  static constexpr std::array<std::string_view, 4> kWords = {"POET", "POET without transfer", "ES alone",
                                                             "direct-path curriculum"};
  return enum_name(mode, kWords, "?");
}

}  // namespace poet
