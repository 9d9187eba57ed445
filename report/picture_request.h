#pragma once
// What a picture of a run is asked for by: its kind, its encoding and, for a pair's episode, the pair (names as
// in run_pictures.h). Kept apart from the renderers so the status socket's headers need not see the simulation.

#include <optional>
#include <string>
#include <string_view>

namespace poet {

enum class PictureKind { kScores, kLevels, kAnnecs, kTree, kRose, kCourse, kFilmstrip, kWalk, kLineage };
enum class PictureEncoding { kPng, kSvg, kGif };

struct PictureRequest {
  PictureKind kind = PictureKind::kScores;
  PictureEncoding encoding = PictureEncoding::kPng;
  int pair = -1;  // the pair of course, filmstrip, walk and lineage
};

// "scores", "levels", ... → the kind; nullopt for an unknown name.
std::optional<PictureKind> picture_kind(std::string_view name);
// "png", "svg", "gif" → the encoding; nullopt for another.
std::optional<PictureEncoding> picture_encoding(std::string_view extension);
bool needs_pair(PictureKind kind);
// The kinds' names, for messages: "scores, levels, annecs, tree, rose, course, filmstrip, walk, lineage".
std::string picture_kind_names();
// Why a request's kind cannot come in its encoding ("the walk is a GIF (.gif)"), or nullopt.
std::optional<std::string> encoding_problem(const PictureRequest& request);
// The MIME type of an encoding.
const char* mime_type(PictureEncoding encoding);

}  // namespace poet
