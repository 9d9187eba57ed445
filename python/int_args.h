#pragma once
// Integers from Python as the module takes them: a Python int of any size, checked against its range here, so that
// a value past what C++ holds (2**63, 2**200) is the module's ValueError naming the argument and its range, not
// pybind11's TypeError listing signatures. Every integer argument of the module is checked by one function here.

#include <pybind11/pybind11.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace poet::python {

// The most walkers one vector env steps. Each holds its own Box2D world and course (about 220 KB), so 4096 of them
// take some 900 MB: a bound well past what one machine's cores step usefully (a few walkers per core), which keeps a
// mistyped num_envs (10**9) a ValueError rather than an out-of-memory kill.
inline constexpr int64_t kMaxVectorEnvs = 4096;
// Threads for episodes, as the tools' --threads.
inline constexpr int64_t kMaxThreads = 4096;

// value in [lo, hi], else std::invalid_argument (ValueError): "NAME must be in [LO, HI], got VALUE", or with a
// reason for the range "NAME must be in [LO, HI] (WHY), got VALUE".
int64_t int_in_range(const pybind11::int_& value, int64_t lo, int64_t hi, const std::string& name,
                     const std::string& why = "");

// A Python int as a message shows it: its digits, or its size in bits when it has too many to print.
std::string int_text(const pybind11::int_& value);

// A terrain seed: in [0, kMaxEnvSeed).
uint32_t terrain_seed(const pybind11::int_& seed);
// The first of `walkers` consecutive terrain seeds (walker i gets seed + i): each of them below kMaxEnvSeed.
uint32_t first_terrain_seed(const pybind11::int_& seed, size_t walkers);
// The time limit of an episode stepped from Python: at least one step, at most what an int holds.
int episode_steps(const pybind11::int_& max_steps);
// The time limit of episodes run to their end inside one call (evaluate): bounded as the tools' (kMaxTimeLimit).
int time_limit(const pybind11::int_& max_steps);
// Threads for episodes: in [1, kMaxThreads].
int thread_count(const pybind11::int_& threads);
// Walkers of a vector env: in [1, kMaxVectorEnvs].
int vector_size(const pybind11::int_& num_envs);
// A frame's width or height (named by `name`) as render() takes it: in [kMinFramePixels, kMaxFramePixels].
int frame_pixels(const pybind11::int_& value, const char* name);

}  // namespace poet::python
