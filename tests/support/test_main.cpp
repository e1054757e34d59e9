// The main() of every test executable: GoogleTest's, after the BLAS kernel check the cutwork
// executable makes (solvers/linear/thread_policy.h ensure_blas_kernels): the tests run in the
// configuration the program runs in.
#include <gtest/gtest.h>

#include "solvers/linear/thread_policy.h"

int main(int argc, char** argv) {
  cutwork::solvers::ensure_blas_kernels(argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
