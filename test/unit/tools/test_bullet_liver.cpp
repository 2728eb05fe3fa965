// bench_bullet_liver (Bullet's deformable solver beside ours on the pressed liver) runs on
// the scene's own 596-tet liver for 3 steps and writes bullet_liver.csv: every run of both
// simulators, finite numbers, each run close to its own model's reference. Files, columns and
// sanity only, never timings. Only where the build passes the executable's path in.
#if defined(TT_BENCH_BULLET_LIVER_PATH)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "../csv_test_util.h"
#include "program_test_util.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

TEST(BulletLiver, SmallLiverRunWritesFiniteRowsForBothSimulators) {
  const fs::path dir = fs::temp_directory_path() / "tt_bullet_liver_smoke";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command = std::string(TT_BENCH_BULLET_LIVER_PATH) +
                              " --tetgen none --steps 3 --out " + dir.string() + " --work " +
                              (dir / "work").string();
  ASSERT_EQ(test::exitCodeOf(command, dir / "run.log"), 0);

  const std::vector<std::vector<std::string>> rows = test::readCsv(dir / "bullet_liver.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], test::splitCsv(
            "tets,nodes,steps,h,simulator,model,setting,reference,step_ms_p50,step_ms_p99,"
            "step_ms_max,newton_per_step,linear_per_step,max_displacement_m,error,"
            "difference_to_edge_length,difference_to_neo_hookean,failure"));
  std::set<std::string> models;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string>& row = rows[i];
    ASSERT_EQ(row.size(), rows[0].size()) << "row " << i;
    EXPECT_EQ(row[0], "596");
    EXPECT_EQ(row[17], "") << "row " << i << " failed";
    for (int column : {8, 9, 12, 13, 15, 16})
      EXPECT_TRUE(std::isfinite(std::stod(row[column]))) << "row " << i << ", column " << column;
    EXPECT_GT(std::stod(row[13]), 1e-4) << "row " << i << ": the pressed liver moves";
    if (row[7] == "0") EXPECT_LT(std::stod(row[14]), 0.1) << "row " << i << " against its reference";
    models.insert(row[4] + " " + row[5]);
  }
  EXPECT_EQ(models, (std::set<std::string>{"ours edge_length", "ours hyperelastic_neo_hookean",
                                           "bullet bullet_linear_elasticity",
                                           "bullet bullet_neohookean"}));
}

}  // namespace
}  // namespace tt
#endif
