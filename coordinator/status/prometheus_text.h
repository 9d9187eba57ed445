#pragma once
// GET /metrics: a board view in Prometheus text format 0.0.4, every family with its HELP and TYPE, every drop
// reason present (0 when none was counted) so that a rate over it never starts from a missing series.

#include <string>

#include "coordinator/status/board_view.h"

namespace poet {

std::string prometheus_text(const BoardView& view);

}  // namespace poet
