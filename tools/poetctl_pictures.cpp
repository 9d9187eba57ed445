#include "tools/poetctl_pictures.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "common/program/tool_flags.h"
#include "common/text/utf8.h"
#include "pictures/canvas.h"
#include "report/run_pictures.h"
#include "run_directory/reading/run_snapshot.h"
#include "tools/poetctl_exit.h"

namespace poet {

// poetctl picture: the request an output path asks for, or the message saying why not.
Expected<PictureRequest> picture_request(const std::string& kind_name, const std::string& out, int pair) {
  const std::optional<PictureKind> kind = picture_kind(kind_name);
  if (!kind) return Unexpected{"no picture \"" + kind_name + "\"; one of " + picture_kind_names()};
  const size_t dot = out.rfind('.');
  const std::optional<PictureEncoding> encoding =
      dot == std::string::npos ? std::nullopt : picture_encoding(out.substr(dot + 1));
  if (!encoding) return Unexpected{out + ": the file name must end in .png, .svg or .gif"};
  if (needs_pair(*kind) && pair < 0) return Unexpected{kind_name + " is a pair's picture: give --pair ID"};
  if (!needs_pair(*kind) && pair >= 0) return Unexpected{kind_name + " is the run's picture: no --pair"};
  const PictureRequest request{*kind, *encoding, pair};
  if (std::optional<std::string> problem = encoding_problem(request)) return Unexpected{*problem};
  return request;
}

// The picture from a run directory's files (read only), written to out.
int picture_from_files(const std::string& run_dir, const PictureRequest& request, const std::string& out) {
  if (is_inside(out, run_dir)) {
    std::fprintf(stderr, "poetctl picture: %s is inside the run directory; pictures are written elsewhere\n",
                 out.c_str());
    return kExitUsage;
  }
  Expected<RunSnapshot> run = read_run_snapshot(run_dir);
  if (!run) {
    std::fprintf(stderr, "poetctl picture: %s\n", run.error().c_str());
    return kExitUsage;
  }
  if (request.pair >= 0 && !run->state.find(request.pair)) {
    std::fprintf(stderr, "poetctl picture: no pair %d in %s (pairs 0 to %zu)\n", request.pair, run_dir.c_str(),
                 run->state.pairs.size() - 1);
    return kExitUsage;
  }
  Expected<std::string> bytes = render_run_picture(*run, request);
  if (!bytes) {
    std::fprintf(stderr, "poetctl picture: %s\n", bytes.error().c_str());
    return kExitUnreachable;
  }
  if (std::string error = write_bytes(out, *bytes); !error.empty()) {
    std::fprintf(stderr, "poetctl picture: %s\n", error.c_str());
    return kExitUnreachable;
  }
  std::printf("%s: %s, %zu bytes\n", out.c_str(), mime_type(request.encoding), bytes->size());
  return 0;
}

// The path of the status socket's picture endpoint for a request.
std::string picture_path(const std::string& kind_name, const std::string& out, const PictureRequest& request) {
  const std::string extension = out.substr(out.rfind('.') + 1);
  if (request.pair >= 0) return "/pictures/pairs/" + std::to_string(request.pair) + "/" + kind_name + "." + extension;
  return "/pictures/" + kind_name + "." + extension;
}

namespace {

// A Content-Type's media type, lowercase, without its parameters ("image/svg+xml; charset=utf-8" -> "image/svg+xml").
std::string media_type(const std::string& content_type) {
  std::string type = content_type.substr(0, content_type.find(';'));
  std::erase_if(type, [](unsigned char c) { return std::isspace(c); });
  std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return std::tolower(c); });
  return type;
}

// Whether bytes begin as a file of the encoding does: PNG's and GIF's signatures; for SVG, XML (a declaration or
// the svg element, after white space) that has an svg element near its start.
bool has_signature(PictureEncoding encoding, std::string_view bytes) {
  switch (encoding) {
    case PictureEncoding::kPng:
      return bytes.starts_with("\x89PNG\r\n\x1a\n");
    case PictureEncoding::kGif:
      return bytes.starts_with("GIF87a") || bytes.starts_with("GIF89a");
    case PictureEncoding::kSvg: {
      const std::string_view head = bytes.substr(0, 4096);
      const size_t start = head.find_first_not_of(" \t\r\n");
      return start != std::string_view::npos && head.find("<svg") != std::string_view::npos &&
             (head.substr(start).starts_with("<?xml") || head.substr(start).starts_with("<svg"));
    }
  }
  return false;
}

}  // namespace

std::optional<std::string> picture_problem(PictureEncoding encoding, const std::string& content_type,
                                           std::string_view bytes) {
  const std::string expected = mime_type(encoding);
  if (media_type(content_type) != expected)
    return "the answer is " + (content_type.empty() ? std::string("of no type") : printable_text(content_type)) +
           ", not " + expected;
  if (!has_signature(encoding, bytes)) return "the answer says " + expected + " but its bytes are not one";
  return std::nullopt;
}

int save_picture(const std::string& out, const StatusAnswer& answer, const std::string& path,
                 PictureEncoding encoding) {
  if (std::optional<std::string> problem = picture_problem(encoding, answer.content_type, answer.body)) {
    std::fprintf(stderr, "poetctl picture: %s: %s; %s not written\n", path.c_str(), problem->c_str(), out.c_str());
    return kExitUnreachable;
  }
  if (std::string error = write_bytes(out, answer.body); !error.empty()) {
    std::fprintf(stderr, "poetctl picture: %s\n", error.c_str());
    return kExitUnreachable;
  }
  std::printf("%s: %zu bytes from %s\n", out.c_str(), answer.body.size(), path.c_str());
  return 0;
}

}  // namespace poet
