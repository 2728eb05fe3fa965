// bench_render [WIDTH HEIGHT [FRAMES]]: time per frame of the renderer node's drawing (the
// liver's render surface, liver-smooth.obj scaled 0.025 as in config/scenes/liver_palpation.yaml,
// 4384 triangles, with its normals recomputed every frame as the node does; the cavity; the
// default instrument with open jaws) and the read-back of the RGB image. Prints the median
// and the quartiles over FRAMES frames (default 200) after 5 warm-up frames.
// Built with -DTT_BENCH_BEFORE it uses only what the renderer had before the laparoscope
// look (fixed-function headlight, no cavity), to measure the same scene on the old code.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "instrument_shapes.h"
#include "offscreen_renderer.h"
#include "tissue_trainer/core/mesh/mesh_io.h"

#ifndef TT_SOURCE_DIR
#define TT_SOURCE_DIR "."
#endif

int main(int argc, char** argv) {
  const int width = argc > 2 ? std::atoi(argv[1]) : 640, height = argc > 2 ? std::atoi(argv[2]) : 480;
  const int frames = argc > 3 ? std::atoi(argv[3]) : 200;
  // TT_BENCH_TEXTURE=0: no procedural texture; TT_BENCH_CAVITY=0: no cavity (to see their cost).
  const bool texture = !std::getenv("TT_BENCH_TEXTURE") || std::atoi(std::getenv("TT_BENCH_TEXTURE"));
  const bool cavity = !std::getenv("TT_BENCH_CAVITY") || std::atoi(std::getenv("TT_BENCH_CAVITY"));
  (void)texture;
  (void)cavity;
  if (width <= 0 || height <= 0 || frames <= 0) {
    std::fprintf(stderr, "usage: bench_render [WIDTH HEIGHT [FRAMES]]\n");
    return 2;
  }
  const tt::SurfaceMesh surface = tt::readObj(std::string(TT_SOURCE_DIR) + "/config/meshes/liver-smooth.obj");
  std::vector<float> positions;
  std::vector<std::uint32_t> triangles;
  for (int i = 0; i < surface.vertices.cols(); ++i)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(0.025 * surface.vertices(k, i)));
  for (const tt::Triangle& t : surface.triangles)
    for (int k = 0; k < 3; ++k) triangles.push_back(static_cast<std::uint32_t>(t[k]));

  tt_render::OffscreenRenderer r(width, height);
  const auto shapes = tt_render::defaultInstrument("instrument_tip", 0.3);
  Eigen::Isometry3d tip = Eigen::Isometry3d::Identity();
  tip.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  tip.translation() = Eigen::Vector3d(-0.035, 0.075, 0.09);
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& s : shapes) {
#ifdef TT_BENCH_BEFORE
    (void)s;
    poses.push_back(tip);
#else
    poses.push_back(tt_render::defaultInstrumentLinkPose(s, tip, 0.8));
#endif
  }
  std::vector<std::uint8_t> rgb;
  std::vector<double> ms;
  for (int f = 0; f < frames + 5; ++f) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<float> normals = tt_render::vertexNormals(positions, triangles);
    r.beginFrame();
#ifndef TT_BENCH_BEFORE
    tt_render::Material tissue = tt_render::wetTissue();
    if (!texture) tissue.texture = 0.0f;
    r.setMaterial(tissue);
#endif
    r.drawMesh(positions, normals, triangles, tt_render::Rgb{0.62f, 0.22f, 0.18f});
#ifndef TT_BENCH_BEFORE
    r.setMaterial(tt_render::steel());
#endif
    tt_render::drawShapes(r, shapes, poses);
#ifndef TT_BENCH_BEFORE
    tt_render::Material wall = tt_render::cavityWall();
    if (!texture) wall.texture = 0.0f;
    r.setMaterial(wall);  // last: the depth test skips what is hidden
    if (cavity)
      r.drawCavity(Eigen::Vector3d(-0.036, 0.06, 0.03), Eigen::Vector3d(0.2, 0.16, 0.25),
                   tt_render::Rgb{0.78f, 0.42f, 0.38f});
#endif
    r.readRgb(rgb);
    const double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (f >= 5) ms.push_back(t);
  }
  std::sort(ms.begin(), ms.end());
  auto quantile = [&](double q) { return ms[static_cast<std::size_t>(q * (ms.size() - 1) + 0.5)]; };
  std::printf("bench_render: %s, %dx%d, %zu triangles, %d frames: median %.2f ms per frame "
              "(quartiles %.2f .. %.2f, max %.2f)\n",
              r.glRenderer().c_str(), width, height, triangles.size() / 3, frames, quantile(0.5),
              quantile(0.25), quantile(0.75), ms.back());
  return 0;
}
