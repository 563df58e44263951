// Velocity Verlet, kick-drift-kick with one force evaluation per substep: the acceleration
// of the end of a substep is kept for the start of the next (explicit_integrator.hpp).
#include "corotate/integrators/explicit_integrator.hpp"

namespace corotate {

namespace {
class VelocityVerlet final : public ExplicitIntegrator {
 public:
  using ExplicitIntegrator::ExplicitIntegrator;
  void attach(ForceModel& model) override {
    ExplicitIntegrator::attach(model);
    a_.setZero(3, model.num_nodes());
  }
  // The kept acceleration is stale when positions, velocities, loads or the fixed set may
  // have changed since the last substep: at the start of every Simulation::step call.
  void begin(const StepInput& in) override { acceleration(in, in.x, in.v, a_); }

 protected:
  void substep(const StepInput& in, Nodes& x, Nodes& v, double h) override {
    v += (0.5 * h) * a_;
    x += h * v;
    acceleration(in, x, v, a_);
    v += (0.5 * h) * a_;
  }

 private:
  Nodes a_;
};
}  // namespace

std::unique_ptr<Integrator> make_velocity_verlet(const IntegratorSettings& settings) {
  return std::make_unique<VelocityVerlet>(settings);
}

}  // namespace corotate
