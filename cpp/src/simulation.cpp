#include "corotate/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "corotate/solvers/direct_solver.hpp"
#include "corotate/solvers/pcg.hpp"

namespace corotate {

const std::vector<std::string>& failure_policy_names() {
  static const std::vector<std::string> names = {"ignore", "warn", "raise"};
  return names;
}

FailurePolicy failure_policy_from_name(const std::string& name) {
  const auto& names = failure_policy_names();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<FailurePolicy>(i);
  throw InvalidInput("unknown failure policy '" + name + "' (choose 'ignore', 'warn' or 'raise')");
}

Simulation::Simulation(std::unique_ptr<ForceModel> model, const IntegratorSettings& settings,
                       std::unique_ptr<LinearSolver> solver)
    : model_(std::move(model)), solver_(std::move(solver)) {
  if (!model_) throw InvalidInput("Simulation needs a force model");
  if (!solver_) solver_ = std::make_unique<PCG>();
  integrator_ = make_integrator(settings);
  integrator_->attach(*model_);
  solver_->set_geometry(model_->rest_positions());
  x_ = model_->rest_positions();
  const Index n = model_->num_nodes();
  v_.setZero(3, n);
  a_.setZero(3, n);
  f_ext_.setZero(3, n);
  load_.setZero(3, n);
  x_next_.setZero(3, n);
  v_next_.setZero(3, n);
  fixed_ = FixedDofs(model_->pattern(), std::vector<char>(3 * n, 0));
  attachments_ = Attachments(n);
  std::vector<Index> all(n);
  for (Index i = 0; i < n; ++i) all[i] = i;
  contacts_.set_nodes(std::move(all));
  lumped_masses_ = model_->lumped_masses();
  rebuild_gravity_forces();
}

Simulation::Claim::Claim(const Simulation& sim, const char* what) : busy_(sim.busy_) {
  if (busy_.exchange(true, std::memory_order_acquire))
    throw SimulationBusy(
        std::string("the simulation is busy: ") + what +
        " called from another thread while a step runs, or from its progress callback (one call at a time per "
        "simulation)");
}

void Simulation::check_health(StepStats& st) {
  if (failure_policy_ == FailurePolicy::Ignore) return;
  st.solver_stalled = !st.solve.converged && st.solve.iterations > 0 && st.solve.relative_residual >= 1;
  double growth_percent = 0;
  if (std::isfinite(st.start_energy)) {
    // Total energy of the start state, and whether anything drove the body since the last one.
    double kinetic = 0;
    for (Index i = 0; i < num_nodes(); ++i) kinetic += 0.5 * lumped_masses_[i] * v_.col(i).squaredNorm();
    const double potential = -as_dofs(load_).dot(as_dofs(x_) - as_dofs(model_->rest_positions()));
    const double total = st.start_energy + attachments_.energy(x_) + kinetic + potential;
    const bool new_load = energy_check_.load.cols() != load_.cols() || energy_check_.load != load_;
    bool driven = !energy_check_.valid || new_load || energy_check_.attachments_version != attachments_.version();
    for (Index d : fixed_.list()) driven = driven || as_dofs(v_)[d] != 0.0;
    // Obstacles do work on the body (moved, or through the multipliers), in this step and in
    // the last one: its start energy, the baseline, was before that work (a probe that pushed
    // and let go leaves the body with more energy than it had when the contact began).
    driven = driven || !contacts_.empty() || energy_check_.touched;
    energy_check_.touched = !contacts_.empty();
    const double size = std::abs(st.start_energy) + kinetic + std::abs(potential) + 1e-300;
    // Against the lowest energy since the body was last driven, not the last step's: a slow
    // run-away (a mode growing by 0.5 % per step, bench/README.md) never grows 1 % in one
    // step while its energy is small, but its total climbs above the lowest within tens of steps.
    st.energy_growth = !driven && total - energy_check_.lowest > 1e-2 * size;
    growth_percent = 100 * (total - energy_check_.lowest) / size;
    energy_check_.valid = true;
    energy_check_.lowest = driven ? total : std::min(energy_check_.lowest, total);
    if (new_load) {  // (copied only when it changed: a step's load is the last one's as a rule)
      energy_check_.load = load_;
      energy_check_took_load_ = true;
    }
    energy_check_.attachments_version = attachments_.version();
  }
  if (failure_policy_ == FailurePolicy::Raise && (st.solver_stalled || st.start_inverted > 0 || st.energy_growth)) {
    // The message only for a step that fails (a stream costs a microsecond or so to build).
    std::ostringstream problem;
    if (st.solver_stalled)
      problem << "the linear solve stalled at its iteration cap (relative residual " << st.solve.relative_residual
              << " >= 1): raise the PCG iteration cap or use a stronger preconditioner";
    if (st.start_inverted > 0)
      problem << (problem.tellp() > 0 ? "; " : "") << st.start_inverted
              << " elements were inverted or flat at the start of the step (det F <= 0): the load or the time step "
                 "is too large for this mesh, or the material too soft";
    if (st.energy_growth)
      problem << (problem.tellp() > 0 ? "; " : "") << "the total energy grew by " << growth_percent
              << " % (of its size) above the lowest it reached while nothing drove the body: a run-away (too few PCG "
                 "iterations, or a time step too large for the linearised step)";
    std::ostringstream msg;
    msg << "step " << stats_.steps + 1 << ": " << problem.str() << "; the state was restored (failure policy 'raise')";
    throw SolverFailure(msg.str());
  }
  stats_.stalled_steps += st.solver_stalled;
  stats_.inverted_steps += st.start_inverted > 0;
  stats_.energy_growth_steps += st.energy_growth;
}

StepInput Simulation::input() {
  return {*model_,
          x_,
          v_,
          load_,
          fixed_,
          attachments_,
          *solver_,
          failure_policy_ != FailurePolicy::Ignore,
          has_contact() ? &contacts_ : nullptr};
}

Index Simulation::obstacle_index(const Obstacle& obstacle) const {
  for (size_t j = 0; j < obstacle_links_.size(); ++j)
    if (obstacle_links_[j].obstacle.get() == &obstacle) return static_cast<Index>(j);
  return -1;
}

namespace {
void check_friction(double friction) {
  if (!std::isfinite(friction) || friction < 0) {
    std::ostringstream msg;
    msg << "the friction coefficient must be non-negative and finite, not " << friction;
    throw InvalidInput(msg.str());
  }
}
}  // namespace

void Simulation::add_obstacle(std::shared_ptr<Obstacle> obstacle, double friction) {
  const Claim claim(*this, "adding an obstacle");
  if (!obstacle) throw InvalidInput("add_obstacle needs an obstacle");
  check_friction(friction);
  if (obstacle_index(*obstacle) >= 0) throw InvalidInput("this " + obstacle->describe() + " was added already");
  if (is_explicit(integrator_->settings().kind))
    throw InvalidInput(std::string("contact needs an implicit integrator ('linearized' or 'newton'), not '") +
                       integrator_->name() + "'");
  check_outside(*obstacle, contacts_);
  ensure_contact_properties();
  ObstacleLink link;
  link.obstacle = std::move(obstacle);
  link.friction = friction;
  obstacle_links_.push_back(std::move(link));
}

void Simulation::check_outside(const Obstacle& obstacle, const ContactSet& set) const {
  // A body that starts inside would be thrown out by the contact force at the first step:
  // refuse, naming how deep, so the user moves one or the other.
  const Pose pose = obstacle.pose();
  const double size = (x_.rowwise().maxCoeff() - x_.rowwise().minCoeff()).norm();
  const Nodes positions = set.unit_positions(x_);
  Index inside = 0, deepest = -1;
  double depth = 0;
  Vec3 normal;
  set.for_each_unit([&](Index i) {
    const double d = obstacle.local_distance(pose.to_local(positions.col(i)), normal);
    if (d < -1e-9 * size) {
      ++inside;
      if (d < depth) depth = d, deepest = i;
    }
  });
  if (inside > 0) {
    const bool points = !set.points().empty();
    std::ostringstream msg;
    msg << inside << (points ? " contact points" : " contact nodes") << " start inside the " << obstacle.describe()
        << (points ? " (point " : " (node ") << deepest << " by " << -depth
        << " m): move the body or the obstacle apart before adding it";
    throw InvalidInput(msg.str());
  }
}

void Simulation::set_contact_points(ContactPoints points) {
  const Claim claim(*this, "setting contact points");
  const Index n = num_nodes();
  if (points.per_point < 1 || points.nodes.size() != points.weights.size() ||
      points.nodes.size() % static_cast<size_t>(points.per_point) != 0 || points.nodes.empty())
    throw InvalidInput("contact points need per_point >= 1 and per_point nodes and weights per point");
  for (size_t k = 0; k < points.nodes.size(); ++k) {
    const Index p = static_cast<Index>(k) / points.per_point;
    if (points.nodes[k] < 0 || points.nodes[k] >= n)
      throw InvalidInput("contact point " + std::to_string(p) + " refers to node " + std::to_string(points.nodes[k]) +
                         ", out of range [0, " + std::to_string(n) + ")");
    if (!std::isfinite(points.weights[k]))
      throw InvalidInput("contact point " + std::to_string(p) + " has a non-finite weight");
  }
  for (Index p = 0; p < points.size(); ++p) {
    double sum = 0;
    for (int k = 0; k < points.per_point; ++k) sum += points.weights[p * points.per_point + k];
    if (std::abs(sum - 1) > 1e-6)
      throw InvalidInput("the weights of contact point " + std::to_string(p) + " sum to " + std::to_string(sum) +
                         ", not 1");
  }
  if (contacts_.has_parts())
    throw InvalidInput("contact points touch obstacles only: clear the contact between parts first");
  ensure_contact_properties();
  ContactSet candidate = contacts_;  // checked against the obstacles before anything changes
  candidate.set_points(std::move(points));
  for (const ObstacleLink& link : obstacle_links_) check_outside(*link.obstacle, candidate);
  contacts_ = std::move(candidate);
}

void Simulation::ensure_contact_properties() {
  if (!contacts_.has_node_properties()) {
    // Each node's share of the rest stiffness (trace / 3 of its diagonal block): with its mass
    // it sets the contact stiffness (contact_set.hpp). Once per simulation.
    BlockSparseMatrix k = model_->pattern();
    k.set_zero();
    Request what;
    what.stiffness = StiffnessKind::Model;
    Results out;
    out.stiffness = &k;
    model_->evaluate(model_->rest_positions(), what, out);
    Vec node_stiffness(num_nodes()), node_sizes(num_nodes());
    const Nodes& rest = model_->rest_positions();
    for (Index i = 0; i < num_nodes(); ++i) {
      node_stiffness[i] = std::max(0.0, k.block(k.diagonal_block(i)).trace() / 3);
      double sum = 0;
      int count = 0;
      for (int b = k.row_start()[i]; b < k.row_start()[i + 1]; ++b)
        if (k.columns()[b] != i) sum += (rest.col(k.columns()[b]) - rest.col(i)).norm(), ++count;
      node_sizes[i] = count ? sum / count : 0.0;
    }
    contacts_.set_node_properties(lumped_masses_, node_stiffness, node_sizes);
  }
}

void Simulation::set_part_contact(const Triangles& surface, const std::vector<int>& part_of_node, double friction,
                                  bool self_contact) {
  const Claim claim(*this, "setting contact between parts");
  check_friction(friction);
  if (is_explicit(integrator_->settings().kind))
    throw InvalidInput(std::string("contact needs an implicit integrator ('linearized' or 'newton'), not '") +
                       integrator_->name() + "'");
  const Index n = num_nodes();
  if (static_cast<Index>(part_of_node.size()) != n)
    throw InvalidInput("part_of_node must have one entry per node (" + std::to_string(n) + "), not " +
                       std::to_string(part_of_node.size()));
  int num_parts = 0;
  for (int p : part_of_node) {
    if (p < 0) throw InvalidInput("part ids must be non-negative");
    num_parts = std::max(num_parts, p + 1);
  }
  if (num_parts < 2 && !self_contact)
    throw InvalidInput("contact between parts needs a body of at least two parts (or self-contact)");
  if (!contacts_.points().empty())
    throw InvalidInput("contact between parts needs the surface nodes as contact points, not a surface's points");
  std::vector<Triangles> local(num_parts);
  std::vector<std::vector<Index>> nodes(num_parts);
  std::vector<int> vertex(static_cast<size_t>(n), -1);
  for (size_t t = 0; t < surface.size(); ++t) {
    for (int k = 0; k < 3; ++k)
      if (surface[t][k] < 0 || surface[t][k] >= n)
        throw InvalidInput("surface triangle " + std::to_string(t) + " refers to node " +
                           std::to_string(surface[t][k]) + ", out of range [0, " + std::to_string(n) + ")");
    const int p = part_of_node[surface[t][0]];
    if (part_of_node[surface[t][1]] != p || part_of_node[surface[t][2]] != p)
      throw InvalidInput("surface triangle " + std::to_string(t) + " joins two parts");
    std::array<int, 3> corners;
    for (int k = 0; k < 3; ++k) {
      const Index node = surface[t][k];
      if (vertex[node] < 0) {
        vertex[node] = static_cast<int>(nodes[p].size());
        nodes[p].push_back(node);
      }
      corners[k] = vertex[node];
    }
    local[p].push_back(corners);
  }
  std::vector<PartSurface> parts(num_parts);
  for (int p = 0; p < num_parts; ++p) {
    Nodes vertices(3, static_cast<Index>(nodes[p].size()));
    for (Index k = 0; k < vertices.cols(); ++k) vertices.col(k) = x_.col(nodes[p][k]);
    try {
      parts[p].mesh = std::make_shared<TriangleMesh>(vertices, local[p]);
    } catch (const InvalidInput& e) {
      throw InvalidInput("the surface of part " + std::to_string(p) + " is not a closed surface: " + e.what());
    }
    parts[p].nodes = std::move(nodes[p]);
    parts[p].triangles = parts[p].mesh->triangles();
  }
  // A part that starts inside another would be thrown out by the contact force at the first
  // step: refuse, naming how deep.
  const double size = (x_.rowwise().maxCoeff() - x_.rowwise().minCoeff()).norm();
  Vec3 normal;
  for (Index i : contacts_.nodes())
    for (int p = 0; p < num_parts; ++p) {
      if (p == part_of_node[i]) continue;
      const double d = parts[p].mesh->local_distance(x_.col(i), normal);
      if (d < -1e-9 * size) {
        std::ostringstream msg;
        msg << "node " << i << " of part " << part_of_node[i] << " starts inside part " << p << " (by " << -d
            << " m): move the parts apart";
        throw InvalidInput(msg.str());
      }
    }
  ensure_contact_properties();
  // A node's neighbourhood: the nodes it shares an element with, the blocks of its row of the
  // model's pattern (fixed for the model's life, which is the simulation's).
  contacts_.set_parts(part_of_node, std::move(parts), friction, self_contact ? &model_->pattern() : nullptr);
}

void Simulation::clear_part_contact() {
  const Claim claim(*this, "clearing contact between parts");
  contacts_.set_parts({}, {}, 0);
}

void Simulation::remove_obstacle(const Obstacle& obstacle) {
  const Claim claim(*this, "removing an obstacle");
  const Index j = obstacle_index(obstacle);
  if (j < 0) throw InvalidInput("this " + obstacle.describe() + " is not an obstacle of the simulation");
  obstacle_links_.erase(obstacle_links_.begin() + j);
  contacts_.reset();  // its contacts' obstacle indices would be stale
}

void Simulation::set_friction(const Obstacle& obstacle, double friction) {
  const Claim claim(*this, "setting friction");
  check_friction(friction);
  const Index j = obstacle_index(obstacle);
  if (j < 0) throw InvalidInput("this " + obstacle.describe() + " is not an obstacle of the simulation");
  obstacle_links_[j].friction = friction;
}

void Simulation::set_contact_nodes(const std::vector<Index>& nodes) {
  const Claim claim(*this, "setting contact nodes");
  std::vector<char> seen(num_nodes(), 0);
  for (Index i : nodes) {
    if (i < 0 || i >= num_nodes()) {
      std::ostringstream msg;
      msg << "contact node index " << i << " is out of range [0, " << num_nodes() << ")";
      throw InvalidInput(msg.str());
    }
    if (seen[i]) throw InvalidInput("contact node " + std::to_string(i) + " is listed twice");
    seen[i] = 1;
  }
  contacts_.reset();
  contacts_.set_nodes(nodes);
  contacts_.set_points({});
}

void Simulation::set_contact_settings(const ContactSettings& settings) {
  const Claim claim(*this, "changing the contact settings");
  contacts_.set_settings(settings);
}

void Simulation::detect_contacts(double dt) {
  contacts_.detect(obstacle_links_, obstacle_poses_, x_, v_, gravity_, dt);
}

void Simulation::rebuild_gravity_forces() {
  // Consistent body-force load: M (1 (x) g). With a lumped mass it is m_i g per node.
  const Index n = num_nodes();
  Nodes g(3, n);
  g.colwise() = gravity_;
  gravity_forces_.resize(3, n);
  Vec out(3 * n);
  integrator_->mass().multiply(as_dofs(g), out);
  as_dofs(gravity_forces_) = out;
}

void Simulation::set_gravity(const Vec3& g) {
  const Claim claim(*this, "setting gravity");
  if (!g.allFinite()) throw InvalidInput("gravity must be finite");
  gravity_ = g;
  rebuild_gravity_forces();
}

void Simulation::set_fixed_nodes(const std::vector<Index>& nodes) {
  const Claim claim(*this, "fixing nodes");
  const Index n = num_nodes();
  std::vector<char> flags(3 * n, 0);
  for (Index i : nodes) {
    if (i < 0 || i >= n) {
      std::ostringstream msg;
      msg << "node index " << i << " is out of range [0, " << n << ")";
      throw InvalidInput(msg.str());
    }
    flags[3 * i] = flags[3 * i + 1] = flags[3 * i + 2] = 1;
  }
  fixed_ = FixedDofs(model_->pattern(), flags);
  fixed_nodes_ = nodes;
  contacts_.set_fixed_nodes(n, nodes);
  integrator_->constraints_changed(fixed_);
  solver_->constraints_changed(fixed_);
}

void Simulation::attach(const std::vector<Index>& nodes, const Nodes& targets, const Vec& stiffness) {
  const Claim claim(*this, "attaching nodes");
  attachments_.attach(nodes, targets, stiffness);
}

void Simulation::move_attachments(const std::vector<Index>& nodes, const Nodes& targets) {
  const Claim claim(*this, "moving attachments");
  attachments_.move(nodes, targets);
}

void Simulation::detach(const std::vector<Index>& nodes) {
  const Claim claim(*this, "detaching nodes");
  attachments_.detach(nodes);
}

void Simulation::detach_all() {
  const Claim claim(*this, "detaching nodes");
  attachments_.clear();
}

std::unique_ptr<Integrator> Simulation::make_attached_integrator(const IntegratorSettings& settings) const {
  auto integrator = make_integrator(settings);  // validates before anything changes
  integrator->attach(*model_);
  integrator->constraints_changed(fixed_);
  return integrator;
}

void Simulation::set_settings(const IntegratorSettings& settings) {
  const Claim claim(*this, "changing the settings");
  if (is_explicit(settings.kind) && has_contact())
    throw InvalidInput(std::string("contact needs an implicit integrator ('linearized' or 'newton'), not '") +
                       integrator_name(settings.kind) +
                       "': remove the obstacles (and the contact between parts) first");
  integrator_ = make_attached_integrator(settings);
  solver_->reset();
  rebuild_gravity_forces();
}

void Simulation::set_solver(std::unique_ptr<LinearSolver> solver) {
  const Claim claim(*this, "changing the solver");
  if (!solver) throw InvalidInput("Simulation needs a linear solver");
  solver->set_geometry(model_->rest_positions());
  solver_ = std::move(solver);
}

void Simulation::set_failure_policy(FailurePolicy policy) {
  const Claim claim(*this, "changing the failure policy");
  failure_policy_ = policy;
}

void Simulation::reset_stats() {
  const Claim claim(*this, "reset_stats");
  stats_ = {};
}

void Simulation::reset() {
  const Claim claim(*this, "reset");
  auto integrator = make_attached_integrator(integrator_->settings());  // fresh carried state
  integrator_ = std::move(integrator);
  solver_->reset();
  model_->reset_caches();
  x_ = model_->rest_positions();
  v_.setZero();
  a_.setZero();
  f_ext_.setZero();
  time_ = 0;
  stats_ = {};
  energy_check_ = {};
  energy_check_backup_ = {};
  energy_check_took_load_ = false;
  contacts_.reset();
  for (ObstacleLink& link : obstacle_links_) link.seen = false;
}

void Simulation::record_estimates() {
  if (ExplicitIntegrator* e = integrator_->as_explicit()) {
    const auto [ms, count] = e->take_estimate_cost();
    stats_.estimate_ms += ms;
    stats_.estimates += count;
  }
}

void Simulation::step(int n, const std::function<void(int done)>& after_each_step) {
  const Claim claim(*this, "step");
  // The wall time the stats report is the call's (checks, copies and commits included, as a
  // user times step()), without the user's callback.
  auto since = std::chrono::steady_clock::now();
  if (n < 0) throw InvalidInput("step count must be non-negative");
  check_finite_state(x_, v_, f_ext_);
  // x_, v_ and a_ change only when a step commits; they need a copy to restore only when
  // something can still fail after the first commit: a later step or the callback (the copy
  // is a few % of a small step).
  const bool backup_at_first_commit = n > 1 || static_cast<bool>(after_each_step);
  bool backed_up = false;
  const double time_before = time_;
  const SimulationStats stats_before = stats_;
  integrator_->save_state();
  if (solver_) solver_->save_state();
  model_->save_caches();
  energy_check_backup_ = static_cast<const EnergyBaseline&>(energy_check_);  // its scalars
  energy_check_took_load_ = false;
  const bool contact = has_contact();
  if (contact) {  // (copies of a few vectors: what a failed call restores)
    obstacle_links_backup_ = obstacle_links_;
    contacts_backup_ = contacts_;
    obstacle_poses_.resize(obstacle_links_.size());
    for (size_t j = 0; j < obstacle_links_.size(); ++j) obstacle_poses_[j] = obstacle_links_[j].obstacle->pose();
  }
  if (energy_check_.valid && (energy_check_.x_end != x_ || energy_check_.v_end != v_))
    energy_check_.valid = false;  // positions or velocities were written since the last call
  try {
    load_ = f_ext_ + gravity_forces_;
    const StepInput in = input();
    integrator_->begin(in);
    for (int s = 0; s < n; ++s) {
      if (contact) detect_contacts(integrator_->settings().time_step);
      StepStats st = integrator_->step(in, x_next_, v_next_);
      check_health(st);  // of the start state and the solve (may throw under Raise)
      if (Index i = first_non_finite_node(x_next_); i >= 0 || !v_next_.allFinite()) {
        std::ostringstream msg;
        msg << "step " << stats_.steps + 1 << " produced non-finite positions or velocities"
            << (i >= 0 ? " (first at node " + std::to_string(i) + ")" : "") << "; the state was restored. "
            << integrator_->non_finite_hint(st);
        throw SolverFailure(msg.str());
      }
      if (s == 0 && backup_at_first_commit) {  // (no allocation after the first call)
        x_backup_ = x_;
        v_backup_ = v_;
        a_backup_ = a_;
        backed_up = true;
      }
      // Copy, not swap: NumPy views point at x_'s and v_'s buffers and must stay valid.
      x_ = x_next_;
      a_ = (v_next_ - v_) / st.dt;
      v_ = v_next_;
      time_ += st.dt;
      if (contact) {
        contacts_.commit(x_);
        for (size_t j = 0; j < obstacle_links_.size(); ++j) {
          obstacle_links_[j].last_pose = obstacle_poses_[j];  // the obstacle's motion is behind us
          obstacle_links_[j].seen = true;
        }
      }
      ++stats_.steps;
      stats_.substeps += st.substeps;
      stats_.total_iterations += st.solve.iterations;
      stats_.kept_matrix_steps += st.kept_matrix;
      stats_.simulated_time += st.dt;
      stats_.last = std::move(st);
      record_estimates();
      const auto now = std::chrono::steady_clock::now();
      stats_.wall_ms += std::chrono::duration<double, std::milli>(now - since).count();
      if (after_each_step) after_each_step(s + 1);
      since = std::chrono::steady_clock::now();
    }
    if (failure_policy_ != FailurePolicy::Ignore) {
      energy_check_.x_end = x_;
      energy_check_.v_end = v_;
    }
    stats_.wall_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
  } catch (...) {
    if (backed_up) {
      x_ = x_backup_;
      v_ = v_backup_;
      a_ = a_backup_;
    }
    time_ = time_before;
    stats_ = stats_before;
    integrator_->restore_state();
    if (solver_) solver_->restore_state();
    model_->restore_caches();
    static_cast<EnergyBaseline&>(energy_check_) = energy_check_backup_;
    if (energy_check_took_load_) energy_check_.valid = false;
    if (contact) {
      obstacle_links_ = obstacle_links_backup_;
      contacts_ = contacts_backup_;
    }
    throw;
  }
}

StaticResult Simulation::solve_static(const StaticSettings& settings, const Nodes* prescribed,
                                      const std::function<void(int done)>& after_each_load_step) {
  const Claim claim(*this, "solve_static");
  if (has_contact())
    throw InvalidInput(
        "solve_static does not include contact: step the simulation to rest instead (mass damping speeds it up), or "
        "remove the obstacles (and the contact between parts)");
  if (!attachments_.empty())
    throw InvalidInput(
        "solve_static does not include attachment springs: detach the nodes first (or fix them and prescribe their "
        "positions)");
  check_finite_state(x_, v_, f_ext_);
  x_backup_ = x_;
  model_->save_caches();
  load_ = f_ext_ + gravity_forces_;
  DirectSolver direct;
  try {
    StaticResult result =
        corotate::solve_static(*model_, x_, load_, fixed_, settings, direct, prescribed, after_each_load_step);
    v_.setZero();
    return result;
  } catch (...) {
    x_ = x_backup_;
    model_->restore_caches();
    throw;
  }
}

ExplicitIntegrator& Simulation::explicit_integrator() {
  ExplicitIntegrator* e = integrator_->as_explicit();
  if (!e)
    throw InvalidInput(std::string("the '") + integrator_->name() +
                       "' integrator is implicit: it has no explicit stability limit");
  return *e;
}

const StabilityEstimate& Simulation::stability() {
  const Claim claim(*this, "a stability estimate");
  ExplicitIntegrator& e = explicit_integrator();
  const StabilityEstimate& est = e.stability(input());
  record_estimates();
  return est;
}

StabilityEstimate Simulation::estimate_stability(bool bound) {
  const Claim claim(*this, "a stability estimate");
  ExplicitIntegrator& e = explicit_integrator();
  const StabilityEstimate est = e.estimate_stability(input(), bound);
  record_estimates();
  return est;
}

double Simulation::kinetic_energy() const {
  const Claim claim(*this, "kinetic_energy");
  Vec mv(v_.size());
  integrator_->mass().multiply(as_dofs(v_), mv);
  return 0.5 * as_dofs(v_).dot(mv);
}

}  // namespace corotate
