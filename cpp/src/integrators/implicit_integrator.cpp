#include "corotate/integrators/implicit_integrator.hpp"

#include <atomic>

namespace corotate {

void ImplicitIntegrator::attach(ForceModel& model) {
  mass_ = model.mass_matrix(settings().lumped_mass);
  static std::atomic<std::uint64_t> versions{0};
  mass_version_ = ++versions;
  kept_.forget();
  kept_turn_ = AggregateRotations();
  body_parts_.clear();
  num_body_parts_ = 0;
  system_ = model.pattern();
  const Index n = model.num_nodes();
  force_.setZero(3, n);
  y_.setZero(3, n);
  rhs_.setZero(3 * n);
  dv_.setZero(3 * n);
  work_.setZero(3 * n);
  saved_dv_.setZero(3 * n);
}

}  // namespace corotate
