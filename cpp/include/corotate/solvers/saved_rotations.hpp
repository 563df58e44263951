// A copy of a turning preconditioner's rotations and their warm starts (node_rotations.hpp,
// aggregate_rotations.hpp), to go back to when a Simulation::step call fails.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "corotate/common.hpp"

namespace corotate {

struct SavedRotations {
  std::vector<Mat3> rotations;
  std::vector<Eigen::Quaterniond> guess;
  bool rotated = false;

  void save(const std::vector<Mat3>& from, const std::vector<Eigen::Quaterniond>& from_guess, bool from_rotated) {
    rotations = from;  // (no allocation once sized)
    guess = from_guess;
    rotated = from_rotated;
  }
  // Nothing when the rotations were built afresh since (another size): nothing saved for them.
  void restore(std::vector<Mat3>& to, std::vector<Eigen::Quaterniond>& to_guess, bool& to_rotated) const {
    if (rotations.size() != to.size()) return;
    to = rotations;
    to_guess = guess;
    to_rotated = rotated;
  }
};

}  // namespace corotate
