// When the linearised step keeps the system matrix of an earlier step.
//
// The co-rotated stiffness is K(R) = sum_e R_e K_e R_e^T: it changes with the configuration
// only through the element rotations. A step whose elements all turned by less than a small
// angle since the matrix was assembled can keep it: the force, f(x) - K(R) (y - x), is still
// evaluated with the current rotations (the element sweep, without the stiffness blocks), so
// a body at rest comes to the same rest, and only the implicit part of the step, A dv, uses
// rotations up to that angle old. This is the error control of Hecht et al. 2012 ("Updated
// sparse Cholesky factors for corotational elastodynamics"), applied to the whole matrix:
// reassemble once the largest element rotation since the assembly would pass the angle.
// The integrator turns the kept matrix with each connected part of the body (shape matching)
// and measures the elements' rotations beyond their part's; the preconditioner keeps the
// frames of the assembly (set_positions there only). docs/theory/implicit-step.md has the
// whole story and the measured deviations.
//
// The drift is measured by every sweep (Request::frame_drift) at the step's start
// positions, from the frames of the last assembly. The next step's is predicted as this one
// plus the last step's growth (a body that turns steadily), so the matrix is rebuilt before
// the angle is passed; right after an assembly the growth is the turn since the assembly
// before, per step (unknown at the first: that step's successor assembles too).
//
// Anything else the matrix holds must be as it was: the same solver and float32 target, the
// same mass, dt and damping (a new integrator), fixed DOFs (forget on constraints_changed)
// and attachment stiffness (Attachments::stiffness_version). Contacts come and go every step:
// the integrator keeps the body's part of the float32 matrix aside and adds each step's own.
#pragma once

#include <cstdint>

namespace corotate {

class KeptSystem {
 public:
  // What the matrix was assembled into and with, besides the model's frames.
  struct Key {
    const void* solver = nullptr;
    const void* target = nullptr;     // the float32 system, or the integrator's double one
    std::uint64_t layout = 0;         // the float32 system's layout (0 for double)
    std::uint64_t mass_version = 0;
    long long attachments_stiffness = 0;
    const void* model = nullptr;
    bool operator==(const Key& o) const {
      return solver == o.solver && target == o.target && layout == o.layout && mass_version == o.mass_version &&
             attachments_stiffness == o.attachments_stiffness && model == o.model;
    }
  };

  // Whether this step may keep the matrix assembled under `key`, turned by at most `angle`.
  bool may_keep(const Key& key, double angle) const {
    return valid_ && key == key_ && angle > 0 && drift_ + growth_ < angle;
  }
  // A matrix was assembled (with its frames recorded) under key; its sweep measured the turn
  // since the frames of the assembly before (infinite for none).
  void assembled(const Key& key, double turn_since_last) {
    growth_ = turn_since_last / static_cast<double>(steps_since_assembly_);  // (infinite stays)
    valid_ = true;
    key_ = key;
    drift_ = 0;
    steps_since_assembly_ = 1;
  }
  // The drift measured by a kept step's sweep.
  void measured(double drift) {
    growth_ = drift > drift_ ? drift - drift_ : 0.0;
    drift_ = drift;
    ++steps_since_assembly_;
  }
  // The matrix no longer holds: the next step assembles.
  void forget() { valid_ = false; }
  bool valid() const { return valid_; }

 private:
  bool valid_ = false;
  Key key_;
  double drift_ = 0, growth_ = 0;  // the last drift measured, and its growth per step
  long steps_since_assembly_ = 1;
};

}  // namespace corotate
