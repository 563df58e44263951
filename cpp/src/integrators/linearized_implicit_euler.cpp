// The linearised implicit Euler step (see implicit_integrator.hpp): one linear solve.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "corotate/integrators/implicit_integrator.hpp"
#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// v_i <- R v_i (or R^T v_i) for every node i, R the rotation of the node's part.
void turn_nodes(const AggregateRotations& parts, bool transpose, Vec& v) {
  const std::vector<int>& part = parts.aggregate_of_node();
  for (size_t i = 0; i < part.size(); ++i) {
    const Mat3& R = parts.rotation(part[i]);
    auto vi = v.segment<3>(3 * static_cast<Index>(i));
    const Vec3 turned = transpose ? Vec3(R.transpose() * vi) : Vec3(R * vi);
    vi = turned;
  }
}

class LinearizedImplicitEuler final : public ImplicitIntegrator {
  // Solves after the first one, when contacts release. A fine embedded surface's many points
  // on a coarse element rocking on the floor needed more than 4 (the points the last pass
  // left released went deeper into the floor: docs/notes/performance.md); resting bodies
  // need none.
  static constexpr int kContactPasses = 8;
  static constexpr double kContactTolerance = 1e-4;  // PCG, where the active set reads the answer
  static constexpr int kContactIterations = 200;

 public:
  using ImplicitIntegrator::ImplicitIntegrator;

  StepStats step(const StepInput& in, Nodes& x_new, Nodes& v_new) override {
    using clock = std::chrono::steady_clock;
    StepStats stats;
    const auto t_start = clock::now();
    const double dt = settings().time_step, alpha = settings().mass_damping, beta = settings().stiffness_damping;
    stats.dt = dt;

    // b = dt (f(x) - (dt + beta) K v + f_ext) - dt alpha M v, where the first two terms are
    // the force linearised about x evaluated at y = x + (dt + beta) v: one sweep over the
    // elements gives them and A, with no matrix-vector product.
    // With contacts, the linearised step treats every contact as holding (its force is
    // linear in the step): a contact whose force at the answer pulls (a node of a body that
    // lands on its bottom, whose own path crossed the floor too; a tool lifted away) is
    // released and the step solved again, a few times at most (contact_set.hpp,
    // update_active).
    stats.solve.iterations = 0;
    for (int pass = 0;; ++pass) {
      const int iterations_before = stats.solve.iterations;
      force_ = in.load;
      y_ = in.x + (dt + beta) * in.v;
      // Only the blocks the solve reads: a third fewer to add (a PCG whose preconditioner is
      // built reads the rest only when it rebuilds). Where the solver multiplies in float32
      // anyway, the system goes straight into its float32 copy: no double matrix to fill and
      // convert (LinearSolver::single_precision_target).
      SinglePrecisionSymmetric* single =
          in.model.assembles_single_precision() ? in.solver.single_precision_target() : nullptr;
      const bool lower_blocks = !single && in.solver.needs_lower_blocks();
      // Keep last step's matrix while the elements turned little since (kept_system.hpp).
      // With contacts only in float32, where the body's part of the matrix is kept aside.
      const bool contacts = in.has_contacts();
      const bool track = in.model.measures_frame_drift() && (!contacts || single);
      KeptSystem::Key key;
      if (track)
        key = {&in.solver,
               single ? static_cast<const void*>(single) : &system_,
               single ? single->layout_id() : 0,
               mass_version_,
               in.attachments.stiffness_version(),
               &in.model};
      // Each part's turn since the matrix was assembled: the turn of a kept matrix (below), and
      // what the drift is measured beyond.
      const bool turned = track && in.model.stiffness_turns() && !kept_turn_.empty() &&
                          body_parts_.size() == static_cast<size_t>(in.x.cols());
      double largest_turn = 0;
      if (turned) {
        kept_turn_.update(in.x);
        part_turns_.resize(num_body_parts_);
        for (int p = 0; p < num_body_parts_; ++p) {
          part_turns_[p] = Eigen::Quaterniond(kept_turn_.rotation(p));
          largest_turn = std::max(largest_turn, 2 * std::acos(std::min(1.0, std::abs(part_turns_[p].w()))));
        }
      }
      // The contacts' terms are in the world's frame: with them the kept matrix is not turned,
      // so the parts' turns count against the angle as well.
      const bool keep = track && pass == 0 && (!contacts || kept_image_valid_) &&
                        kept_.may_keep(key, settings().matrix_reuse_angle - (contacts ? largest_turn : 0.0));
      if (!keep) {
        kept_.forget();  // until the matrix is whole again
        kept_image_valid_ = false;
        if (single) single->start_assembly(mass_, 1 + dt * alpha, mass_version_);
        else system_.assign_scaled(1 + dt * alpha, mass_, lower_blocks);
      } else if (kept_has_contacts_ || contacts) {
        single->restore_values(kept_image_);  // the body's part, without the last contacts
      } else if (lower_blocks && !kept_lower_blocks_) {
        // A solver that now factorizes (a reference factor refreshing) reads the lower blocks,
        // which the kept matrix was assembled without. Mirrored rather than assembled: the
        // matrix and the steps that keep it stay what they were.
        system_.mirror_upper_blocks();
        kept_lower_blocks_ = true;
      }
      if (!keep) kept_lower_blocks_ = single || lower_blocks;
      Request what;
      what.lower_blocks = lower_blocks;
      what.forces = true;
      what.energy = in.diagnose;  // at x, in the same sweep: for the simulation's run-away checks
      what.count_inverted = in.diagnose;
      what.forces_at = &y_;
      what.stiffness = keep ? StiffnessKind::None : StiffnessKind::Model;
      what.stiffness_scale = dt * dt + dt * beta;
      what.frame_drift = track;
      if (turned) {
        what.frame_turn = part_turns_.data();
        what.frame_turn_of_node = body_parts_.data();
      }
      Results out;
      out.forces = &force_;
      if (!keep && single) out.single_stiffness = single;
      else if (!keep) out.stiffness = &system_;
      in.model.evaluate(in.x, what, out);
      if (keep) {
        kept_.measured(out.frame_drift);
        stats.kept_matrix = true;
      }
      // The attachment springs are linear: their force at y is their linearisation, and their
      // stiffness goes into A like the body's (damped by beta with it).
      in.attachments.add_forces(y_, force_);
      if (!keep && single) in.attachments.add_stiffness(what.stiffness_scale, *single);
      else if (!keep) in.attachments.add_stiffness(what.stiffness_scale, system_);
      if (!keep && track && contacts) {  // the body's part kept aside for the next steps
        in.fixed.project(*single);
        single->save_values(kept_image_);
        kept_image_valid_ = true;
      }
      kept_has_contacts_ = contacts;
      // Contacts likewise (undamped by beta), linearised where each node's free flight ends:
      // a node at rest above the floor touches it only under the step's gravity. The
      // friction's Hessian times dt^2 is its damping dt dF/dv on the new velocity.
      if (in.has_contacts()) in.contacts->add_linearized(y_, force_, dt * dt, single ? nullptr : &system_, single);
      if (in.diagnose) {
        stats.start_energy = out.energy;
        stats.start_inverted = out.inverted;
      }
      rhs_ = dt * as_dofs(force_);
      if (alpha != 0) {
        mass_.multiply(as_dofs(in.v), work_);
        rhs_ -= (dt * alpha) * work_;
      }
      if (single && (!keep || contacts)) in.fixed.project(*single);
      else if (!keep) in.fixed.project(system_);
      in.fixed.project(rhs_);
      stats.assembly_ms = ms_since(t_start);

      // dv_ still holds the previous step's answer: the warm start. A is assembled at x.
      const auto t_solve = clock::now();
      // The preconditioner follows the frames the matrix was assembled in.
      if (!keep) in.solver.set_positions(in.x);
      else in.solver.same_matrix_next();
      // Where the active set decides from the answer (an impact, a re-solve), the usual loose
      // tolerance would decide by noise (and a capped solve at an impact inverted elements).
      if (in.has_contacts() && (pass > 0 || in.contacts->has_impacts()))
        in.solver.request_accuracy(kContactTolerance, kContactIterations);
      // Contacts between parts of the body couple nodes outside the pattern: the solve adds them.
      const CouplingScope coupling(in.solver, in.has_contacts() && in.contacts->has_coupling() ? in.contacts : nullptr,
                                   in.has_contacts() ? &in.contacts->diagonal_terms() : nullptr);
      // A kept matrix is the system of the configuration it was assembled at: turned by the
      // rotation of each part of the body (each connected body) since, R A R^T, whose solve
      // is R A^-1 R^T (R orthogonal). Without the turn a body swinging as a whole (Table 1's
      // cage on its anchor) met the kept stiffness against its rigid rotation and strayed 19 %
      // from its path; one rotation per node instead of per part broke the conservation of
      // momentum (a part's translation is no longer in the turned matrix's null space).
      const bool turn = keep && turned && !contacts;
      if (turn) {
        turn_nodes(kept_turn_, true, rhs_);
        turn_nodes(kept_turn_, true, dv_);
      }
      try {
        stats.solve = single ? in.solver.solve_single_precision(rhs_, dv_) : in.solver.solve(system_, rhs_, dv_);
      } catch (const NotPositiveDefinite& e) {
        // A linearised step needs M + dt^2 K positive definite; a hyperelastic tangent under
        // compression (StVK sheets crumpling, inverted elements) is not, and the step that
        // meets it is too large for the linearisation anyway.
        throw NotPositiveDefinite(std::string(e.what()) +
                                  ": the linearised step met an indefinite stiffness (compressed StVK, membranes or "
                                  "inverted elements): the step is too large for its linearisation; use a smaller dt "
                                  "with Body(..., project_psd=True), which keeps the system positive definite");
      }
      if (turn) turn_nodes(kept_turn_, false, dv_);
      in.fixed.project(dv_);
      stats.solve_ms = ms_since(t_solve);
      if (track && !keep) {
        if (in.model.stiffness_turns()) {
          if (body_parts_.size() != static_cast<size_t>(in.x.cols()))
            body_parts_ = connected_parts(in.model.pattern(), &num_body_parts_);
          kept_turn_.build(body_parts_, num_body_parts_, in.x);
        }
        kept_.assembled(key, out.frame_drift);
      }

      as_dofs(v_new) = as_dofs(in.v) + dv_;
      as_dofs(x_new) = as_dofs(in.x) + dt * as_dofs(v_new);
      stats.solve.iterations += iterations_before;
      // A capped solve that did not even halve the residual, with contacts: the
      // preconditioner was built for another contact set (a reference factor refreshed at an
      // impact). Solved again, accurately, as a pass of its own (from zero: the answer is
      // no start), with the preconditioner refreshed for this system.
      const bool stalled = in.has_contacts() && !stats.solve.converged && stats.solve.relative_residual > 0.5;
      if (stalled) dv_.setZero();
      if (!in.has_contacts() || pass == kContactPasses || (!stalled && !in.contacts->update_active(x_new))) break;
      ++stats.contact_passes;
    }
    stats.total_ms = ms_since(t_start);
    return stats;
  }
};
}  // namespace

std::unique_ptr<Integrator> make_linearized_implicit_euler(const IntegratorSettings& settings) {
  return std::make_unique<LinearizedImplicitEuler>(settings);
}

}  // namespace corotate
