// The registered element types, one list each for solids and membranes: a new element type
// is its file in elements/ plus one entry here. Every model family, the embedding, the mass,
// the cell-type table that Python reads (cell_types.hpp) and the tests that iterate over it
// then know it. Anything that must act per cell type visits this list (visit_cell_type) rather
// than comparing names by hand.
#pragma once

#include <string>
#include <vector>

#include "corotate/elements/hex20.hpp"
#include "corotate/elements/hex8.hpp"
#include "corotate/elements/tet10.hpp"
#include "corotate/elements/tet4.hpp"
#include "corotate/elements/tri3.hpp"

namespace corotate {

template <class... T>
struct TypeList {};
template <class T>
struct Tag {
  using type = T;
};

using SolidElements = TypeList<Tet4, Tet10, Hex8, Hex20>;
using MembraneElements = TypeList<Tri3>;

// Calls f(Tag<T>{}) for the T of the list whose T::name equals name; false if none does.
template <class... T, class F>
bool visit_by_name(TypeList<T...>, const std::string& name, F&& f) {
  return ((name == T::name ? (f(Tag<T>{}), true) : false) || ...);
}
// Calls f(Tag<T>{}) for every T of the list, in order.
template <class... T, class F>
void for_each_type(TypeList<T...>, F&& f) {
  (f(Tag<T>{}), ...);
}
template <class... T>
std::vector<std::string> names_of(TypeList<T...>) {
  return {T::name...};
}

// Every registered cell type name, solids first.
std::vector<std::string> cell_type_names();
std::string joined(const std::vector<std::string>& names);

// Calls f(Tag<E>{}) for the solid element named cell_type; what names the caller in the
// error ("a surface can be embedded in ...") that lists the solid types when none matches.
template <class F>
void visit_solid_element(const std::string& cell_type, const std::string& what, F&& f) {
  if (!visit_by_name(SolidElements{}, cell_type, f))
    throw InvalidInput(what + " needs solid cells (" + joined(names_of(SolidElements{})) + "), not '" + cell_type +
                       "'");
}

}  // namespace corotate
