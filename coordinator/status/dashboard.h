#pragma once
// The dashboard page served at GET /: one HTML document with its script and style inline (no network needed),
// following the run through the status socket's JSON and picture endpoints.

#include <string_view>

namespace poet {

std::string_view dashboard_html();

}  // namespace poet
