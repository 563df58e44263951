// corotate_bench --scenario rotations: the polar rotations of the element sweep
// (models/rotation_extraction.hpp) timed alone, one call per element against the batched
// extract_rotations, on one thread.
//
// N deformation gradients F = R S (R random, S symmetric with entries perturbed by 5 %), each
// warm-started from its rotation turned by `turn` radians about a random axis (the rotation
// an element makes in one step); every repetition starts from those warm starts again.
// Prints the median ns per element of each form (interleaved repetitions) and the largest
// difference of either result from the SVD's rotation.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "corotate/models/rotation_extraction.hpp"

namespace corotate::bench {

inline int rotations_main(int argc, char** argv) {
  int elements = 15360, repeats = 21;
  double turn = 0.01;
  for (int a = 0; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--elements" && a + 1 < argc) elements = std::stoi(argv[++a]);
    else if (arg == "--turn" && a + 1 < argc) turn = std::stod(argv[++a]);
    else if (arg == "--repeats" && a + 1 < argc) repeats = std::stoi(argv[++a]);
    else if (arg == "--help" || arg == "-h") {
      std::puts(
          "usage: corotate_bench --scenario rotations [--elements N (15360)] [--turn RAD (0.01: the warm\n"
          "       start's distance from the answer)] [--repeats N (21)]");
      return 0;
    } else throw InvalidInput("unknown option " + arg + " for --scenario rotations");
  }
  if (elements < 1 || repeats < 1 || !(turn >= 0)) throw InvalidInput("--elements, --repeats >= 1 and --turn >= 0");
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  std::vector<Mat3> F(elements), exact(elements), R(elements);
  std::vector<Eigen::Quaterniond> start(elements), q(elements);
  for (int e = 0; e < elements; ++e) {
    const Eigen::Quaterniond rotation(Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized());
    Mat3 S = Mat3::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) S(i, j) = S(j, i) = S(i, j) + 0.05 * normal(rng);
    F[e] = rotation.toRotationMatrix() * S;
    exact[e] = polar_rotation_svd(F[e]);
    const Vec3 axis = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    start[e] = Eigen::Quaterniond(Eigen::AngleAxisd(turn, axis)) * Eigen::Quaterniond(exact[e]);
  }
  using clock_type = std::chrono::steady_clock;
  std::vector<double> single_ns, batched_ns;
  double single_error = 0, batched_error = 0;
  auto error = [&]() {
    double worst = 0;
    for (int e = 0; e < elements; ++e) worst = std::max(worst, (R[e] - exact[e]).cwiseAbs().maxCoeff());
    return worst;
  };
  for (int r = 0; r < repeats; ++r) {
    q = start;
    auto t0 = clock_type::now();
    for (int e = 0; e < elements; ++e) R[e] = extract_rotation(F[e], q[e]);
    single_ns.push_back(std::chrono::duration<double, std::nano>(clock_type::now() - t0).count() / elements);
    single_error = error();
    q = start;
    t0 = clock_type::now();
    for (int e = 0; e < elements; e += 16) extract_rotations(&F[e], &q[e], &R[e], std::min(16, elements - e));
    batched_ns.push_back(std::chrono::duration<double, std::nano>(clock_type::now() - t0).count() / elements);
    batched_error = error();
  }
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  std::printf("rotations: %d elements, warm starts %g rad off, median of %d interleaved repetitions, one thread\n",
              elements, turn, repeats);
  std::printf("  one call per element (extract_rotation)   %7.1f ns/element, max |R - R_svd| %.1e\n", median(single_ns),
              single_error);
  std::printf("  sixteen per call (extract_rotations)      %7.1f ns/element, max |R - R_svd| %.1e\n",
              median(batched_ns), batched_error);
  return 0;
}

}  // namespace corotate::bench
