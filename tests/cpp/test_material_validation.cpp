// Material::validate: parameters outside the physical range are InvalidInput; a material in
// a law's own parameters (material_of_law) checks each as the law declares and carries the
// law's small-strain moduli; RegionMaterials names a cell whose region has no material.
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "corotate/material.hpp"
#include "corotate/region_materials.hpp"
#include "test_driver.hpp"

using namespace corotate;

TEST(incompressible_poisson_ratio_is_rejected) {
  CHECK_THROWS((Material{1e6, 0.5, 1000.0}.validate()), InvalidInput);
  try {
    Material{1e6, 0.5, 1000.0}.validate();
  } catch (const InvalidInput& e) {
    CHECK(std::string(e.what()).find("nu = 0.5") != std::string::npos);
  }
  CHECK_THROWS((Material{1e6, 0.7, 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e6, -1.0, 1000.0}.validate()), InvalidInput);
}

TEST(other_bad_parameters_are_rejected) {
  CHECK_THROWS((Material{0.0, 0.3, 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{-1e6, 0.3, 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e6, 0.3, 0.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e6, std::nan(""), 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{std::numeric_limits<double>::infinity(), 0.3, 1000.0}.validate()), InvalidInput);
}

TEST(ill_conditioned_and_overflowing_parameters_are_rejected) {
  CHECK_THROWS((Material{1e6, std::nextafter(0.5, 0.0), 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e6, 0.49999999, 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e6, std::nextafter(-1.0, 0.0), 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e308, 0.3, 1000.0}.validate()), InvalidInput);
  CHECK_THROWS((Material{1e200, 0.3, 1000.0}.validate()), InvalidInput);  // E^2 overflows
  try {
    Material{1e6, std::nextafter(0.5, 0.0), 1000.0}.validate();
  } catch (const InvalidInput& e) {
    CHECK(std::string(e.what()).find("lambda/mu") != std::string::npos);
  }
  Material{1e6, 0.499999, 1.0}.validate();  // lambda/mu = 5e5: accepted
  Material{1e13, 0.3, 1.0}.validate();
}

TEST(valid_parameters_pass_and_give_the_lame_constants) {
  const Material m{2.6e6, 0.3, 1000.0};
  m.validate();
  Material{1e6, 0.4999, 1.0}.validate();
  Material{1e6, -0.99, 1.0}.validate();
  CHECK_NEAR(m.lame_mu(), 1e6, 1e-9);               // E / (2 (1 + nu))
  CHECK_NEAR(m.lame_lambda(), 1.5e6, 1e-9);          // E nu / ((1 + nu) (1 - 2 nu))
}

namespace {
bool message_has(const std::function<void()>& f, const std::string& text) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return std::string(e.what()).find(text) != std::string::npos;
  }
  return false;
}
}  // namespace

TEST(a_law_material_checks_its_parameters_and_has_the_small_strain_moduli) {
  const Material m = material_of_law("mooney_rivlin", {{"C01", 0.1e6}, {"bulk", 5e6}, {"C10", 0.3e6}}, 1100.0);
  CHECK(m.law == "mooney_rivlin");
  CHECK(m.parameters == std::vector<double>({0.3e6, 0.1e6, 5e6}));  // in the law's order
  CHECK_NEAR(m.lame_mu(), 2 * (0.3e6 + 0.1e6), 1e-6);                 // mu = 2 (C10 + C01)
  CHECK_NEAR(m.lame_lambda() + 2 * m.lame_mu() / 3, 5e6, 1e-6);       // bulk = lambda + 2 mu / 3
  CHECK(m.density == 1100.0);
  m.validate();
  auto make = [](std::vector<std::pair<std::string, double>> named) {
    return [named] { material_of_law("mooney_rivlin", named, 1000.0); };
  };
  CHECK(message_has(make({{"C10", -1.0}, {"C01", 0.0}, {"bulk", 1e6}}), "C10"));
  CHECK(message_has(make({{"C10", 1.0}, {"C01", -1.0}, {"bulk", 1e6}}), "C01"));
  CHECK(message_has(make({{"C10", 1.0}, {"C01", 0.0}, {"bulk", std::nan("")}}), "bulk"));
  CHECK(message_has(make({{"C10", 1.0}, {"bulk", 1e6}}), "C01"));                              // missing
  CHECK(message_has(make({{"C10", 1.0}, {"C01", 0.0}, {"bulk", 1e6}, {"E", 1.0}}), "no parameter 'E'"));
  CHECK(message_has(make({{"C10", 1.0}, {"C01", 0.0}, {"bulk", 1e9}}), "small-strain"));  // bulk/mu > 1e6
  CHECK(message_has([] { material_of_law("stvk", {}, 1000.0); }, "no law 'stvk' with parameters"));
  Material edited = m;
  edited.youngs_modulus *= 2;  // no longer the law's small-strain modulus
  CHECK(message_has([&] { edited.validate(); }, "small-strain moduli"));
}

TEST(region_materials_name_a_cell_without_a_material) {
  const Material a{1e6, 0.3, 1000.0}, b{2e6, 0.2, 500.0};
  RegionMaterials({a, b}, {0, 1, 1}).validate(3);
  RegionMaterials(a).validate(3);
  CHECK(message_has([&] { RegionMaterials({a, b}, {0, 2, 1}).validate(3); }, "cell 1 has region id 2"));
  CHECK(message_has([&] { RegionMaterials({a, b}, {0, -1, 1}).validate(3); }, "cell 1 has region id -1"));
  CHECK(message_has([&] { RegionMaterials({a, b}, {0, 1}).validate(3); }, "one region id per cell"));
  CHECK(message_has([&] { RegionMaterials({a, Material{1e6, 0.5, 1.0}}, {0, 1, 1}).validate(3); }, "region 1"));
  CHECK(RegionMaterials({a, b}, {1, 0, 1}).of_cells({2, 1}).cell_regions == std::vector<int>({1, 0}));
}
