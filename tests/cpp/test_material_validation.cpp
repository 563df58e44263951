// Material::validate: parameters outside the physical range are InvalidInput.
#include <cmath>
#include <limits>
#include <string>

#include "corotate/material.hpp"
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
