#pragma once
// Learning curves: the per-step CSVs experiments/learning_curve.sh writes (es_step, score, finished, env_steps,
// rollouts, wall_s; columns found by name), read with every bad field named, and drawn as one picture of three
// charts — evaluation score against ES steps, against environment steps and against wall time — with the
// solved score (spec §1.4) as a reference line.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "pictures/canvas.h"

namespace poet {

struct CurvePoint {
  int64_t es_step = 0;
  double score = 0;
  bool finished = false;
  int64_t env_steps = 0;
  int64_t rollouts = 0;
  double wall_s = 0;
};

struct LearningCurve {
  std::string label;
  std::vector<CurvePoint> points;  // in ES-step order
};

// The curve in `text` (the contents of `source`, which only names it in errors: "FILE:LINE: column: why"). Lines
// may end in "\r\n" and the text may begin with a UTF-8 byte-order mark, as spreadsheet programs save CSV.
Expected<LearningCurve> parse_learning_curve(const std::string& text, const std::string& source);

// The curve in the file at path: a regular file of at most 64 MB (common/plumbing/text_file.h), else an error naming
// it.
Expected<LearningCurve> read_learning_curve(const std::string& path);

// The first point that is solved: finished with a score of at least solved_score.
const CurvePoint* first_solved(const LearningCurve& curve, double solved_score);

// The three charts, stacked, as PNG or SVG bytes.
Expected<std::string> render_learning_curves(PictureFormat format, std::span<const LearningCurve> curves,
                                             double solved_score);

}  // namespace poet
