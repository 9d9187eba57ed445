#pragma once
// poetctl picture: the run's pictures, from the live coordinator's /pictures endpoints or drawn here from a run
// directory's files. The one part of poetctl that links the drawing code (report/, pictures/).

#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "report/picture_request.h"
#include "tools/status_client/status_request.h"

namespace poet {

// The request an output path asks for (its kind, the encoding its extension names, the pair), or why not.
Expected<PictureRequest> picture_request(const std::string& kind_name, const std::string& out, int pair);

// The picture from a run directory's files (read only), written to out; returns the exit code.
int picture_from_files(const std::string& run_dir, const PictureRequest& request, const std::string& out);

// The status socket's path for a request: /pictures/KIND.EXT or /pictures/pairs/ID/KIND.EXT.
std::string picture_path(const std::string& kind_name, const std::string& out, const PictureRequest& request);

// Why an answer is not a picture in `encoding`: its Content-Type is not the encoding's MIME type, or its bytes do
// not begin as that format's do (PNG's and GIF's signatures, SVG's XML). nullopt: it is one.
std::optional<std::string> picture_problem(PictureEncoding encoding, const std::string& content_type,
                                           std::string_view bytes);

// The picture the socket answered at path, written to out when it is one in `encoding` (nothing is written
// otherwise); returns the exit code.
int save_picture(const std::string& out, const StatusAnswer& answer, const std::string& path, PictureEncoding encoding);

}  // namespace poet
