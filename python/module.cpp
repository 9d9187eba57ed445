// The Python module poet._poet (the package poet re-exports it): the walker as a Gymnasium-style environment,
// policies and their evaluation — bindings only, over EpisodeEnv, VectorEnv and the simulation. Arguments from
// Python are hostile input, checked by the helpers: wrong shapes, dtypes and non-finite actions are ValueError
// (array_args.h), and so are integers out of range, whatever their size (int_args.h); a step outside an episode is
// RuntimeError, unreadable files give the tools' messages. The GIL is released while episodes run.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/formats/policy/policy_file.h"
#include "common/formats/suite_score_json.h"
#include "common/program/command_line.h"
#include "pictures/walker_frame.h"
#include "python/array_args.h"
#include "python/course_spec.h"
#include "python/episode_env.h"
#include "python/int_args.h"
#include "python/run_view.h"
#include "python/vector_env.h"
#include "simulation/course_sweep.h"
#include "simulation/policy/mlp.h"
#include "simulation/rollout.h"
#include "simulation/suite/course_suite.h"
#include "simulation/walker/walker_constants.h"
#include "simulation/walker/walker_spaces.h"

namespace py = pybind11;

namespace poet::python {
namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

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

// reset()'s options: Gymnasium's, none of which the walker takes; only their type is checked.
void check_reset_options(const py::object& options) {
  if (!options.is_none() && !py::isinstance<py::dict>(options))
    throw std::invalid_argument("options must be a dict or None");
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

// The names of a space's indices, in order: OBSERVATION_NAMES and ACTION_NAMES.
template <size_t N>
py::tuple index_names(const std::array<walker::SpaceIndex, N>& indices) {
  py::tuple names(N);
  for (size_t i = 0; i < N; ++i) names[i] = py::str(indices[i].name.data(), indices[i].name.size());
  return names;
}

// Each index as a dict (name, meaning, low, high), for the environment's card.
template <size_t N>
py::list index_fields(const std::array<walker::SpaceIndex, N>& indices) {
  py::list fields;
  for (const walker::SpaceIndex& index : indices) {
    py::dict field;
    field["name"] = py::str(index.name.data(), index.name.size());
    field["meaning"] = py::str(index.meaning.data(), index.meaning.size());
    field["low"] = index.low;
    field["high"] = index.high;
    fields.append(field);
  }
  return fields;
}

// The constants of walker_constants.h that the environment's card states: its reward, episode end and start.
py::dict walker_constants() {
  using namespace walker;
  py::dict c;
  c["scale"] = kScale;
  c["fps"] = kFps;
  c["motors_torque"] = kMotorsTorque;
  c["speed_hip"] = kSpeedHip;
  c["speed_knee"] = kSpeedKnee;
  c["lidar_range"] = kLidarRange;
  c["lidar_rays"] = kLidarRays;
  c["torque_cost"] = kTorqueCost;
  c["fall_reward"] = kFallReward;
  c["init_x"] = kInitX;
  c["init_y"] = kInitY;
  c["finish_x"] = kFinishX;
  c["leg_start_angle"] = kLegStartAngle;
  c["hip_lower"] = kHipLower;
  c["hip_upper"] = kHipUpper;
  c["knee_lower"] = kKneeLower;
  c["knee_upper"] = kKneeUpper;
  c["max_time_limit"] = kMaxTimeLimit;
  c["max_env_seed"] = kMaxEnvSeed;
  return c;
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
    check_reset_options(options);
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

// VectorEnv's face: arguments checked and converted, the GIL released while the walkers step, results as numpy.
class PyVectorWalkerEnv {
 public:
  PyVectorWalkerEnv(const std::vector<CourseSpec>& courses, const py::int_& num_envs, const py::int_& threads,
                    const std::string& lidar, double push_scale, const py::int_& max_steps)
      : env_(courses, vector_size(num_envs), thread_count(threads), walker_options(lidar, push_scale),
             episode_steps(max_steps)) {}

  py::tuple reset(const std::optional<py::int_>& seed, const py::object& options) {
    check_reset_options(options);
    const std::optional<uint32_t> first =
        seed ? std::optional(first_terrain_seed(*seed, static_cast<size_t>(env_.size()))) : std::nullopt;
    {
      py::gil_scoped_release release;
      env_.reset(first);
    }
    return py::make_tuple(observations(), infos());
  }

  // Before reset(), RuntimeError from VectorEnv::step once the actions are found well formed.
  py::tuple step(const py::handle& actions) {
    const std::vector<Action> rows = finite_rows<kActDim>(actions, "actions", static_cast<size_t>(env_.size()));
    {
      py::gil_scoped_release release;
      env_.step(rows);
    }
    const std::vector<EpisodeStep>& steps = env_.last_steps();
    return py::make_tuple(observations(), column<double>(steps.size(), [&](size_t i) { return steps[i].reward; }),
                          column<bool>(steps.size(), [&](size_t i) { return steps[i].terminated; }),
                          column<bool>(steps.size(), [&](size_t i) { return steps[i].truncated; }), infos());
  }

  int size() const { return env_.size(); }

 private:
  py::array_t<float> observations() const {
    const auto n = static_cast<size_t>(env_.size());
    py::array_t<float> out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(kObsDim)});
    auto view = out.mutable_unchecked<2>();
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < kObsDim; ++j)
        view(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) =
            static_cast<float>(env_.walker(i).observation()[j]);
    return out;
  }

  py::dict infos() const {
    const auto n = static_cast<size_t>(env_.size());
    const std::vector<EpisodeStep>& steps = env_.last_steps();
    py::dict info;
    info["seed"] = column<int64_t>(n, [&](size_t i) { return env_.walker(i).seed(); });
    info["steps"] = column<int64_t>(n, [&](size_t i) { return env_.walker(i).steps(); });
    info["finished"] = column<bool>(n, [&](size_t i) { return steps[i].finished; });
    info["fell"] = column<bool>(n, [&](size_t i) { return steps[i].fell; });
    return info;
  }

  VectorEnv env_;
};

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

  py::class_<PyPolicy>(m, "Policy", R"doc(A 24→40→40→4 tanh network, the project's policy (and the reference's files).

Made by Policy.load from a policy file; act gives the network's action for an observation, the action the
coordinator's rollouts and poet-eval take.

Example:
    >>> walker = poet.Policy.load("data/walkers/flat-walker.json")
    >>> walker.act(np.zeros(poet.OBS_DIM, dtype=np.float32)).shape
    (4,)
    >>> walker.params.shape
    (2804,)
)doc")
      .def_static("load", &PyPolicy::load, py::arg("path"), R"doc(Reads a policy file.

Args:
    path (str): a policy file, JSON: [[p0, ..., p2803], score] or [[p0, ..., p2803]] (the reference's form).

Returns:
    Policy: the file's network, with the score it records.

Raises:
    ValueError: the file cannot be read or is not a policy file (the message says why).

Example:
    >>> poet.Policy.load("data/walkers/flat-walker.json").params.size
    2804
)doc")
      .def("act", &PyPolicy::act, py::arg("obs"), R"doc(The network's action for one observation.

Args:
    obs (numpy.ndarray): one observation: shape (OBS_DIM,) = (24,), of a floating-point dtype, every value finite.

Returns:
    numpy.ndarray: the action, float32 of shape (4,), each in [-1, 1].

Raises:
    ValueError: obs is not a numpy array of a floating-point dtype and shape (24,), or a value is not finite.

Example:
    >>> walker = poet.Policy.load("data/walkers/flat-walker.json")
    >>> action = walker.act(np.zeros(24, dtype=np.float32))
    >>> action.dtype, bool(np.all(np.abs(action) <= 1))
    (dtype('float32'), True)
)doc")
      .def_property_readonly("params", &PyPolicy::params,
                             "numpy.ndarray: the 2804 parameters, float64, in the reference's layout (a copy).")
      .def_property_readonly("score", &PyPolicy::score,
                             "float or None: the score the file records, None when it records none.");

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

  static_assert(walker::kObservationIndices.size() == size_t{kObsDim} &&
                walker::kActionIndices.size() == size_t{kActDim});
  m.attr("OBS_DIM") = static_cast<int>(kObsDim);
  m.attr("ACT_DIM") = static_cast<int>(kActDim);
  m.attr("DEFAULT_PUSH_SCALE") = walker::kDefaultPushScale;
  m.attr("DEFAULT_MAX_STEPS") = walker::kDefaultTimeLimit;
  m.attr("OBSERVATION_NAMES") = index_names(walker::kObservationIndices);
  m.attr("ACTION_NAMES") = index_names(walker::kActionIndices);
  m.def("_observation_fields", [] { return index_fields(walker::kObservationIndices); });
  m.def("_action_fields", [] { return index_fields(walker::kActionIndices); });
  m.def("_walker_constants", &walker_constants);
  m.attr("__version__") = poet::project_version();  // the project's version (CMakeLists.txt)
}
