// The discussion's statements ("Adamss: Advanced Anisotropic Mass-Spring System", Secs.
// 2.9.1-2.9.3), its resolution claim (Sec. 2.1.4) and the slope of Fig. 2.29 (Sec. 2.8.3), from
// bench_adamss oscillation, locking, resolution and scaling in their --quick form. Values and
// verdicts only, never timings: the slope of Fig. 2.29 is checked on the counts that do not
// depend on the machine (matrix and factor nonzeros, PCG iterations, their product).
#if defined(TT_BENCH_ADAMSS_PATH)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "../csv_test_util.h"
#include "program_test_util.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

fs::path discussionDir() { return fs::temp_directory_path() / "tt_bench_adamss_discussion"; }

// Runs `bench_adamss ARGUMENTS --quick --no-plot` into discussionDir(); the exit code.
int runDiscussionExperiment(const std::string& arguments) {
  fs::create_directories(discussionDir());
  return test::exitCodeOf(std::string(TT_BENCH_ADAMSS_PATH) + " " + arguments +
                              " --quick --no-plot --out " + discussionDir().string(),
                          discussionDir() / "log.txt");
}

using test::namedRows;
using test::number;

// Sec. 2.9.3: with the explicit methods the volume oscillates; backward Euler at the same step
// (5e-5 s) "removed the unwanted oscillation of the volume". Measured as the fast part of dV/V0
// (about a 2 ms running mean) over the second half of a 20 ms run: 3.2e-6 (symplectic Euler,
// ABM3) against 5.7e-7 (backward Euler), a factor 5.6; asserted: more than 3. The forward
// Euler method diverges (no damping).
TEST(BenchAdamssDiscussion, BackwardEulerRemovesTheVolumeOscillationOfTheExplicitMethods) {
  ASSERT_EQ(runDiscussionExperiment("oscillation"), 0);
  std::map<std::string, std::map<std::string, std::string>> byIntegrator;
  for (const auto& r : namedRows(discussionDir() / "oscillation_summary.csv"))
    byIntegrator[r.at("integrator")] = r;
  ASSERT_EQ(byIntegrator.size(), 4u);
  EXPECT_EQ(byIntegrator.at("explicit_euler").at("ok"), "0");  // unstable without damping
  const auto& implicit = byIntegrator.at("backward_euler");
  ASSERT_EQ(implicit.at("ok"), "1") << implicit.at("failure");
  for (const char* name : {"symplectic_euler", "abm3"}) {
    const auto& r = byIntegrator.at(name);
    ASSERT_EQ(r.at("ok"), "1") << name << ": " << r.at("failure");
    EXPECT_GT(number(r, "fast_rms"), 3.0 * number(implicit, "fast_rms")) << name;
    EXPECT_GT(number(r, "fast_rms"), 1e-7) << name;  // an oscillation, not round-off
  }
}

// Secs. 2.9.1-2.9.2: locking grows with p. The tet cantilever's deflection falls as p grows,
// and faster than the stiffening a beam that does not lock would show (the locking factor,
// deflection x E(p) / E relative to p = 0, falls too and ends well below 1).
TEST(BenchAdamssDiscussion, TetLockingGrowsWithTheVolumeParameter) {
  ASSERT_EQ(runDiscussionExperiment("locking"), 0);
  const auto rows = namedRows(discussionDir() / "locking.csv");
  ASSERT_GE(rows.size(), 4u);
  for (size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(rows[i].at("failure").empty()) << rows[i].at("failure");
    EXPECT_GT(number(rows[i], "tip_deflection_m"), 0.0);
    if (i == 0) continue;
    EXPECT_LT(number(rows[i], "tip_deflection_m"), number(rows[i - 1], "tip_deflection_m")) << i;
    EXPECT_LT(number(rows[i], "locking_factor"), number(rows[i - 1], "locking_factor")) << i;
  }
  EXPECT_LT(number(rows.back(), "locking_factor"), 0.3);
}

// Sec. 2.1.4: the spring cantilever under the same load at three resolutions: the tip
// deflection converges (each refinement changes it by less than the one before).
TEST(BenchAdamssDiscussion, TheSpringCantileverConvergesWithTheResolution) {
  ASSERT_EQ(runDiscussionExperiment("resolution"), 0);
  const auto rows = namedRows(discussionDir() / "resolution.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& r : rows) ASSERT_TRUE(r.at("failure").empty()) << r.at("failure");
  const double d1 = number(rows[1], "change_from_previous_m"),
               d2 = number(rows[2], "change_from_previous_m");
  EXPECT_LT(std::abs(d2), 0.7 * std::abs(d1));
  EXPECT_GT(number(rows[2], "tip_deflection_m"), 0.0);
}

// Fig. 2.29 shows the time of 1000 implicit steps growing linearly with the number of
// elements (slope 1 of time against elements on a log-log plot), which Sec. 2.8.3 puts down to
// sparse solvers whose work per step is O(n). The counts that do not depend on the machine, on
// the hanging cuboids of 54 to 432 hexahedra: the step matrix's nonzeros grow with slope 1
// (within 0.1, the figure's linear regression) and the Cholesky-preconditioned PCG needs
// nearly as many iterations at every size (slope below 0.3); but the factor fills in, so the
// work of a step's iterations grows with slope 1.4, not 1 (1.2 .. 1.6 asserted): the linear
// relation of Fig. 2.29 does not hold for this solver's work.
TEST(BenchAdamssDiscussion, TheStepMatrixGrowsLinearlyAsFig229ShowsItsFactorDoesNot) {
  ASSERT_EQ(runDiscussionExperiment("scaling --preconditioners cholesky --sizes 3,4,5,6 --steps 20"), 0);
  const auto fits = namedRows(discussionDir() / "scaling_fits.csv");
  ASSERT_EQ(fits.size(), 1u);
  EXPECT_NEAR(number(fits[0], "slope_matrix_nonzeros"), 1.0, 0.1);
  EXPECT_LT(std::abs(number(fits[0], "slope_iterations")), 0.3);
  EXPECT_GT(number(fits[0], "slope_work"), 1.2);
  EXPECT_LT(number(fits[0], "slope_work"), 1.6);
}

}  // namespace
}  // namespace tt
#endif
