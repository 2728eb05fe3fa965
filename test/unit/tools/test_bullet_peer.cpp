// bench_bullet_peer (Bullet's deformable bodies beside our models) runs the static cantilever
// with --quick and writes bullet_peer.csv with the columns of work_precision.csv, Bullet's rows
// for both of its models and the rows of our pair. Files, columns and sanity only, never
// timings. Only where the build passes the executable's path in.
#if defined(TT_BENCH_BULLET_PEER_PATH)
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

TEST(BulletPeer, QuickStaticRunWritesBulletRowsBesideOurPair) {
  const fs::path dir = fs::temp_directory_path() / "tt_bullet_peer_quick";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command = std::string(TT_BENCH_BULLET_PEER_PATH) +
                              " --quick --problems cantilever_static --out " + dir.string();
  ASSERT_EQ(test::exitCodeOf(command, dir / "run.log"), 0);

  const std::vector<std::vector<std::string>> rows = test::readCsv(dir / "bullet_peer.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], test::splitCsv(
            "problem,model,integrator,parameter,error,cpu_seconds,wall_seconds,steps,"
            "rejected_steps,newton_iterations,linear_iterations,stable,parameter_name,"
            "discrete_error,tets,note"));
  const size_t columns = rows[0].size();
  std::set<std::string> stableBullet;
  bool pair = false;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string>& row = rows[i];
    ASSERT_EQ(row.size(), columns) << "row " << i;
    EXPECT_EQ(row[0], "cantilever_static");
    EXPECT_GE(std::stod(row[5]), 0.0);
    if (row[2] == "backward_euler") pair = true;
    if (row[2] == "bullet_backward_euler" && row[12] == "h" && row[11] == "1") {
      const double error = std::stod(row[4]), discrete = std::stod(row[13]);
      EXPECT_TRUE(std::isfinite(error)) << "row " << i;
      // The damped beam bends: against our own static solution of the mesh within 10 %.
      EXPECT_LT(discrete, 0.1) << "row " << i;
      stableBullet.insert(row[1]);
    }
  }
  EXPECT_TRUE(pair);
  EXPECT_EQ(stableBullet, (std::set<std::string>{"bullet_linear_elasticity", "bullet_neohookean"}));
}

}  // namespace
}  // namespace tt
#endif
