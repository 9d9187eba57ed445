#pragma once
// Constants of the POET bipedal walker domain (spec §1). Sizes are given in pixels as in the reference and
// divided by kScale into Box2D metres.

#include "schema_defaults.h"

namespace poet::walker {

inline constexpr double kScale = 30.0;  // pixels per metre; also part of the reward and terrain formulas
inline constexpr double kFps = 50.0;
inline constexpr int kVelocityIterations = 180;
inline constexpr int kPositionIterations = 60;
inline constexpr double kGravity = -10.0;

inline constexpr double kMotorsTorque = 80.0;
inline constexpr double kSpeedHip = 4.0;
inline constexpr double kSpeedKnee = 6.0;
inline constexpr double kLidarRange = 160.0 / kScale;
inline constexpr int kLidarRays = 10;
// initial horizontal push F ~ U[-5, 5) N: the schema's default (proto/poet.proto is the home of every default)
inline constexpr double kDefaultPushScale = schema_defaults::walker_config::push_scale;

inline constexpr double kHullPoly[5][2] = {{-30, +9}, {+6, +9}, {+34, +1}, {+34, -8}, {-30, -8}};  // pixels
inline constexpr double kHullDensity = 5.0;
inline constexpr double kHullFriction = 0.1;
inline constexpr double kLegDown = -8.0 / kScale;
inline constexpr double kLegW = 8.0 / kScale;
inline constexpr double kLegH = 34.0 / kScale;
inline constexpr double kLowerLegWidthFactor = 0.8;
inline constexpr double kLegDensity = 1.0;
inline constexpr double kLegFriction = 0.2;  // Box2D's default; the reference sets none
inline constexpr double kHipLower = -0.8, kHipUpper = 1.1;
inline constexpr double kKneeLower = -1.6, kKneeUpper = -0.1;
inline constexpr double kLegStartAngle = 0.05;  // leg i ∈ {-1, +1} starts at angle 0.05·i

inline constexpr unsigned kGroundCategory = 0x0001;
inline constexpr unsigned kWalkerCategory = 0x0020;

inline constexpr double kTerrainStep = 14.0 / kScale;
inline constexpr int kTerrainLength = 200;  // points
inline constexpr double kTerrainHeight = 400.0 / kScale / 4.0;
inline constexpr int kTerrainGrass = 10;
inline constexpr int kTerrainStartpad = 20;
inline constexpr double kTerrainFriction = 2.5;
inline constexpr double kPitDepthSteps = 4.0;

// Debian's Box2D 2.4.1 keeps its assertions and welds polygon vertices closer than 2.5 mm, so a stump or stair
// box whose sampled height is near 0 would abort the process. Boxes are built at least this thick (in terrain
// steps, ≈ 4.7 mm); the course's ground line and recorded sizes keep the sampled value.
inline constexpr double kMinObstacleHeightSteps = 0.01;

inline constexpr double kInitX = kTerrainStep * kTerrainStartpad / 2;
inline constexpr double kInitY = kTerrainHeight + 2 * kLegH;
inline constexpr double kFinishX = (kTerrainLength - kTerrainGrass) * kTerrainStep;

inline constexpr double kTorqueCost = 0.00035;  // reward cost per unit of |action| · kMotorsTorque
inline constexpr double kFallReward = -100.0;
// steps after the reset step; belongs to the rollout; the schema's default
inline constexpr int kDefaultTimeLimit = schema_defaults::walker_config::max_steps;
// The longest episode the tools and the Python module run for a user (500 times the reference's): beyond it a
// standing walker would hold an evaluation for hours.
inline constexpr int kMaxTimeLimit = 1'000'000;

}  // namespace poet::walker
