#include "corotate/models/linear_fem.hpp"

namespace corotate {

template <class E>
LinearFEM<E>::LinearFEM(const Nodes& rest, const Connectivity& cells, const Material& material)
    : FEModel<E>(rest, cells, material) {
  constexpr int N = E::num_nodes;
  auto& set = this->elements_;
  stiffness_ = set.pattern();
  stiffness_.set_zero();
  for (Index e = 0; e < set.num_elements(); ++e) {
    const int* ids = set.block_ids(e);
    const auto& K = set.stiffness(e);
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) stiffness_.block(ids[a * N + b]) += K.template block<3, 3>(3 * a, 3 * b);
  }
  set.release_stiffness();  // the assembled K is all this model uses
  displacement_.resize(3 * rest.cols());
  kd_.resize(3 * rest.cols());
}

template <class E>
void LinearFEM<E>::add_forces(const Nodes& x, Nodes& f) const {
  displacement_ = as_dofs(x) - as_dofs(this->elements_.rest());
  stiffness_.multiply(displacement_, kd_);
  as_dofs(f) -= kd_;
}

template <class E>
void LinearFEM<E>::add_stiffness(double scale, BlockSparseMatrix& A) const {
  auto& dst = A.values();
  const auto& src = stiffness_.values();
  for (size_t k = 0; k < dst.size(); ++k) dst[k] += scale * src[k];
}

template <class E>
double LinearFEM<E>::energy(const Nodes& x) const {
  displacement_ = as_dofs(x) - as_dofs(this->elements_.rest());
  stiffness_.multiply(displacement_, kd_);
  return 0.5 * displacement_.dot(kd_);
}

template class LinearFEM<Tet4>;
template class LinearFEM<Hex8>;
template class LinearFEM<Hex20>;

}  // namespace corotate
