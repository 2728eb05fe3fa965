// bench_frame_overhead --quick runs and writes a row per mesh size with the columns the docs
// quote, and a verdict; bad input is one error line. Files, columns and verdicts only: whether
// the verdict says linear depends on the machine's load, so it is not asserted here.
#ifdef TT_BENCH_FRAME_OVERHEAD_PATH
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../csv_test_util.h"
#include "program_test_util.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

fs::path frameOverheadDir() { return fs::temp_directory_path() / "tt_frame_overhead_test"; }

// Runs the benchmark with `arguments`, its output in frameOverheadDir()/log; the exit code.
int runFrameOverhead(const std::string& arguments, const std::string& log) {
  return test::exitCodeOf(std::string(TT_BENCH_FRAME_OVERHEAD_PATH) + " " + arguments,
                          frameOverheadDir() / log);
}

std::vector<std::string> lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(FrameOverheadBench, QuickRunWritesARowPerSizeAndAVerdict) {
  fs::remove_all(frameOverheadDir());
  fs::create_directories(frameOverheadDir());
  const fs::path csv = frameOverheadDir() / "frame_overhead.csv";
  const int exit = runFrameOverhead("--quick --csv " + csv.string(), "quick.log");
  // 0: linear; 1: not linear (a verdict on this machine's timing, not a crash).
  ASSERT_TRUE(exit == 0 || exit == 1) << "exit " << exit;
  const auto rows = test::readCsv(csv);
  ASSERT_EQ(rows.size(), 4u);  // header and 596, ~5,000 and ~10,000 tets
  const std::vector<std::string> header = {
      "tets", "nodes", "surface_vertices", "frames", "failed_steps", "step_ms", "step_p90_ms",
      "status_ms", "guard_ms", "surface_ms", "marker_ms", "snapshot_ms", "overhead_ms",
      "overhead_share", "overhead_ns_per_tet"};
  EXPECT_EQ(rows[0], header);
  EXPECT_EQ(rows[1][0], "596");
  for (size_t r = 1; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].size(), header.size()) << "row " << r;
    EXPECT_EQ(rows[r][4], "0") << "failed steps in row " << r;
    for (size_t c = 5; c < header.size(); ++c) EXPECT_GT(std::stod(rows[r][c]), 0.0) << header[c];
    if (r > 1) EXPECT_GT(std::stoi(rows[r][0]), std::stoi(rows[r - 1][0]));
  }
  bool verdict = false;
  for (const std::string& line : lines(frameOverheadDir() / "quick.log"))
    verdict = verdict || line.rfind("verdict: linear", 0) == 0 || line.find("NOT LINEAR") != std::string::npos;
  EXPECT_TRUE(verdict);
}

TEST(FrameOverheadBench, BadInputIsOneErrorLine) {
  fs::create_directories(frameOverheadDir());
  for (const std::string& arguments : {"--sizes 600,abc", "--frames 0", "--sizes 600", "--fast"}) {
    EXPECT_EQ(runFrameOverhead(arguments, "bad.log"), 2) << arguments;
    const auto out = lines(frameOverheadDir() / "bad.log");
    ASSERT_EQ(out.size(), 1u) << arguments;
    EXPECT_NE(out[0].find("expect"), std::string::npos) << out[0];
  }
}

}  // namespace
}  // namespace tt
#endif
