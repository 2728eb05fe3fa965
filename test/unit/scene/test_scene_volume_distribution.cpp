// The scene key `distribution` of the virtual hexahedron with the volume law ("Adamss:
// Advanced Anisotropic Mass-Spring System", Sec. 2.4.2.3): a block compressed to 0.9 in every
// direction and left free under mass damping. With a shear-resisting law beside the volume
// term it returns to its rest volume with the point forces along the axes and with their equal
// shares to the face nodes. With the volume term alone only `axes` does: the moments of the
// equal shares drive the shear modes the volume term does not resist until a tet inverts.
// The factor is rebuilt on the stepping thread: with the default background rebuild, when a
// new factor takes over depends on the machine's timing, and so does the collapse (the frame
// it fails in and which of the guard's checks sees it first).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "scene_test_util.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {
namespace {

const char* const kCompressed = R"(name: squeezed
mesh: {generator: box, nodes: [3, 3, 3], size: [0.02, 0.02, 0.02], split: five}
materials: [{young_modulus: 1000, poisson_ratio: 0.3, volume_stiffness: 2000, density: 1000}]
fibres: {angles_deg: [21.25, 49.6]}
force_models: [{type: virtual_hexahedron, law: volume DISTRIBUTION}, SHEAR]
integrator: {type: backward_euler, background_refactor: false}
loads: {rayleigh_mass: 20}
run: {frame_time: 0.01, duration: 1.0}
)";

// `shear`: a neo-Hookean model beside the volume term, or none.
Scene compressed(const std::string& distribution, bool shear) {
  const std::string text = testutil::replaced(
      testutil::replaced(kCompressed, " DISTRIBUTION", distribution),
      ", SHEAR", shear ? ", {type: hyperelastic, law: neo_hookean}" : "");
  Scene scene = loadScene(testutil::writeScene("squeezed.yaml", text));
  Eigen::VectorXd& x = scene.system.state.x;
  const Eigen::Vector3d centre(0.01, 0.01, 0.01);
  for (Eigen::Index i = 0; i < x.size() / 3; ++i)
    x.segment<3>(3 * i) = centre + 0.9 * (x.segment<3>(3 * i) - centre);
  return scene;
}

using VolumeVH = adamss::VirtualHexahedronModel<VolumeLaw>;

TEST(VolumeDistributionScene, BothDistributionsRestoreTheVolume) {
  for (const std::string distribution : {"", ", distribution: axes", ", distribution: vertices"}) {
    SCOPED_TRACE(distribution);
    Scene scene = compressed(distribution, true);
    const auto& model = dynamic_cast<const VolumeVH&>(*scene.system.models.at(0));
    const bool vertices = distribution.find("vertices") != std::string::npos;
    EXPECT_EQ(model.distribution(), vertices ? adamss::PointForceDistribution::kVertices
                                             : adamss::PointForceDistribution::kAxes);
    EXPECT_EQ(model.hasEnergy(), !vertices);
    EXPECT_NEAR(measureFrame(scene.system, 0, {}).volumeRatio, 0.729, 1e-12);
    const RunSummary run = runScene(scene, {});
    ASSERT_TRUE(run.ok) << run.failure;
    EXPECT_NEAR(run.last.volumeRatio, 1.0, 1e-9);
    EXPECT_LT(run.last.kineticEnergy, 1e-15);
    std::printf("[ measured ] %s: volume ratio - 1 = %.3g after %.2f s, kinetic energy %.3g J\n",
                vertices ? "vertices" : "axes", run.last.volumeRatio - 1.0, run.simulatedTime,
                run.last.kineticEnergy);
  }
}

TEST(VolumeDistributionScene, AloneTheVolumeTermKeepsTheMeshOnlyAlongTheAxes) {
  Scene axes = compressed(", distribution: axes", false);
  const RunSummary kept = runScene(axes, {});
  ASSERT_TRUE(kept.ok) << kept.failure;
  EXPECT_NEAR(kept.last.volumeRatio, 1.0, 1e-3);
  Scene vertices = compressed(", distribution: vertices", false);
  const RunSummary lost = runScene(vertices, {});
  EXPECT_FALSE(lost.ok);
  EXPECT_NE(lost.failure.find("inverted or flat"), std::string::npos) << lost.failure;
  std::printf("[ measured ] vertices alone: %s\n", lost.failure.c_str());
}

}  // namespace
}  // namespace tt
