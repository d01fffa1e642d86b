#include <gtest/gtest.h>

#include "velum/material/plane_stress.hpp"

TEST(Smoke, IsotropicLaw) {
  const auto law = velum::PlaneStressLaw::isotropic("iso", 1.0, 0.3);
  EXPECT_NEAR(law.Q()(0, 0), 1.0 / (1 - 0.09), 1e-12);
}
