#pragma once
// The run's pictures and a pair's episode (for the dashboard's replay) as the status socket serves them: read
// from the run directory's last checkpoint (run_directory/reading/run_snapshot.h, never changing the directory) and
// kept until the checkpoint changes, so a page polling every few seconds costs one rendering per picture per
// checkpoint. Thread-safe; a rendering runs outside the lock, so a slow picture never holds up another request.

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "report/picture_request.h"
#include "run_directory/reading/run_snapshot.h"

namespace poet {

// The keys of the object episode_json writes, each always there (docs/reference/examples/pair-episode.json is checked
// to have exactly these). A key added to or dropped from episode_json belongs here too.
inline constexpr std::string_view kEpisodeKeys[] = {"pair",     "env",   "seed",   "iteration", "steps",
                                                    "finished", "fell",  "reward", "every",     "finish_x",
                                                    "ground",   "boxes", "shapes", "frames"};

class RunPictureCache {
 public:
  explicit RunPictureCache(std::filesystem::path run_dir) : run_dir_(std::move(run_dir)) {}

  // The picture's bytes, or an error: "no run yet" before the first checkpoint, an unknown pair, a kind in an
  // encoding it has not.
  Expected<std::string> picture(const PictureRequest& request) const;

  // GET /pairs/{id}/episode: the pair's current θ on its own course — the course (ground points, obstacle boxes,
  // the finish line), the walker's body shapes and its pose every `every` steps — as JSON.
  Expected<std::string> episode_json(int pair) const;

 private:
  // The checkpoint's identity (size and modification time): a new checkpoint clears the cache.
  std::string stamp() const;
  Expected<std::shared_ptr<const RunSnapshot>> snapshot() const;
  Expected<std::string> cached(const std::string& key,
                               const std::function<Expected<std::string>(const RunSnapshot&)>& make) const;

  const std::filesystem::path run_dir_;
  mutable std::mutex mutex_;
  mutable std::string stamp_;
  mutable std::shared_ptr<const RunSnapshot> run_;
  mutable std::map<std::string, std::string> entries_;
};

}  // namespace poet
