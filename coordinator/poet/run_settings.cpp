#include "poet/run_settings.h"

namespace poet {

std::string_view mode_name(RunMode mode) {
  switch (mode) {
    case RunMode::kPoetWithoutTransfer:
      return "POET_WITHOUT_TRANSFER";
    case RunMode::kEsAlone:
      return "ES_ALONE";
    case RunMode::kDirectPath:
      return "DIRECT_PATH";
    default:
      return "POET";
  }
}

}  // namespace poet
