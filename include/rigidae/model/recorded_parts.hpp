#pragma once
// Which bodies and joints a mechanism's records carry columns for: the
// scene's [output] bodies / joints when given, else every part of a small
// mechanism and none of a large one. A 10,000-link chain would otherwise
// write 60,000+ numbers per step; above kAllPartsUpToJoints joints the step
// file and trajectory.csv hold only the global columns (t, h, order, drift,
// energy, momentum) unless the scene names the parts (summary.json says so).
#include <vector>

#include "rigidae/model/multibody_spec.hpp"

namespace rigidae {

inline constexpr std::size_t kAllPartsUpToJoints = 50;

struct RecordedParts {
  std::vector<int> bodies, joints;  // indices, in the scene's order
  bool bodies_by_default = true, joints_by_default = true;  // the scene named none
  bool cut_by_size = false;  // the default left parts out (more than kAllPartsUpToJoints joints)
};

// `cut_large`: whether the default leaves a large mechanism's parts out (the
// step file); trajectory.csv, on the output grid, keeps every part unless the
// scene names them.
inline RecordedParts recorded_parts(const MultibodySpec& spec, bool cut_large = true) {
  RecordedParts r;
  const bool large = cut_large && spec.joints.size() > kAllPartsUpToJoints;
  const auto pick = [&](const std::optional<std::vector<int>>& chosen, std::size_t n, std::vector<int>& out,
                        bool& by_default) {
    by_default = !chosen.has_value();
    if (chosen) {
      out = *chosen;
      return;
    }
    if (large) {
      r.cut_by_size = r.cut_by_size || n > 0;
      return;
    }
    for (std::size_t i = 0; i < n; ++i) out.push_back(static_cast<int>(i));
  };
  pick(spec.output_bodies, spec.bodies.size(), r.bodies, r.bodies_by_default);
  pick(spec.output_joints, spec.joints.size(), r.joints, r.joints_by_default);
  return r;
}

}  // namespace rigidae
