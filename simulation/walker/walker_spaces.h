#pragma once
// What each index of the walker's observation and action is, in the order WalkerEnv::observe() writes them and
// apply_action() reads them: the one home of the names the Python module exposes (OBSERVATION_NAMES, ACTION_NAMES)
// and of the environment's card (docs/reference/environment.md). A change to observe() changes this table.

#include <array>
#include <limits>
#include <string_view>

namespace poet::walker {

struct SpaceIndex {
  std::string_view name;     // an identifier, for code and columns: hull_angle, hip1_speed, lidar3
  std::string_view meaning;  // the quantity, its units and its scaling
  double low, high;          // the bounds it keeps to; ±infinity when none holds (a joint's limits are soft)
};

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// Leg 1 is the one whose segments start at angle −kLegStartAngle, leg 2 the other.
inline constexpr std::array<SpaceIndex, 24> kObservationIndices = {{
    {"hull_angle", "the hull's angle, radians (0: level)", -kUnbounded, kUnbounded},
    {"hull_angular_velocity", "the hull's angular velocity, rad/s × 2 / fps", -kUnbounded, kUnbounded},
    {"hull_velocity_x", "the hull's horizontal velocity, m/s × 0.3 × (600 / scale) / fps", -kUnbounded, kUnbounded},
    {"hull_velocity_y", "the hull's vertical velocity, m/s × 0.3 × (400 / scale) / fps", -kUnbounded, kUnbounded},
    {"hip1_angle", "leg 1's hip angle, radians (the hip's limits, soft)", -kUnbounded, kUnbounded},
    {"hip1_speed", "leg 1's hip speed, rad/s / the hip motor's speed", -kUnbounded, kUnbounded},
    {"knee1_angle", "leg 1's knee angle + 1, radians (the knee's limits + 1, soft)", -kUnbounded, kUnbounded},
    {"knee1_speed", "leg 1's knee speed, rad/s / the knee motor's speed", -kUnbounded, kUnbounded},
    {"leg1_contact", "1 while leg 1's lower leg touches the ground, else 0", 0, 1},
    {"hip2_angle", "leg 2's hip angle, radians (the hip's limits, soft)", -kUnbounded, kUnbounded},
    {"hip2_speed", "leg 2's hip speed, rad/s / the hip motor's speed", -kUnbounded, kUnbounded},
    {"knee2_angle", "leg 2's knee angle + 1, radians (the knee's limits + 1, soft)", -kUnbounded, kUnbounded},
    {"knee2_speed", "leg 2's knee speed, rad/s / the knee motor's speed", -kUnbounded, kUnbounded},
    {"leg2_contact", "1 while leg 2's lower leg touches the ground, else 0", 0, 1},
    {"lidar0", "lidar ray 0 (straight down): distance to the ground / lidar range, 1 if none", 0, 1},
    {"lidar1", "lidar ray 1 (0.15 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar2", "lidar ray 2 (0.30 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar3", "lidar ray 3 (0.45 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar4", "lidar ray 4 (0.60 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar5", "lidar ray 5 (0.75 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar6", "lidar ray 6 (0.90 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar7", "lidar ray 7 (1.05 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar8", "lidar ray 8 (1.20 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
    {"lidar9", "lidar ray 9 (1.35 rad ahead of down): distance / lidar range, 1 if none", 0, 1},
}};

// Each action is clipped to [-1, 1]: its sign turns the joint's motor forward or back at the joint's speed, its
// magnitude is the share of kMotorsTorque the motor may use.
inline constexpr std::array<SpaceIndex, 4> kActionIndices = {{
    {"hip1_torque", "leg 1's hip motor: direction and share of the motors' torque", -1, 1},
    {"knee1_torque", "leg 1's knee motor: direction and share of the motors' torque", -1, 1},
    {"hip2_torque", "leg 2's hip motor: direction and share of the motors' torque", -1, 1},
    {"knee2_torque", "leg 2's knee motor: direction and share of the motors' torque", -1, 1},
}};

}  // namespace poet::walker
