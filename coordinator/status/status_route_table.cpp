#include "coordinator/status/status_route_table.h"

#include <algorithm>
#include <charconv>
#include <utility>
#include <vector>

namespace poet {
namespace {

// "/pairs/17" → {"pairs", "17"}; "/" → {""}.
std::vector<std::string_view> segments(std::string_view path) {
  std::vector<std::string_view> out;
  if (!path.starts_with('/')) return out;
  path.remove_prefix(1);
  for (;;) {
    const size_t slash = path.find('/');
    out.push_back(path.substr(0, slash));
    if (slash == std::string_view::npos) return out;
    path.remove_prefix(slash + 1);
  }
}

// "17" → 17; nullopt for anything else (a sign, a leading zero, letters, more than 9 digits).
std::optional<int> pair_id(std::string_view digits) {
  if (digits.empty() || digits.size() > 9 || (digits.size() > 1 && digits[0] == '0')) return std::nullopt;
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return std::nullopt;
  int id = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
  if (ec != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return id;
}

const PathParam* path_param(const StatusRoute& route, std::string_view name) {
  for (const PathParam& param : route.path_params)
    if (param.name == name) return &param;
  return nullptr;
}

bool one_of(std::span<const std::string_view> values, std::string_view value) {
  return std::find(values.begin(), values.end(), value) != values.end();
}

// "walk.gif" against "{picture}.{format}": both placeholders' values from the route's table, the kind and
// encoding read with report/picture_request.h's names.
bool match_picture(const StatusRoute& route, std::string_view segment, RouteMatch& match) {
  const PathParam* picture = path_param(route, "picture");
  const PathParam* format = path_param(route, "format");
  const size_t dot = segment.rfind('.');
  if (picture == nullptr || format == nullptr || dot == std::string_view::npos) return false;
  const std::string_view name = segment.substr(0, dot), extension = segment.substr(dot + 1);
  if (!one_of(picture->values, name) || !one_of(format->values, extension)) return false;
  const std::optional<PictureKind> kind = picture_kind(name);
  const std::optional<PictureEncoding> encoding = picture_encoding(extension);
  if (!kind || !encoding) return false;
  match.picture.kind = *kind;
  match.picture.encoding = *encoding;
  return true;
}

std::optional<RouteMatch> match(const StatusRoute& route, const std::vector<std::string_view>& path) {
  const std::vector<std::string_view> pattern = segments(route.pattern);
  if (pattern.size() != path.size()) return std::nullopt;
  RouteMatch match{&route, -1, {}};
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] == "{id}") {
      const std::optional<int> id = pair_id(path[i]);
      if (!id) return std::nullopt;
      match.pair = *id;
    } else if (pattern[i] == "{picture}.{format}") {
      if (!match_picture(route, path[i], match)) return std::nullopt;
    } else if (pattern[i] != path[i]) {
      return std::nullopt;
    }
  }
  match.picture.pair = match.pair;
  return match;
}

// "{a,b,c}" for several values, "a" for one.
std::string alternatives(const std::vector<std::string_view>& values) {
  if (values.size() == 1) return std::string(values[0]);
  std::string out = "{";
  for (std::string_view value : values) out += (out.size() > 1 ? "," : "") + std::string(value);
  return out + "}";
}

// The formats a picture is served in: those of the route's table that the picture code's encoding check accepts.
std::vector<std::string_view> served_formats(std::string_view picture, std::span<const std::string_view> formats) {
  std::vector<std::string_view> served;
  const std::optional<PictureKind> kind = picture_kind(picture);
  for (std::string_view format : formats) {
    const std::optional<PictureEncoding> encoding = picture_encoding(format);
    if (kind && encoding && !encoding_problem(PictureRequest{*kind, *encoding, 0})) served.push_back(format);
  }
  return served;
}

// "{picture}.{format}" written out as the pairs served, the pictures grouped by the formats they come in
// ("{scores,levels}.{png,svg}", "walk.gif"): never a path that answers 400.
std::vector<std::string> picture_segments(const PathParam& picture, const PathParam& format) {
  std::vector<std::pair<std::vector<std::string_view>, std::vector<std::string_view>>> groups;  // formats, pictures
  for (std::string_view name : picture.values) {
    std::vector<std::string_view> formats = served_formats(name, format.values);
    if (formats.empty()) continue;
    auto group = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == formats; });
    if (group == groups.end()) group = groups.insert(groups.end(), {std::move(formats), {}});
    group->second.push_back(name);
  }
  std::vector<std::string> segments;
  for (const auto& [formats, pictures] : groups)
    segments.push_back(alternatives(pictures) + "." + alternatives(formats));
  return segments;
}

// A route's endpoints: its pattern with {id} kept, {picture}.{format} written out, the query's parameters as "=N".
std::vector<std::string> endpoints(const StatusRoute& route) {
  std::string pattern(route.pattern);
  char separator = '?';
  for (const QueryParam& param : route.query_params) {
    pattern += separator + std::string(param.name) + "=N";
    separator = '&';
  }
  constexpr std::string_view kPicture = "{picture}.{format}";
  const size_t at = pattern.find(kPicture);
  const PathParam* picture = path_param(route, "picture");
  const PathParam* format = path_param(route, "format");
  if (at == std::string::npos || picture == nullptr || format == nullptr) return {pattern};
  std::vector<std::string> out;
  for (const std::string& segment : picture_segments(*picture, *format))
    out.push_back(pattern.substr(0, at) + segment + pattern.substr(at + kPicture.size()));
  return out;
}

}  // namespace

std::optional<RouteMatch> match_route(std::string_view path) {
  const std::vector<std::string_view> parts = segments(path);
  for (const StatusRoute& route : kStatusRoutes)
    if (std::optional<RouteMatch> found = match(route, parts)) return found;
  return std::nullopt;
}

std::string endpoint_list() {
  std::string list;
  for (const StatusRoute& route : kStatusRoutes)
    for (const std::string& endpoint : endpoints(route)) list += (list.empty() ? "" : ", ") + endpoint;
  return list;
}

}  // namespace poet
