#include "poetctl_pictures.h"

#include <cstdio>

#include "common/tool_flags.h"
#include "pictures/canvas.h"
#include "poetctl_exit.h"
#include "report/run_pictures.h"
#include "run_directory/reading/run_snapshot.h"

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

int save_picture(const std::string& out, const std::string& bytes, const std::string& path) {
  if (std::string error = write_bytes(out, bytes); !error.empty()) {
    std::fprintf(stderr, "poetctl picture: %s\n", error.c_str());
    return kExitUnreachable;
  }
  std::printf("%s: %zu bytes from %s\n", out.c_str(), bytes.size(), path.c_str());
  return 0;
}

}  // namespace poet
