// The benchmark report's pipeline (scripts/bench): bench_work_precision and bench_scaling
// run with --quick and write CSV files with the columns the plot script reads. Files and
// columns only, never timings. Only where the build passes the executables' paths in.
// The output goes to TT_BENCH_TEST_OUT when set (scripts/test then draws the report from it).
#if defined(TT_BENCH_WORK_PRECISION_PATH) && defined(TT_BENCH_SCALING_PATH)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "csv_test_util.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

fs::path outputDir() {
  const char* dir = std::getenv("TT_BENCH_TEST_OUT");
  return dir && *dir ? fs::path(dir) : fs::temp_directory_path() / "tt_bench_quick";
}

using test::readCsv;
using test::splitCsv;

// Runs command with its output in outputDir()/log.
int run(const std::string& command, const std::string& log) {
  const int status = std::system((command + " > " + (outputDir() / log).string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class BenchPipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(outputDir());
    fs::create_directories(outputDir());
    workPrecisionExit = run(std::string(TT_BENCH_WORK_PRECISION_PATH) + " --quick --out " +
                            outputDir().string(), "work_precision.log");
    scalingExit = run(std::string(TT_BENCH_SCALING_PATH) + " --quick --out " +
                      outputDir().string(), "scaling.log");
  }
  static int workPrecisionExit, scalingExit;
};

int BenchPipeline::workPrecisionExit = -1;
int BenchPipeline::scalingExit = -1;

TEST_F(BenchPipeline, WorkPrecisionCsvHasTheColumnsAndEveryProblem) {
  ASSERT_EQ(workPrecisionExit, 0);
  const auto rows = readCsv(outputDir() / "work_precision.csv");
  ASSERT_GT(rows.size(), 1u);
  const std::vector<std::string> leading = {
      "problem", "model", "integrator", "parameter", "error", "cpu_seconds", "wall_seconds",
      "steps", "rejected_steps", "newton_iterations", "linear_iterations", "stable"};
  ASSERT_GE(rows[0].size(), leading.size());
  EXPECT_EQ(std::vector<std::string>(rows[0].begin(), rows[0].begin() + leading.size()), leading);
  std::set<std::string> problems, integrators, stableProblems;
  for (size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), rows[0].size()) << "row " << i;
    problems.insert(rows[i][0]);
    integrators.insert(rows[i][2]);
    const std::string& stable = rows[i][11];
    EXPECT_TRUE(stable == "0" || stable == "1") << "row " << i;
    if (stable == "1" && std::isfinite(std::stod(rows[i][4]))) stableProblems.insert(rows[i][0]);
    EXPECT_GE(std::stod(rows[i][5]), 0.0) << "row " << i;
  }
  const std::set<std::string> expected = {"cantilever_static", "cantilever_vibration",
                                          "beam_large_deflection", "spindle_pull", "patch",
                                          "cantilever_static_mesh"};
  EXPECT_EQ(problems, expected);
  EXPECT_EQ(stableProblems, expected);  // every problem has a run with a finite error
  for (const char* name : {"explicit_euler", "symplectic_euler", "newtonian", "backward_euler",
                           "backward_euler_newton", "radau_iia"})
    EXPECT_TRUE(integrators.count(name)) << name;
}

TEST_F(BenchPipeline, FactsCsvNamesTheAnalyticValues) {
  ASSERT_EQ(workPrecisionExit, 0);
  const auto rows = readCsv(outputDir() / "work_precision_facts.csv");
  ASSERT_GT(rows.size(), 1u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"problem", "quantity", "value", "unit", "meaning"}));
  std::set<std::string> quantities;
  for (size_t i = 1; i < rows.size(); ++i) quantities.insert(rows[i][0] + "/" + rows[i][1]);
  EXPECT_TRUE(quantities.count("cantilever_static/tip_deflection_euler_bernoulli"));
  EXPECT_TRUE(quantities.count("cantilever_vibration/frequency_euler_bernoulli"));
  EXPECT_TRUE(quantities.count("spindle_pull/reference_accuracy"));
}

TEST_F(BenchPipeline, ScalingCsvAndFits) {
  ASSERT_EQ(scalingExit, 0);
  const auto rows = readCsv(outputDir() / "scaling.csv");
  ASSERT_GT(rows.size(), 1u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"quantity", "model", "tets", "nodes",
                                               "wall_seconds", "cpu_seconds", "repeats",
                                               "linear_iterations"}));
  std::set<std::string> quantities;
  for (size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), rows[0].size());
    quantities.insert(rows[i][0]);
    EXPECT_GT(std::stod(rows[i][4]), 0.0);
  }
  EXPECT_EQ(quantities, (std::set<std::string>{"force_evaluation", "explicit_step", "implicit_step"}));
  const auto fits = readCsv(outputDir() / "scaling_fits.csv");
  ASSERT_GT(fits.size(), 1u);
  EXPECT_EQ(fits[0], (std::vector<std::string>{"quantity", "model", "slope", "log_intercept"}));
  for (size_t i = 1; i < fits.size(); ++i) EXPECT_TRUE(std::isfinite(std::stod(fits[i][2])));
}

}  // namespace
}  // namespace tt
#endif
