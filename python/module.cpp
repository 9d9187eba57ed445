// The Python module poet._poet (the package poet re-exports it): the walker as a Gymnasium-style environment,
// policies and their evaluation. Arguments from Python are hostile input: wrong shapes, dtypes and non-finite
// actions are ValueError, and so are integers out of range, whatever their size (int_args.h); a step outside an
// episode is RuntimeError, unreadable files give the tools' messages. The GIL is released while episodes run.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/policy/policy_file.h"
#include "common/suite_score_json.h"
#include "course_spec.h"
#include "episode_env.h"
#include "int_args.h"
#include "pictures/walker_frame.h"
#include "run_view.h"
#include "simulation/course_sweep.h"
#include "simulation/policy/mlp.h"
#include "simulation/rollout.h"
#include "simulation/suite/course_suite.h"
#include "simulation/walker/walker_constants.h"
#include "thread_team.h"

namespace py = pybind11;

namespace poet::python {
namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// The most walkers one VectorWalkerEnv steps. Each holds its own Box2D world and course (about 220 KB), so 4096
// of them take some 900 MB: a bound well past what one machine's cores step usefully (a few walkers per core),
// which keeps a mistyped num_envs (10**9) a ValueError rather than an out-of-memory kill.
constexpr int64_t kMaxVectorEnvs = 4096;
// Threads for episodes, as the tools' --threads.
constexpr int64_t kMaxThreads = 4096;
constexpr int64_t kLastSeed = int64_t{kMaxEnvSeed} - 1;

// A terrain seed from Python, of any size: in [0, kMaxEnvSeed), else ValueError.
uint32_t terrain_seed(const py::int_& seed) { return static_cast<uint32_t>(int_in_range(seed, 0, kLastSeed, "seed")); }

// The steps of an episode stepped from Python: at least one, at most what an int holds.
int episode_steps(const py::int_& max_steps) {
  return static_cast<int>(int_in_range(max_steps, 1, INT_MAX, "max_steps"));
}

// A frame's width or height as render() takes it.
int frame_pixels(const py::int_& value, const char* name) {
  return static_cast<int>(int_in_range(value, kMinFramePixels, kMaxFramePixels, name));
}

LidarRule lidar_rule(const std::string& name) {
  if (name == "nearest") return LidarRule::kNearest;
  if (name == "first") return LidarRule::kFirst;
  throw std::invalid_argument("lidar must be 'nearest' or 'first', got '" + name + "'");
}

WalkerOptions walker_options(const std::string& lidar, double push_scale) {
  if (!std::isfinite(push_scale) || push_scale < 0)
    throw std::invalid_argument("push_scale must be a finite number >= 0");
  WalkerOptions options;
  options.lidar = lidar_rule(lidar);
  options.push_scale = push_scale;
  return options;
}

// A 1-D floating-point array of n finite values, as doubles; anything else is ValueError naming `what`.
template <size_t N>
std::array<double, N> finite_vector(const py::handle& value, const char* what) {
  if (!py::isinstance<py::array>(value))
    throw std::invalid_argument(std::string(what) + " must be a numpy array of shape (" + std::to_string(N) + ",)");
  const py::array array = py::reinterpret_borrow<py::array>(value);
  if (array.dtype().kind() != 'f')
    throw std::invalid_argument(std::string(what) + " must hold floating-point numbers, got dtype " +
                                std::string(py::str(array.dtype())));
  if (array.ndim() != 1 || array.shape(0) != static_cast<py::ssize_t>(N))
    throw std::invalid_argument(std::string(what) + " must have shape (" + std::to_string(N) + ",), got " +
                                std::string(py::str(py::tuple(
                                    py::cast(std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim()))))));
  const auto doubles = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  std::array<double, N> out{};
  for (size_t i = 0; i < N; ++i) {
    out[i] = doubles.at(static_cast<py::ssize_t>(i));
    if (!std::isfinite(out[i]))
      throw std::invalid_argument(std::string(what) + "[" + std::to_string(i) + "] is not finite");
  }
  return out;
}

// A 1-D array of n values, value(i) each: the one way results become numpy columns here.
template <class T, class Value>
py::array_t<T> column(size_t n, Value value) {
  py::array_t<T> out(static_cast<py::ssize_t>(n));
  auto view = out.template mutable_unchecked<1>();
  for (size_t i = 0; i < n; ++i) view(static_cast<py::ssize_t>(i)) = static_cast<T>(value(i));
  return out;
}

template <size_t N>
FloatArray float_array(const std::array<double, N>& values) {
  FloatArray out(static_cast<py::ssize_t>(N));
  auto view = out.mutable_unchecked<1>();
  for (size_t i = 0; i < N; ++i) view(static_cast<py::ssize_t>(i)) = static_cast<float>(values[i]);
  return out;
}

py::dict episode_info(const EpisodeEnv& env, bool finished, bool fell) {
  py::dict info;
  info["seed"] = env.seed();
  info["steps"] = env.steps();
  info["x"] = env.hull_x();
  info["finished"] = finished;
  info["fell"] = fell;
  return info;
}

class PyWalkerEnv {
 public:
  // width and height: render()'s frame, the pictures' default size when not given; checked here, not at the first
  // frame (Gymnasium's rule: an env's rendering is settled when it is made).
  PyWalkerEnv(CourseSpec course, const std::optional<py::int_>& seed, const std::string& lidar, double push_scale,
              const py::int_& max_steps, const std::optional<py::int_>& width, const std::optional<py::int_>& height)
      : env_(std::move(course), seed ? std::optional(terrain_seed(*seed)) : std::nullopt,
             walker_options(lidar, push_scale), episode_steps(max_steps)) {
    if (width) frame_.width = frame_pixels(*width, "width");
    if (height) frame_.height = frame_pixels(*height, "height");
    if (auto error = frame_options_error(frame_)) throw std::invalid_argument(*error);
  }

  py::tuple reset(const std::optional<py::int_>& seed, const py::object& options) {
    if (!options.is_none() && !py::isinstance<py::dict>(options))
      throw std::invalid_argument("options must be a dict or None");
    const Observation& obs = env_.reset(seed ? std::optional(terrain_seed(*seed)) : std::nullopt);
    return py::make_tuple(float_array(obs), episode_info(env_, false, false));
  }

  py::tuple step(const py::handle& action) {
    const Action a = finite_vector<kActDim>(action, "action");
    const EpisodeStep s = env_.step(a);
    return py::make_tuple(float_array(env_.observation()), s.reward, s.terminated, s.truncated,
                          episode_info(env_, s.finished, s.fell));
  }

  // The current frame as uint8 RGB of shape (height, width, 3), drawn by the pictures library.
  py::array_t<uint8_t> render() const {
    if (!env_.has_episode()) throw std::logic_error("render() before reset(): call reset() first");
    Expected<FrameImage> frame = render_walker_frame(env_.terrain(), env_.pose(), frame_);
    if (!frame) throw std::invalid_argument(frame.error());
    py::array_t<uint8_t> out({frame->height, frame->width, 3});
    std::copy(frame->rgb.begin(), frame->rgb.end(), out.mutable_data());
    return out;
  }

  const EpisodeEnv& episode() const { return env_; }

 private:
  EpisodeEnv env_;
  FrameOptions frame_;  // render()'s
};

class PyPolicy {
 public:
  explicit PyPolicy(PolicyFile file) : file_(std::move(file)), mlp_(file_.params) {}

  static PyPolicy load(const std::string& path) {
    Expected<PolicyFile> file = load_policy(path);
    if (!file) throw std::invalid_argument(file.error());
    return PyPolicy(std::move(*file));
  }

  FloatArray act(const py::handle& obs) const {
    const Observation o = finite_vector<kObsDim>(obs, "obs");
    return float_array(mlp_.act(o));
  }

  py::array_t<double> params() const { return py::array_t<double>(file_.params.size(), file_.params.data()); }
  std::optional<double> score() const { return file_.score; }
  const Mlp& mlp() const { return mlp_; }

 private:
  PolicyFile file_;
  Mlp mlp_;
};

// num_envs walkers stepped together on C++ threads. Gymnasium's next-step autoreset: the step after an episode
// ends resets that walker (its action ignored) and reports the first observation with reward 0, neither
// terminated nor truncated. Walker i runs courses[i % len(courses)].
class PyVectorWalkerEnv {
 public:
  PyVectorWalkerEnv(const std::vector<CourseSpec>& courses, const py::int_& num_envs, const py::int_& threads,
                    const std::string& lidar, double push_scale, const py::int_& max_steps)
      : team_(team_size(courses, num_envs, threads)) {
    const WalkerOptions options = walker_options(lidar, push_scale);
    const int64_t count = num_envs.cast<int64_t>();  // checked by team_size
    const int steps = episode_steps(max_steps);
    for (int64_t i = 0; i < count; ++i)
      envs_.emplace_back(courses[static_cast<size_t>(i) % courses.size()], std::nullopt, options, steps);
    ended_.assign(envs_.size(), 0);
  }

  // seed: walker i gets seed + i, so the seed leaves room for every walker's below kMaxEnvSeed.
  py::tuple reset(const std::optional<py::int_>& seed, const py::object& options) {
    if (!options.is_none() && !py::isinstance<py::dict>(options))
      throw std::invalid_argument("options must be a dict or None");
    std::vector<std::optional<uint32_t>> seeds(envs_.size());
    if (seed) {
      const int64_t last = kLastSeed - static_cast<int64_t>(envs_.size() - 1);
      if (*seed < py::int_(0) || *seed > py::int_(last))
        throw std::invalid_argument("seed must be in [0, " + std::to_string(last) +
                                    "] (walker i gets seed + i, each below " + std::to_string(kMaxEnvSeed) + "), got " +
                                    int_text(*seed));
      for (size_t i = 0; i < envs_.size(); ++i)
        seeds[i] = static_cast<uint32_t>(seed->cast<int64_t>() + static_cast<int64_t>(i));
    }
    {
      py::gil_scoped_release release;
      team_.run(size(), [&](int i) { envs_[static_cast<size_t>(i)].reset(seeds[static_cast<size_t>(i)]); });
    }
    ended_.assign(envs_.size(), 0);
    started_ = true;
    std::vector<EpisodeStep> none(envs_.size());
    return py::make_tuple(observations(), infos(none));
  }

  py::tuple step(const py::handle& actions) {
    if (!started_) throw std::logic_error("step() before reset(): call reset() first");
    const std::vector<Action> a = action_rows(actions);
    std::vector<EpisodeStep> steps(envs_.size());
    {
      py::gil_scoped_release release;
      team_.run(size(), [&](int k) {
        const auto i = static_cast<size_t>(k);
        if (ended_[i]) {
          envs_[i].reset();
          return;
        }
        steps[i] = envs_[i].step(a[i]);
      });
    }
    // written here, not by the threads: the flags of neighbouring walkers share a cache line
    for (size_t i = 0; i < envs_.size(); ++i) ended_[i] = steps[i].terminated || steps[i].truncated ? 1 : 0;
    return py::make_tuple(observations(), column<double>(steps.size(), [&](size_t i) { return steps[i].reward; }),
                          column<bool>(steps.size(), [&](size_t i) { return steps[i].terminated; }),
                          column<bool>(steps.size(), [&](size_t i) { return steps[i].truncated; }), infos(steps));
  }

  int size() const { return static_cast<int>(envs_.size()); }

 private:
  // The threads of the team for the arguments, checked before any walker is made: no more threads than walkers.
  static int team_size(const std::vector<CourseSpec>& courses, const py::int_& num_envs, const py::int_& threads) {
    if (courses.empty()) throw std::invalid_argument("courses must name at least one course");
    const int64_t walkers = int_in_range(num_envs, 1, kMaxVectorEnvs, "num_envs");
    return static_cast<int>(std::min(int_in_range(threads, 1, kMaxThreads, "threads"), walkers));
  }

  // (num_envs, 4) floating-point finite actions; anything else is ValueError.
  std::vector<Action> action_rows(const py::handle& value) const {
    const std::string shape = "(" + std::to_string(envs_.size()) + ", " + std::to_string(kActDim) + ")";
    if (!py::isinstance<py::array>(value))
      throw std::invalid_argument("actions must be a numpy array of shape " + shape);
    const py::array array = py::reinterpret_borrow<py::array>(value);
    if (array.dtype().kind() != 'f')
      throw std::invalid_argument("actions must hold floating-point numbers, got dtype " +
                                  std::string(py::str(array.dtype())));
    if (array.ndim() != 2 || array.shape(0) != static_cast<py::ssize_t>(envs_.size()) || array.shape(1) != kActDim)
      throw std::invalid_argument("actions must have shape " + shape);
    const auto doubles = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
    const auto view = doubles.unchecked<2>();
    std::vector<Action> rows(envs_.size());
    for (size_t i = 0; i < rows.size(); ++i)
      for (size_t j = 0; j < kActDim; ++j) {
        rows[i][j] = view(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j));
        if (!std::isfinite(rows[i][j]))
          throw std::invalid_argument("actions[" + std::to_string(i) + ", " + std::to_string(j) + "] is not finite");
      }
    return rows;
  }

  py::array_t<float> observations() const {
    py::array_t<float> out({static_cast<py::ssize_t>(envs_.size()), static_cast<py::ssize_t>(kObsDim)});
    auto view = out.mutable_unchecked<2>();
    for (size_t i = 0; i < envs_.size(); ++i)
      for (size_t j = 0; j < kObsDim; ++j)
        view(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = static_cast<float>(envs_[i].observation()[j]);
    return out;
  }

  py::dict infos(const std::vector<EpisodeStep>& steps) const {
    const size_t n = envs_.size();
    py::dict info;
    info["seed"] = column<int64_t>(n, [&](size_t i) { return envs_[i].seed(); });
    info["steps"] = column<int64_t>(n, [&](size_t i) { return envs_[i].steps(); });
    info["finished"] = column<bool>(n, [&](size_t i) { return steps[i].finished; });
    info["fell"] = column<bool>(n, [&](size_t i) { return steps[i].fell; });
    return info;
  }

  std::vector<EpisodeEnv> envs_;
  std::vector<char> ended_;  // ended at the last step: reset at the next
  ThreadTeam team_;          // kept between steps: starting threads each step would cost a fifth of a step
  bool started_ = false;
};

// evaluate's and evaluate_suite's episodes run to their end inside one call: their length is bounded as the tools'.
int time_limit(const py::int_& max_steps) {
  return static_cast<int>(int_in_range(max_steps, 1, walker::kMaxTimeLimit, "max_steps"));
}

int thread_count(const py::int_& threads) { return static_cast<int>(int_in_range(threads, 1, kMaxThreads, "threads")); }

py::dict evaluate(const PyPolicy& policy, const CourseSpec& course, const std::vector<py::int_>& seeds,
                  const py::int_& threads_arg, const std::string& lidar, double push_scale,
                  const py::int_& max_steps_arg) {
  const int threads = thread_count(threads_arg);
  const int max_steps = time_limit(max_steps_arg);
  const WalkerOptions options = walker_options(lidar, push_scale);
  std::vector<uint32_t> terrain_seeds;
  for (const py::int_& s : seeds) terrain_seeds.push_back(terrain_seed(s));
  std::vector<RolloutResult> episodes;
  {
    py::gil_scoped_release release;
    episodes = run_episodes(policy.mlp(), course.encoding, terrain_seeds, options, max_steps, threads);
  }
  const size_t n = episodes.size();
  py::dict out;
  out["return"] = column<double>(n, [&](size_t i) { return episodes[i].total_reward; });
  out["steps"] = column<int64_t>(n, [&](size_t i) { return episodes[i].steps; });
  out["finished"] = column<bool>(n, [&](size_t i) { return episodes[i].finished; });
  out["fell"] = column<bool>(n, [&](size_t i) { return episodes[i].fell; });
  return out;
}

// The policy on a named test suite: suite_score_json.h's document (every episode) as JSON text, the numbers
// poet-eval --suite --json writes.
std::string evaluate_suite(const PyPolicy& policy, const std::string& name, const py::int_& threads_arg,
                           const std::string& lidar, double push_scale, const py::int_& max_steps_arg) {
  const int threads = thread_count(threads_arg);
  const int max_steps = time_limit(max_steps_arg);
  const std::optional<CourseSuite> suite = named_suite(name);
  if (!suite) throw std::invalid_argument("unknown suite '" + name + "'");
  const WalkerOptions options = walker_options(lidar, push_scale);
  SuiteScore score;
  {
    py::gil_scoped_release release;
    score = run_suite(policy.mlp(), *suite, options, max_steps, threads);
  }
  return to_json(score, *suite).dump();
}

}  // namespace
}  // namespace poet::python

PYBIND11_MODULE(_poet, m) {
  using namespace poet;
  using namespace poet::python;
  m.doc() = "poet's C++ core: the POET bipedal walker, policies and their evaluation";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::logic_error& e) {
      if (dynamic_cast<const std::invalid_argument*>(&e)) {
        PyErr_SetString(PyExc_ValueError, e.what());
      } else {
        PyErr_SetString(PyExc_RuntimeError, e.what());
      }
    }
  });

  py::class_<CourseSpec>(m, "_Course", "A course resolved from a name, an environment file or JSON text.");
  m.def("_course_from_name_or_file", &course_from_name_or_file, py::arg("course"));
  m.def("_course_from_json_text", &course_from_json_text, py::arg("text"));

  py::class_<PyWalkerEnv>(m, "_WalkerEnv")
      .def(py::init<CourseSpec, const std::optional<py::int_>&, const std::string&, double, const py::int_&,
                    const std::optional<py::int_>&, const std::optional<py::int_>&>(),
           py::arg("course"), py::arg("seed"), py::arg("lidar"), py::arg("push_scale"), py::arg("max_steps"),
           py::arg("width"), py::arg("height"))
      .def("reset", &PyWalkerEnv::reset, py::arg("seed") = py::none(), py::arg("options") = py::none())
      .def("step", &PyWalkerEnv::step, py::arg("action"))
      .def("render", &PyWalkerEnv::render)
      .def_property_readonly("seed", [](const PyWalkerEnv& e) { return e.episode().seed(); })
      .def_property_readonly("max_steps", [](const PyWalkerEnv& e) { return e.episode().max_steps(); });

  py::class_<PyPolicy>(m, "Policy", "A 24→40→40→4 tanh network, the project's policy (and the reference's files).")
      .def_static("load", &PyPolicy::load, py::arg("path"),
                  "Reads a policy file ([[p0 ... p2803], score] or [[p...]]); ValueError with the reason if it "
                  "cannot.")
      .def("act", &PyPolicy::act, py::arg("obs"),
           "The action (float32, shape (4,), each in [-1, 1]) for one observation (shape (24,)).")
      .def_property_readonly("params", &PyPolicy::params, "The 2804 parameters, float64.")
      .def_property_readonly("score", &PyPolicy::score, "The score recorded in the file, or None.");

  py::class_<PyVectorWalkerEnv>(m, "_VectorWalkerEnv")
      .def(py::init<const std::vector<CourseSpec>&, const py::int_&, const py::int_&, const std::string&, double,
                    const py::int_&>(),
           py::arg("courses"), py::arg("num_envs"), py::arg("threads"), py::arg("lidar"), py::arg("push_scale"),
           py::arg("max_steps"))
      .def("reset", &PyVectorWalkerEnv::reset, py::arg("seed") = py::none(), py::arg("options") = py::none())
      .def("step", &PyVectorWalkerEnv::step, py::arg("actions"))
      .def_property_readonly("num_envs", &PyVectorWalkerEnv::size);

  m.def("_evaluate_suite", &evaluate_suite, py::arg("policy"), py::arg("suite"), py::arg("threads"), py::arg("lidar"),
        py::arg("push_scale"), py::arg("max_steps"));
  m.def("_suite_names", [] {
    std::vector<std::string> names;
    for (std::string_view n : suite_names()) names.emplace_back(n);
    return names;
  });
  m.def("_evaluate", &evaluate, py::arg("policy"), py::arg("course"), py::arg("seeds"), py::arg("threads"),
        py::arg("lidar"), py::arg("push_scale"), py::arg("max_steps"));

  m.def(
      "_read_run",
      [](const std::string& dir) {
        RunView view;
        {
          py::gil_scoped_release release;
          view = read_run_view(dir);
        }
        py::list pairs;
        for (const PairView& p : view.pairs) {
          py::dict pair;
          pair["id"] = p.id;
          pair["env"] = p.env_json;
          pair["theta"] = py::array_t<double>(static_cast<py::ssize_t>(p.theta.size()), p.theta.data());
          pair["best_theta"] = py::array_t<double>(static_cast<py::ssize_t>(p.best_theta.size()), p.best_theta.data());
          pairs.append(pair);
        }
        py::dict out;
        out["report"] = view.report_json;
        out["events"] = view.events_json;
        out["pair_stats"] = py::bytes(view.stats_csv);
        out["config"] = view.config_text;
        out["next_iteration"] = view.next_iteration;
        out["live"] = view.live;
        out["pairs"] = pairs;
        return out;
      },
      py::arg("dir"));

  m.attr("OBS_DIM") = static_cast<int>(kObsDim);
  m.attr("ACT_DIM") = static_cast<int>(kActDim);
  m.attr("DEFAULT_PUSH_SCALE") = walker::kDefaultPushScale;
  m.attr("DEFAULT_MAX_STEPS") = walker::kDefaultTimeLimit;
}
