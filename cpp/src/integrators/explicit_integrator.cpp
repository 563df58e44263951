#include "corotate/integrators/explicit_integrator.hpp"

namespace corotate {

ExplicitScheme explicit_scheme_from_name(const std::string& name) {
  if (name == "symplectic_euler") return ExplicitScheme::SymplecticEuler;
  if (name == "verlet" || name == "velocity_verlet") return ExplicitScheme::VelocityVerlet;
  throw InvalidInput("unknown integrator '" + name + "' (choose 'verlet' or 'symplectic_euler')");
}

const char* explicit_scheme_name(ExplicitScheme scheme) {
  return scheme == ExplicitScheme::SymplecticEuler ? "symplectic_euler" : "verlet";
}

ExplicitIntegrator::ExplicitIntegrator(ForceModel& model) : model_(model), a_(Nodes::Zero(3, model.num_nodes())) {}

void ExplicitIntegrator::begin(ExplicitScheme scheme, const Nodes& x, const Nodes& v, const Nodes& load,
                               const Vec& inv_mass, const Vec& damping_rate) {
  scheme_ = scheme;
  load_ = &load;
  inv_mass_ = &inv_mass;
  damping_rate_ = &damping_rate;
  if (scheme_ == ExplicitScheme::VelocityVerlet) acceleration(x, v);
}

void ExplicitIntegrator::acceleration(const Nodes& x, const Nodes& v) {
  a_ = *load_;
  model_.add_explicit_forces(x, v, a_);
  const Index n = a_.cols();
  const double* im = inv_mass_->data();
  const double* dr = damping_rate_->data();
  for (Index i = 0; i < n; ++i) a_.col(i) = im[i] * a_.col(i) - dr[i] * v.col(i);
}

void ExplicitIntegrator::substep(Nodes& x, Nodes& v, double h) {
  if (scheme_ == ExplicitScheme::SymplecticEuler) {
    acceleration(x, v);
    v += h * a_;
    x += h * v;
  } else {
    v += (0.5 * h) * a_;
    x += h * v;
    acceleration(x, v);
    v += (0.5 * h) * a_;
  }
}

}  // namespace corotate
