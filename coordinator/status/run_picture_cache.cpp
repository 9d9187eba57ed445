#include "coordinator/status/run_picture_cache.h"

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

#include "report/pair_episode.h"
#include "report/run_pictures.h"
#include "run_directory/files/run_directory.h"
#include "simulation/enum_names.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

constexpr size_t kMaxEntries = 64;  // pictures kept for one checkpoint
constexpr int kEpisodeEvery = 2;    // a pose every 2 steps: 25 per simulated second

double rounded(double v) { return std::round(v * 1000.0) / 1000.0; }

const char* box_kind(ObstacleKind kind) {
  static constexpr std::array<std::string_view, 3> kNames = {"pit", "stump", "stair"};
  return enum_name(kind, kNames, "?").data();
}

}  // namespace

std::string RunPictureCache::stamp() const {
  std::error_code ec;
  const std::filesystem::path path = run_dir_ / kCheckpointFile;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return {};
  const auto time = std::filesystem::last_write_time(path, ec);
  if (ec) return {};
  return std::to_string(size) + "@" + std::to_string(time.time_since_epoch().count());
}

Expected<std::shared_ptr<const RunSnapshot>> RunPictureCache::snapshot() const {
  const std::string now = stamp();
  {
    std::lock_guard lock(mutex_);
    if (run_ && now == stamp_) return run_;
  }
  Expected<RunSnapshot> read = read_run_snapshot(run_dir_);
  if (!read) return Unexpected{read.error()};
  auto run = std::make_shared<const RunSnapshot>(std::move(*read));
  std::lock_guard lock(mutex_);
  if (now != stamp_) entries_.clear();
  stamp_ = now;
  run_ = run;
  return run;
}

Expected<std::string> RunPictureCache::cached(
    const std::string& key, const std::function<Expected<std::string>(const RunSnapshot&)>& make) const {
  Expected<std::shared_ptr<const RunSnapshot>> run = snapshot();
  if (!run) return Unexpected{run.error()};
  {
    std::lock_guard lock(mutex_);
    if (const auto found = entries_.find(key); found != entries_.end() && run_ == *run) return found->second;
  }
  Expected<std::string> bytes = make(**run);
  if (!bytes) return bytes;
  std::lock_guard lock(mutex_);
  if (run_ == *run) {
    if (entries_.size() >= kMaxEntries) entries_.clear();
    entries_[key] = *bytes;
  }
  return bytes;
}

Expected<std::string> RunPictureCache::picture(const PictureRequest& request) const {
  const std::string key = "picture/" + std::to_string(static_cast<int>(request.kind)) + "/" +
                          std::to_string(static_cast<int>(request.encoding)) + "/" + std::to_string(request.pair);
  return cached(key, [&](const RunSnapshot& run) { return render_run_picture(run, request); });
}

Expected<std::string> RunPictureCache::episode_json(int pair) const {
  return cached("episode/" + std::to_string(pair), [&](const RunSnapshot& run) -> Expected<std::string> {
    Expected<RolloutResult> episode = pair_episode(run, pair);
    if (!episode) return Unexpected{episode.error()};
    const Pair& p = *run.state.find(pair);
    const Terrain terrain = Terrain::generate(p.env);
    nlohmann::json out;
    out["pair"] = pair;
    out["env"] = p.env.encoding.name;
    out["seed"] = p.env.seed;
    out["iteration"] = run.state.next_iteration;
    out["steps"] = episode->steps;
    out["finished"] = episode->finished;
    out["fell"] = episode->fell;
    out["reward"] = episode->total_reward;
    out["every"] = kEpisodeEvery;
    out["finish_x"] = walker::kFinishX;
    nlohmann::json ground = nlohmann::json::array();
    for (const Point& g : terrain.ground()) ground.push_back({rounded(g.x), rounded(g.y)});
    out["ground"] = std::move(ground);
    nlohmann::json boxes = nlohmann::json::array();
    for (const TerrainBox& b : terrain.boxes())
      boxes.push_back({rounded(b.x0), rounded(b.y0), rounded(b.x1), rounded(b.y1), box_kind(b.kind)});
    out["boxes"] = std::move(boxes);
    nlohmann::json hull = nlohmann::json::array();
    for (const auto& v : walker::kHullPoly) hull.push_back({v[0] / walker::kScale, v[1] / walker::kScale});
    out["shapes"] = {{"hull", std::move(hull)},
                     {"upper_leg", {walker::kLegW, walker::kLegH}},
                     {"lower_leg", {walker::kLegW * walker::kLowerLegWidthFactor, walker::kLegH}}};
    nlohmann::json frames = nlohmann::json::array();
    const auto& t = episode->trajectory;
    for (size_t i = 0; i < t.size(); i += kEpisodeEvery) {
      nlohmann::json frame = nlohmann::json::array();
      for (const BodyPose& body : t[i]) {
        frame.push_back(rounded(body.x));
        frame.push_back(rounded(body.y));
        frame.push_back(rounded(body.angle));
      }
      frames.push_back(std::move(frame));
    }
    out["frames"] = std::move(frames);
    return out.dump();
  });
}

}  // namespace poet
