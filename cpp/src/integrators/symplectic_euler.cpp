// Symplectic (semi-implicit) Euler: v <- v + h a(x, v), x <- x + h v (explicit_integrator.hpp).
#include "corotate/integrators/explicit_integrator.hpp"

namespace corotate {

namespace {
class SymplecticEuler final : public ExplicitIntegrator {
 public:
  using ExplicitIntegrator::ExplicitIntegrator;
  void attach(ForceModel& model) override {
    ExplicitIntegrator::attach(model);
    a_.setZero(3, model.num_nodes());
  }

 protected:
  void substep(const StepInput& in, Nodes& x, Nodes& v, double h) override {
    acceleration(in, x, v, a_);
    v += h * a_;
    x += h * v;
  }

 private:
  Nodes a_;
};
}  // namespace

std::unique_ptr<Integrator> make_symplectic_euler(const IntegratorSettings& settings) {
  return std::make_unique<SymplecticEuler>(settings);
}

}  // namespace corotate
