// Shared part of the finite-element force models: the element set and what follows from it.
#pragma once

#include "corotate/fem/element_set.hpp"
#include "corotate/models/force_model.hpp"

namespace corotate {

template <class E>
class FEModel : public ForceModel {
 public:
  FEModel(const Nodes& rest, const Connectivity& cells, const Material& material)
      : elements_(rest, cells, material) {}

  Index num_nodes() const override { return elements_.num_nodes(); }
  const Nodes& rest_positions() const override { return elements_.rest(); }
  const BlockSparseMatrix& pattern() const override { return elements_.pattern(); }
  BlockSparseMatrix mass_matrix(bool lumped) const override { return elements_.mass_matrix(lumped); }
  const ElementSet<E>& elements() const { return elements_; }

 protected:
  ElementSet<E> elements_;
};

}  // namespace corotate
