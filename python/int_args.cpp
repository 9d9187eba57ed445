#include "python/int_args.h"

#include <climits>
#include <stdexcept>

#include "pictures/walker_frame.h"
#include "simulation/envgen/env_encoding.h"
#include "simulation/walker/walker_constants.h"

namespace poet::python {
namespace {

constexpr int64_t kLastSeed = int64_t{kMaxEnvSeed} - 1;

}  // namespace

std::string int_text(const pybind11::int_& value) {
  // Python refuses to print an int of more than 4300 digits; a message needs no more than its size
  const auto bits = value.attr("bit_length")().cast<int64_t>();
  if (bits > 256)
    return std::string(value < pybind11::int_(0) ? "minus " : "") + "an integer of " + std::to_string(bits) + " bits";
  return std::string(pybind11::str(static_cast<const pybind11::handle&>(value)));
}

int64_t int_in_range(const pybind11::int_& value, int64_t lo, int64_t hi, const std::string& name,
                     const std::string& why) {
  if (value < pybind11::int_(lo) || value > pybind11::int_(hi))
    throw std::invalid_argument(name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" +
                                (why.empty() ? "" : " (" + why + ")") + ", got " + int_text(value));
  return value.cast<int64_t>();
}

uint32_t terrain_seed(const pybind11::int_& seed) {
  return static_cast<uint32_t>(int_in_range(seed, 0, kLastSeed, "seed"));
}

uint32_t first_terrain_seed(const pybind11::int_& seed, size_t walkers) {
  const int64_t last = kLastSeed - static_cast<int64_t>(walkers - 1);
  return static_cast<uint32_t>(int_in_range(
      seed, 0, last, "seed", "walker i gets seed + i, each below " + std::to_string(kMaxEnvSeed)));
}

int episode_steps(const pybind11::int_& max_steps) {
  return static_cast<int>(int_in_range(max_steps, 1, INT_MAX, "max_steps"));
}

int time_limit(const pybind11::int_& max_steps) {
  return static_cast<int>(int_in_range(max_steps, 1, walker::kMaxTimeLimit, "max_steps"));
}

int thread_count(const pybind11::int_& threads) {
  return static_cast<int>(int_in_range(threads, 1, kMaxThreads, "threads"));
}

int vector_size(const pybind11::int_& num_envs) {
  return static_cast<int>(int_in_range(num_envs, 1, kMaxVectorEnvs, "num_envs"));
}

int frame_pixels(const pybind11::int_& value, const char* name) {
  return static_cast<int>(int_in_range(value, kMinFramePixels, kMaxFramePixels, name));
}

}  // namespace poet::python
