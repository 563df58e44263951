// pybind11 glue for corotate._core.Simulation (implicit and explicit stepping of one body)
// and its settings. Nothing but conversions; the defaults are read from the C++ structs.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <functional>
#include <optional>

#include "conversions.hpp"
#include "corotate/models/explicit_traits.hpp"
#include "corotate/simulation.hpp"
#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"

namespace py = pybind11;
using namespace corotate;
using namespace corotate::bindings;

std::unique_ptr<LinearSolver> make_solver(const std::string& kind, const PCGSettings& pcg) {
  if (kind == "pcg") return std::make_unique<PCG>(pcg);
  if (kind == "direct") return std::make_unique<DirectSolver>();
  throw InvalidInput("unknown solver '" + kind + "' (choose 'pcg' or 'direct')");
}

namespace {

py::dict eigen_dict(const EigenEstimate& e) {
  py::dict d;
  d["value"] = e.value;
  d["ritz"] = e.ritz;
  d["residual"] = e.residual;
  d["iterations"] = e.iterations;
  return d;
}

py::dict stability_dict(const StabilityEstimate& s) {
  py::dict d;
  d["critical_step"] = s.critical_step;
  d["omega_max"] = s.omega_max;
  d["attachment_rate"] = s.attachment_rate;
  d["lambda_max"] = s.stiffness.value;
  d["damping_rate"] = s.damping_rate;
  d["bound"] = s.bound;
  d["stiffness"] = eigen_dict(s.stiffness);
  d["damping"] = eigen_dict(s.damping);
  return d;
}

py::dict stats_dict(const SimulationStats& st) {
  py::dict d;
  d["steps"] = st.steps;
  d["substeps"] = st.substeps;
  d["last_substeps"] = st.last.substeps;
  d["last_substep"] = st.last.substep;
  d["iterations"] = st.last.solve.iterations;
  d["newton_iterations"] = st.last.newton_iterations;
  d["contact_passes"] = st.last.contact_passes;
  d["kept_matrix"] = st.last.kept_matrix;
  d["kept_matrix_steps"] = st.kept_matrix_steps;
  d["newton_residuals"] = st.last.newton_residuals;
  d["residual"] = st.last.solve.relative_residual;
  d["converged"] = st.last.solve.converged;
  d["tolerance"] = st.last.solve.tolerance;
  d["iterations_per_step"] = st.iterations_per_step();
  d["ms_per_step"] = st.ms_per_step();
  d["assembly_ms"] = st.last.assembly_ms;
  d["solve_ms"] = st.last.solve_ms;
  d["simulated_time"] = st.simulated_time;
  d["wall_time"] = st.wall_ms * 1e-3;
  d["estimate_time"] = st.estimate_ms * 1e-3;
  d["estimates"] = st.estimates;
  d["real_time_ratio"] = st.real_time_ratio();
  d["solver_stalled"] = st.last.solver_stalled;
  d["inverted_elements"] = st.last.start_inverted;
  d["energy_growth"] = st.last.energy_growth;
  d["stalled_steps"] = st.stalled_steps;
  d["inverted_steps"] = st.inverted_steps;
  d["energy_growth_steps"] = st.energy_growth_steps;
  return d;
}

// The hook a long call (step(n), solve_static) runs between its steps, with the GIL released
// around it: the progress callback (if any) after each step, with the GIL, and at most every
// 20 ms the signal handlers (Ctrl-C). Whatever they raise fails the call, and the state is
// restored to what it was before it, as for every failure.
class ProgressAndSignals {
 public:
  ProgressAndSignals(const std::optional<py::function>& progress, int total) : progress_(progress), total_(total) {}

  void operator()(int done) {
    const bool signals_due = Clock::now() - last_check_ >= std::chrono::milliseconds(20);
    if (!signals_due && !progress_) return;
    py::gil_scoped_acquire gil;
    if (progress_) (*progress_)(done, total_);
    if (signals_due) {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      last_check_ = Clock::now();
    }
  }

 private:
  using Clock = std::chrono::steady_clock;
  const std::optional<py::function>& progress_;
  int total_;
  Clock::time_point last_check_ = Clock::now();
};

}  // namespace

void bind_simulation(py::module_& m) {
  // The enums (members in upper case: RAISE is not a keyword); the Python API takes their names.
  py::enum_<IntegratorKind>(m, "IntegratorKind")
      .value("LINEARIZED", IntegratorKind::Linearized)
      .value("NEWTON", IntegratorKind::Newton)
      .value("SYMPLECTIC_EULER", IntegratorKind::SymplecticEuler)
      .value("VERLET", IntegratorKind::Verlet);
  py::enum_<TimeStepPolicy>(m, "TimeStepPolicy")
      .value("FIXED", TimeStepPolicy::Fixed)
      .value("ONLINE", TimeStepPolicy::Online);
  py::enum_<OnUnstable>(m, "OnUnstable")
      .value("SUBSTEP", OnUnstable::Substep)
      .value("RAISE", OnUnstable::Raise)
      .value("ALLOW", OnUnstable::Allow);
  const IntegratorSettings defaults;
  py::class_<IntegratorSettings>(m, "IntegratorSettings")
      .def(py::init([](const std::string& integrator, double time_step, double mass_damping, double stiffness_damping,
                       bool lumped_mass, int newton_iterations, double newton_tolerance, const std::string& policy,
                       const std::string& on_unstable, double safety, double matrix_reuse_angle) {
             IntegratorSettings s{integrator_from_name(integrator),
                                  time_step,
                                  mass_damping,
                                  stiffness_damping,
                                  lumped_mass,
                                  newton_iterations,
                                  newton_tolerance,
                                  time_step_policy_from_name(policy),
                                  on_unstable_from_name(on_unstable),
                                  safety,
                                  matrix_reuse_angle};
             s.validate();
             return s;
           }),
           py::arg("integrator") = std::string(integrator_name(defaults.kind)),
           py::arg("time_step") = defaults.time_step, py::arg("mass_damping") = defaults.mass_damping,
           py::arg("stiffness_damping") = defaults.stiffness_damping, py::arg("lumped_mass") = defaults.lumped_mass,
           py::arg("newton_iterations") = defaults.newton_iterations,
           py::arg("newton_tolerance") = defaults.newton_tolerance,
           py::arg("policy") = std::string(time_step_policy_name(defaults.policy)),
           py::arg("on_unstable") = std::string(on_unstable_name(defaults.on_unstable)),
           py::arg("safety") = defaults.safety, py::arg("matrix_reuse_angle") = defaults.matrix_reuse_angle,
           "Settings of every integrator (each reads what applies to it); see integrators/integrator.hpp.")
      .def_property_readonly("integrator", [](const IntegratorSettings& s) { return integrator_name(s.kind); })
      .def_property_readonly("is_explicit", [](const IntegratorSettings& s) { return is_explicit(s.kind); })
      .def_readonly("time_step", &IntegratorSettings::time_step)
      .def_readonly("mass_damping", &IntegratorSettings::mass_damping)
      .def_readonly("stiffness_damping", &IntegratorSettings::stiffness_damping)
      .def_readonly("lumped_mass", &IntegratorSettings::lumped_mass)
      .def_readonly("newton_iterations", &IntegratorSettings::newton_iterations)
      .def_readonly("newton_tolerance", &IntegratorSettings::newton_tolerance)
      .def_property_readonly("policy", [](const IntegratorSettings& s) { return time_step_policy_name(s.policy); })
      .def_property_readonly("on_unstable", [](const IntegratorSettings& s) { return on_unstable_name(s.on_unstable); })
      .def_readonly("safety", &IntegratorSettings::safety)
      .def_readonly("matrix_reuse_angle", &IntegratorSettings::matrix_reuse_angle);

  py::class_<Simulation>(m, "Simulation")
      .def(py::init([](const ForceModel& model, const IntegratorSettings& settings, const std::string& solver,
                       const PCGSettings& pcg) {
             return std::make_unique<Simulation>(model.clone(), settings, make_solver(solver, pcg));
           }),
           py::arg("model"), py::arg("settings"), py::arg("solver") = "pcg", py::arg("pcg") = PCGSettings{},
           "Simulation of its own copy of `model`, stepped by the integrator of `settings`.")
      .def_property_readonly("positions",
                             [](py::object self) { return node_view(self.cast<Simulation&>().positions(), self); })
      .def_property_readonly("velocities",
                             [](py::object self) { return node_view(self.cast<Simulation&>().velocities(), self); })
      .def_property_readonly(
          "external_forces",
          [](py::object self) { return node_view(self.cast<Simulation&>().external_forces(), self); })
      .def_property_readonly("accelerations",
                             [](const Simulation& s) {
                               const Simulation::Claim claim(s, "reading the accelerations");
                               return Eigen::MatrixXd(s.accelerations().transpose());
                             })
      .def_property_readonly("gravity_forces",
                             [](const Simulation& s) { return Eigen::MatrixXd(s.gravity_forces().transpose()); })
      .def_property_readonly("time", &Simulation::time)
      .def_property_readonly("num_nodes", &Simulation::num_nodes)
      .def_property("gravity", &Simulation::gravity, &Simulation::set_gravity)
      .def_property("fixed_nodes", &Simulation::fixed_nodes, &Simulation::set_fixed_nodes)
      .def(
          "attach",
          [](Simulation& s, const std::vector<Index>& nodes, const PointsIn& targets,
             const Eigen::VectorXd& stiffness) { s.attach(nodes, nodes_from(targets, "targets"), stiffness); },
          py::arg("nodes"), py::arg("targets"), py::arg("stiffness"),
          "Attach nodes to targets ((m, 3)) by zero-rest-length springs (stiffness: m values [N/m]).")
      .def(
          "move_attachments",
          [](Simulation& s, const std::vector<Index>& nodes, const PointsIn& targets) {
            s.move_attachments(nodes, nodes_from(targets, "targets"));
          },
          py::arg("nodes"), py::arg("targets"), "New targets ((m, 3)) for attached nodes.")
      .def("detach", &Simulation::detach, py::arg("nodes"), "Release attached nodes.")
      .def("detach_all", &Simulation::detach_all, "Release every attached node.")
      .def_property_readonly(
          "attachments",
          [](const Simulation& s) {
            const Simulation::Claim claim(s, "reading the attachments");
            const Attachments& a = s.attachments();
            return py::make_tuple(a.nodes(), Eigen::MatrixXd(a.targets().transpose()), a.stiffness());
          },
          "(nodes, targets (m, 3), stiffness (m,)) of the attachment springs (copies).")
      .def_property("settings", &Simulation::settings, &Simulation::set_settings)
      .def_property(
          "failure_policy",
          [](const Simulation& s) { return failure_policy_names()[static_cast<int>(s.failure_policy())]; },
          [](Simulation& s, const std::string& name) { s.set_failure_policy(failure_policy_from_name(name)); },
          "'warn' (default), 'raise' or 'ignore': what a stalled solve, inverted elements or a run-away do")
      .def(
          "set_solver",
          [](Simulation& s, const std::string& solver, const PCGSettings& pcg) {
            s.set_solver(make_solver(solver, pcg));
          },
          py::arg("solver"), py::arg("pcg") = PCGSettings{})
      .def(
          "step",
          [](Simulation& s, int n, const std::optional<py::function>& progress) {
            ProgressAndSignals after_each_step(progress, n);
            py::gil_scoped_release release;
            // A single step without progress has no "between steps" to interrupt (Python
            // raises a Ctrl-C as the call returns): no callback, so the step needs no copy
            // of the state to restore after it committed (Simulation::step).
            if (n == 1 && !progress) s.step(1);
            else s.step(n, std::ref(after_each_step));
          },
          py::arg("n") = 1, py::arg("progress") = py::none(),
          "Take n steps; progress(done, n) is called after each; interruptible between steps (Ctrl-C "
          "restores the state of before the call).")
      .def("reset", &Simulation::reset,
           "Back to the rest state (positions = rest, velocities, external forces and time zero, stats and "
           "warm starts cleared); fixed nodes, gravity and settings are kept.")
      .def(
          "solve_static",
          [](Simulation& s, int load_steps, double tolerance, int max_iterations,
             const std::optional<PointsIn>& prescribed, const std::optional<py::function>& progress) {
            std::optional<Nodes> target;
            if (prescribed) {
              target = nodes_from(*prescribed, "prescribed positions");
              if (target->cols() != s.num_nodes())
                throw InvalidInput("prescribed positions must have one row per node");
            }
            ProgressAndSignals after_each_load_step(progress, load_steps);
            StaticResult r;
            {
              py::gil_scoped_release release;
              r = s.solve_static({load_steps, tolerance, max_iterations}, target ? &*target : nullptr,
                                 std::ref(after_each_load_step));
            }
            py::dict d;
            d["residual_history"] = r.residual_history;
            d["iterations"] = r.total_iterations;
            return d;
          },
          py::arg("load_steps") = StaticSettings{}.load_steps, py::arg("tolerance") = StaticSettings{}.tolerance,
          py::arg("max_iterations") = StaticSettings{}.max_iterations, py::arg("prescribed") = py::none(),
          py::arg("progress") = py::none(),
          "Static equilibrium by Newton with load steps; progress(done, load_steps) after each load step; "
          "interruptible between load steps (Ctrl-C restores the state).")
      .def("internal_forces",
           [](Simulation& s) {
             const Simulation::Claim claim(s, "internal_forces");
             Nodes f = Nodes::Zero(3, s.num_nodes());
             s.model().add_forces(s.positions(), f);
             return Eigen::MatrixXd(f.transpose());
           })
      .def("damping_forces",
           [](Simulation& s) {
             // The model's own damping forces: all explicit forces at (x, v) minus the elastic ones.
             const Simulation::Claim claim(s, "damping_forces");
             Nodes f = Nodes::Zero(3, s.num_nodes());
             if (const ExplicitTraits* traits = s.model().explicit_traits()) {
               traits->add_forces_and_damping(s.positions(), s.velocities(), f);
               Nodes elastic = Nodes::Zero(3, s.num_nodes());
               s.model().add_forces(s.positions(), elastic);
               f -= elastic;
             }
             return Eigen::MatrixXd(f.transpose());
           })
      .def("energy",
           [](Simulation& s) {
             const Simulation::Claim claim(s, "energy");
             return s.model().energy(s.positions());
           })
      .def("kinetic_energy", &Simulation::kinetic_energy)
      .def(
          "mass_csr", [](const Simulation& s) { return to_csr(s.mass()); },
          "The integrator's mass matrix as a CSR triple.")
      .def("stability", [](Simulation& s) { return stability_dict(s.stability()); })
      .def(
          "estimate_stability", [](Simulation& s, bool bound) { return stability_dict(s.estimate_stability(bound)); },
          py::arg("bound"))
      .def_property_readonly("stats",
                             [](const Simulation& s) {
                               const Simulation::Claim claim(s, "reading the stats");
                               return stats_dict(s.stats());
                             })
      .def("reset_stats", &Simulation::reset_stats);
}
