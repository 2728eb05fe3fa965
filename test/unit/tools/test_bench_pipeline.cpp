// The benchmark report's pipeline (scripts/bench): bench_work_precision, bench_scaling and
// bench_stability_sweep run with --quick and write CSV files with the columns the report
// scripts read. Files, columns and verdicts only, never timings. Only where the build passes the executables' paths in.
// The output goes to TT_BENCH_TEST_OUT when set (scripts/test then draws the report from it).
#if defined(TT_BENCH_WORK_PRECISION_PATH) && defined(TT_BENCH_SCALING_PATH) && \
    defined(TT_BENCH_STABILITY_SWEEP_PATH)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "../csv_test_util.h"
#include "program_test_util.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

fs::path pipelineOutputDir() {
  const char* dir = std::getenv("TT_BENCH_TEST_OUT");
  return dir && *dir ? fs::path(dir) : fs::temp_directory_path() / "tt_bench_quick";
}

using test::readCsv;
using test::splitCsv;

// Runs command with its output in pipelineOutputDir()/log.
int run(const std::string& command, const std::string& log) {
  return test::exitCodeOf(command, pipelineOutputDir() / log);
}

class BenchPipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(pipelineOutputDir());
    fs::create_directories(pipelineOutputDir());
    workPrecisionExit = run(std::string(TT_BENCH_WORK_PRECISION_PATH) + " --quick --out " +
                            pipelineOutputDir().string(), "work_precision.log");
    scalingExit = run(std::string(TT_BENCH_SCALING_PATH) + " --quick --out " +
                      pipelineOutputDir().string(), "scaling.log");
    sweepExit = run(std::string(TT_BENCH_STABILITY_SWEEP_PATH) + " --quick --out " +
                    pipelineOutputDir().string(), "stability_sweep.log");
  }
  static int workPrecisionExit, scalingExit, sweepExit;
};

int BenchPipeline::workPrecisionExit = -1;
int BenchPipeline::scalingExit = -1;
int BenchPipeline::sweepExit = -1;

TEST_F(BenchPipeline, WorkPrecisionCsvHasTheColumnsAndEveryProblem) {
  ASSERT_EQ(workPrecisionExit, 0);
  const auto rows = readCsv(pipelineOutputDir() / "work_precision.csv");
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
                                          "uniaxial_stretch", "muscle_contraction",
                                          "cantilever_static_mesh"};
  EXPECT_EQ(problems, expected);
  EXPECT_EQ(stableProblems, expected);  // every problem has a run with a finite error
  for (const char* name : {"explicit_euler", "symplectic_euler", "newtonian", "backward_euler",
                           "backward_euler_newton", "radau_iia", "abm3", "rk4_adaptive",
                           "backward_euler_adaptive", "quasistatic", "quasistatic_cholesky"})
    EXPECT_TRUE(integrators.count(name)) << name;
}

TEST_F(BenchPipeline, FactsCsvNamesTheAnalyticValues) {
  ASSERT_EQ(workPrecisionExit, 0);
  const auto rows = readCsv(pipelineOutputDir() / "work_precision_facts.csv");
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
  const auto rows = readCsv(pipelineOutputDir() / "scaling.csv");
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
  const auto fits = readCsv(pipelineOutputDir() / "scaling_fits.csv");
  ASSERT_GT(fits.size(), 1u);
  EXPECT_EQ(fits[0], (std::vector<std::string>{"quantity", "model", "slope", "log_intercept"}));
  for (size_t i = 1; i < fits.size(); ++i) EXPECT_TRUE(std::isfinite(std::stod(fits[i][2])));
}

// Rows of a CSV file as column name -> text (test::namedRows), the header checked against
// `columns` and every row's length against the header's.
std::vector<std::map<std::string, std::string>> namedRows(const fs::path& path,
                                                          const std::vector<std::string>& columns) {
  const auto rows = readCsv(path);
  EXPECT_GT(rows.size(), 1u) << path;
  if (rows.empty()) return {};
  EXPECT_EQ(rows[0], columns) << path;
  for (size_t i = 1; i < rows.size(); ++i)
    EXPECT_EQ(rows[i].size(), columns.size()) << path << " row " << i;
  return test::namedRows(path);
}

const std::set<std::string> kOutcomes = {"stable", "recovered", "failed"};

// The quick grid: its verdicts must tell a step far beyond the explicit limit from one far
// below it (E = 100 MPa, nu = 0.3: h_c = L/c = 1.8e-5 s on this block).
TEST_F(BenchPipeline, StabilitySweepGridSeparatesStableFromUnstable) {
  ASSERT_EQ(sweepExit, 0);
  const auto rows = namedRows(
      pipelineOutputDir() / "stability_sweep.csv",
      {"integrator", "model", "young", "poisson", "step", "outcome", "energy_growth",
       "inverted_max", "guard_recoveries", "guard_halvings", "guard_failures", "wall_seconds",
       "guarded_wall_seconds", "failure"});
  int checked = 0;
  std::set<std::string> integrators;
  for (const auto& r : rows) {
    ASSERT_TRUE(kOutcomes.count(r.at("outcome"))) << r.at("outcome");
    integrators.insert(r.at("integrator"));
    const double young = std::stod(r.at("young")), step = std::stod(r.at("step"));
    const bool bareFailed = r.at("outcome") != "stable";
    EXPECT_EQ(bareFailed, !r.at("failure").empty()) << "a failed bare run names its failure";
    if (r.at("integrator") == "symplectic_euler" && young == 1e8 && step == 1e-2) {
      EXPECT_TRUE(bareFailed) << r.at("model") << ": 500x the explicit limit cannot be stable";
      ++checked;
    }
    if (r.at("integrator") == "backward_euler" && young == 1e4 && step == 1e-4) {
      EXPECT_EQ(r.at("outcome"), "stable") << r.at("model") << " " << r.at("failure");
      ++checked;
    }
    // The iteration-controlled implicit step holds where the explicit one cannot.
    if (r.at("integrator") == "backward_euler_adaptive" && young == 1e8 && step == 1e-2) {
      EXPECT_EQ(r.at("outcome"), "stable") << r.at("model") << " " << r.at("failure");
      ++checked;
    }
    if (r.at("outcome") == "recovered") EXPECT_GT(std::stol(r.at("guard_halvings")), 0);
  }
  EXPECT_GE(checked, 12);  // 2 models x 2 Poisson ratios x the 3 cells above
  for (const char* name : {"backward_euler_adaptive", "abm3", "rk4_adaptive"})
    EXPECT_TRUE(integrators.count(name)) << name << ": the adaptive steppers are in the grid";
}

TEST_F(BenchPipeline, StabilitySweepCriticalStepAndExtremeCases) {
  ASSERT_EQ(sweepExit, 0);
  const auto critical = namedRows(
      pipelineOutputDir() / "critical_step.csv",
      {"model", "young", "poisson", "shortest_edge", "wave_speed", "predicted_hc",
       "two_over_omega_max", "limit_symplectic_euler", "limit_newtonian"});
  for (const auto& r : critical) {
    const double predicted = std::stod(r.at("predicted_hc"));
    const double measured = std::stod(r.at("limit_symplectic_euler"));
    EXPECT_GT(predicted, 0.0);
    // A CFL-type estimate is right to within an order of magnitude, not exactly.
    EXPECT_GT(measured, 0.1 * predicted) << r.at("young");
    EXPECT_LT(measured, 10.0 * predicted) << r.at("young");
  }
  const auto extremes = namedRows(
      pipelineOutputDir() / "extreme_cases.csv",
      {"case", "integrator", "model", "step", "outcome", "energy_growth", "inverted_max",
       "guard_recoveries", "guard_halvings", "guard_failures", "wall_seconds", "failure"});
  std::set<std::string> cases, quasistaticCases;
  for (const auto& r : extremes) {
    EXPECT_TRUE(kOutcomes.count(r.at("outcome"))) << r.at("case");
    cases.insert(r.at("case"));
    if (r.at("integrator") == "quasistatic") {
      EXPECT_EQ(r.at("model"), "teran_muscle_inversion") << "the muscle tissue alone";
      quasistaticCases.insert(r.at("case"));
    }
  }
  // The quasistatic solver runs every case but the impact, which is all inertia.
  EXPECT_EQ(quasistaticCases, (std::set<std::string>{"compression_80pct", "forced_inversion",
                                                      "twist_180deg", "sliver_elements"}));
  EXPECT_EQ(cases, (std::set<std::string>{"compression_80pct", "forced_inversion", "twist_180deg",
                                          "impact_20m_per_s", "sliver_elements"}));
}

// A misspelt name or option, a bad count or the old positional form is one error line naming
// it and exit 2, not a run that silently leaves the name out.
TEST(BenchCommandLine, UnknownNamesAndBadValuesAreOneErrorLine) {
  fs::create_directories(pipelineOutputDir());
  const std::string out = " --out " + (pipelineOutputDir() / "bad_input").string();
  const std::string workPrecision = TT_BENCH_WORK_PRECISION_PATH, scaling = TT_BENCH_SCALING_PATH,
                    sweep = TT_BENCH_STABILITY_SWEEP_PATH;
  // command, what its error line must name
  std::vector<std::pair<std::string, std::string>> cases = {
      {workPrecision + " --models edge_lenght" + out, "'edge_lenght'"},
      {workPrecision + " --problems patch,cantilever" + out, "'cantilever'"},
      {workPrecision + " --time-limit 0" + out, "'0'"},
      {workPrecision + " --fast" + out, "'--fast'"},
      {scaling + " --repeats 0" + out, "'0'"},
      {scaling + " --quick 3" + out, "'3'"},
      {scaling + " --out", "--out"},
      {sweep + " --integrators rk4" + out, "'rk4'"},
      {sweep + " --models tensormass" + out, "'tensormass'"},
      {sweep + " --cases twist_180deg" + out, "--cases"},
      {sweep + " --grid-only --extremes-only" + out, "--grid-only"}};
#ifdef TT_BENCH_BULLET_PEER_PATH
  cases.push_back({std::string(TT_BENCH_BULLET_PEER_PATH) + " --problems patch" + out, "'patch'"});
  cases.push_back({std::string(TT_BENCH_BULLET_PEER_PATH) + " --bullet-newton 2.5" + out, "'2.5'"});
#endif
#ifdef TT_BENCH_BULLET_LIVER_PATH
  cases.push_back({std::string(TT_BENCH_BULLET_LIVER_PATH) + " --steps 2.5" + out, "'2.5'"});
  cases.push_back({std::string(TT_BENCH_BULLET_LIVER_PATH) + " --tetgen 'q1.4 a0.1'" + out, "'q1.4 a0.1'"});
#endif
  // The build puts every benchmark in one folder.
  const fs::path folder = fs::path(scaling).parent_path();
  const std::string quasistatic = (folder / "bench_quasistatic").string();
  cases.push_back({quasistatic + " --cases tongue,lips" + out, "'lips'"});
  cases.push_back({quasistatic + " --threads 0" + out, "'0'"});
  const std::string clock = (folder / "bench_real_time_clock").string();
  cases.push_back({clock + " - 0.1 0.1 clock.csv 5.5", "'-'"});  // the old positional form
  cases.push_back({clock + " --seconds -1", "'-1'"});
  cases.push_back({clock + " --max-frame-time", "--max-frame-time"});
#ifdef TT_BENCH_ADAMSS_PATH
  const std::string adamss = TT_BENCH_ADAMSS_PATH;
  cases.push_back({adamss + " volume --steps 3" + out, "'--steps'"});
  cases.push_back({adamss + " stretch --quick 3" + out, "'3'"});
  cases.push_back({adamss + " scaling --sizes 3,x" + out, "'x'"});
  cases.push_back({adamss + " strech" + out, "'strech'"});
  cases.push_back({adamss, "experiment"});
#endif
  for (const auto& [command, named] : cases) {
    EXPECT_EQ(run(command, "bad_input.log"), 2) << command;
    std::ifstream log(pipelineOutputDir() / "bad_input.log");
    std::vector<std::string> lines;
    for (std::string line; std::getline(log, line);) lines.push_back(line);
    ASSERT_EQ(lines.size(), 1u) << command;
    EXPECT_NE(lines[0].find(named), std::string::npos) << lines[0];
    EXPECT_NE(lines[0].find("expect"), std::string::npos) << lines[0];
  }
}

}  // namespace
}  // namespace tt
#endif
