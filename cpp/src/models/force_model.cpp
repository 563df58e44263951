#include "corotate/models/force_model.hpp"

#include <sstream>

#include "corotate/sparse/single_precision_symmetric.hpp"

namespace corotate {

double ForceModel::energy(const Nodes& x) {
  Request what;
  what.energy = true;
  Results out;
  evaluate(x, what, out);
  return out.energy;
}

void ForceModel::add_forces(const Nodes& x, Nodes& f) {
  Request what;
  what.forces = true;
  Results out;
  out.forces = &f;
  evaluate(x, what, out);
}

void ForceModel::add_stiffness(const Nodes& x, StiffnessKind kind, double scale, BlockSparseMatrix& A) {
  Request what;
  what.stiffness = kind;
  what.stiffness_scale = scale;
  Results out;
  out.stiffness = &A;
  evaluate(x, what, out);
}

Vec ForceModel::lumped_masses() const {
  const BlockSparseMatrix M = mass_matrix(true);
  Vec m(num_nodes());
  for (Index i = 0; i < num_nodes(); ++i) m[i] = M.block(M.diagonal_block(i))(0, 0);
  return m;
}

void ForceModel::check_evaluation(const Nodes& x, const Request& what, const Results& out) const {
  const Index n = num_nodes();
  auto fail = [&](const char* what_is_wrong) {
    std::ostringstream msg;
    msg << name() << " model: " << what_is_wrong << " (the model has " << n << " nodes)";
    throw InvalidInput(msg.str());
  };
  if (x.cols() != n) fail("positions have the wrong number of nodes");
  if (what.forces && (!out.forces || out.forces->cols() != n))
    fail("the force buffer is missing or has the wrong size");
  if (what.forces_at && what.forces_at->cols() != n) fail("the linearisation point has the wrong number of nodes");
  if (what.forces_at && what.stiffness != StiffnessKind::None && what.stiffness != StiffnessKind::Model)
    fail("linearised forces go with the Model stiffness only");
  if (out.single_stiffness) {
    if (!assembles_single_precision() || what.stiffness != StiffnessKind::Model || !what.forces || what.lower_blocks)
      fail("only the implicit step's forces and Model stiffness go to a float32 system, and not from this model");
    if (!out.single_stiffness->has_layout() || out.single_stiffness->num_pattern_blocks() != pattern().num_blocks() ||
        out.single_stiffness->num_nodes() != pattern().num_nodes())
      fail("the float32 system does not have the model's pattern");
  } else if (what.stiffness != StiffnessKind::None &&
             (!out.stiffness || out.stiffness->num_blocks() != pattern().num_blocks() ||
              out.stiffness->num_nodes() != pattern().num_nodes())) {
    fail("the stiffness matrix is missing or does not have the model's pattern");
  }
}

}  // namespace corotate
