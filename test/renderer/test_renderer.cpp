// The OSMesa renderer on known scenes: the SOFA liver surface (liver.msh scaled 0.025, the
// training rig's world coordinates) under the default laparoscope camera, with the default
// instrument in front of it, alone and inside the cavity with the scope light. Checks pixels
// and image statistics and writes the PNGs (look at them).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <cmath>

#include "instrument_shapes.h"
#include "offscreen_renderer.h"
#include "png_writer.h"
#include "tissue_trainer/core/mesh/mesh_io.h"

namespace {

using tt_render::OffscreenRenderer;
using tt_render::Rgb;

struct Pixel {
  int r, g, b;
  int sum() const { return r + g + b; }
};

Pixel at(const std::vector<std::uint8_t>& rgb, int width, double col, double row) {
  const std::size_t i = 3 * (std::size_t(std::lround(row)) * width + std::size_t(std::lround(col)));
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

std::string outPath(const std::string& name) {
  ::mkdir(TT_RENDER_OUT, 0755);
  return std::string(TT_RENDER_OUT) + "/" + name;
}

struct Liver {
  std::vector<float> positions;
  std::vector<std::uint32_t> triangles;
  Eigen::Vector3d min = Eigen::Vector3d::Constant(1e9), max = Eigen::Vector3d::Constant(-1e9);
};

Liver loadLiver() {
  const tt::Mesh mesh = tt::readMesh(std::string(TT_SOURCE_DIR) + "/config/meshes/liver.msh");
  Liver l;
  for (int i = 0; i < mesh.numNodes(); ++i) {
    const Eigen::Vector3d x = 0.025 * mesh.rest.col(i);
    l.min = l.min.cwiseMin(x);
    l.max = l.max.cwiseMax(x);
    for (int k = 0; k < 3; ++k) l.positions.push_back(static_cast<float>(x[k]));
  }
  for (const tt::Triangle& t : mesh.surface)
    for (int k = 0; k < 3; ++k) l.triangles.push_back(static_cast<std::uint32_t>(t[k]));
  return l;
}

TEST(Renderer, VertexNormalsOfATetPointOutward) {
  const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::vector<std::uint32_t> t = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};  // outward
  const std::vector<float> n = tt_render::vertexNormals(p, t);
  ASSERT_EQ(n.size(), p.size());
  const Eigen::Vector3d centre(0.25, 0.25, 0.25);
  for (int v = 0; v < 4; ++v) {
    const Eigen::Vector3d nv(n[3 * v], n[3 * v + 1], n[3 * v + 2]);
    const Eigen::Vector3d pv(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
    EXPECT_NEAR(nv.norm(), 1.0, 1e-6);
    EXPECT_GT(nv.dot(pv - centre), 0.0) << "vertex " << v;
  }
}

TEST(Renderer, ShadedLiverAndInstrument) {
  const Liver liver = loadLiver();
  ASSERT_GT(liver.triangles.size(), 300u);
  // The contract's extent of the scaled liver.
  EXPECT_NEAR(liver.min.x(), -0.117, 0.002);
  EXPECT_NEAR(liver.max.y(), 0.129, 0.002);

  OffscreenRenderer r(640, 480);  // default camera: beside the trocar, at the liver
  const Rgb background{0.08f, 0.05f, 0.05f};
  r.setBackground(background);
  const std::vector<float> normals = tt_render::vertexNormals(liver.positions, liver.triangles);
  // The instrument through the trocar, shaft along world -z, tip 2 cm in front of the liver.
  Eigen::Isometry3d tip = Eigen::Isometry3d::Identity();
  tip.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();  // +z -> -z
  tip.translation() = Eigen::Vector3d(-0.035, 0.075, 0.09);
  const auto shapes = tt_render::defaultInstrument("instrument_tip", 0.3);

  const int frames = 10;  // after one warm-up frame (llvmpipe compiles its shaders)
  std::vector<std::uint8_t> rgb;
  auto start = std::chrono::steady_clock::now();
  for (int f = 0; f <= frames; ++f) {
    if (f == 1) start = std::chrono::steady_clock::now();
    r.beginFrame();
    r.drawMesh(liver.positions, normals, liver.triangles, Rgb{0.62f, 0.22f, 0.18f});
    tt_render::drawShapes(r, shapes, std::vector<Eigen::Isometry3d>(shapes.size(), tip));
    r.readRgb(rgb);
  }
  const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / frames;
  std::printf("[renderer] %s, 640x480, %zu triangles + instrument: %.1f ms per frame\n",
              r.glRenderer().c_str(), liver.triangles.size() / 3, ms);
  tt_render::writePng(outPath("liver_instrument.png"), r.width(), r.height(), rgb);

  // Background where nothing is: the top-left corner.
  const Pixel corner = at(rgb, r.width(), 2, 2);
  EXPECT_NEAR(corner.r, 255 * background.r, 1.5);
  EXPECT_NEAR(corner.g, 255 * background.g, 1.5);

  // Liver pixels: reddish, lit, and shaded (brightness varies over the organ).
  int liverPixels = 0, darkest = 765, brightest = 0;
  for (int row = 0; row < r.height(); ++row)
    for (int col = 0; col < r.width(); ++col) {
      const Pixel p = at(rgb, r.width(), col, row);
      if (p.r > p.g + 30 && p.r > 60) {
        ++liverPixels;
        darkest = std::min(darkest, p.sum());
        brightest = std::max(brightest, p.sum());
      }
    }
  std::printf("[renderer] liver pixels %d (%.0f%% of the image), brightness %d..%d\n", liverPixels,
              100.0 * liverPixels / (r.width() * r.height()), darkest, brightest);
  EXPECT_GT(liverPixels, r.width() * r.height() / 8);
  EXPECT_GT(brightest - darkest, 120) << "no shading";

  // The liver's front centre and the instrument's shaft project where they are drawn.
  double col = 0, row = 0;
  ASSERT_TRUE(r.project(Eigen::Vector3d(-0.036, 0.06, 0.06), col, row));
  const Pixel organ = at(rgb, r.width(), col, row);
  EXPECT_GT(organ.r, organ.g + 30) << "liver expected at (" << col << ", " << row << ")";
  ASSERT_TRUE(r.project(Eigen::Vector3d(-0.035, 0.075, 0.12), col, row));  // on the shaft
  const Pixel shaft = at(rgb, r.width(), col, row);
  EXPECT_LT(std::abs(shaft.r - shaft.b), 40) << "grey instrument expected at (" << col << ", " << row << ")";
  EXPECT_GT(shaft.sum(), 150);
}

// The laparoscope scene as the renderer node draws it: cavity, wet liver, instrument with
// its jaws opened by `jaw` (rad), the tip at `tip`.
struct Scene {
  Liver liver = loadLiver();
  std::vector<float> normals = tt_render::vertexNormals(liver.positions, liver.triangles);
  std::vector<tt_render::Shape> shapes = tt_render::defaultInstrument("instrument_tip", 0.3);
  bool cavity = true, organ = true, instrument = true;
  double jaw = 0.8;
  Eigen::Vector3d tip{-0.035, 0.075, 0.09};

  void draw(OffscreenRenderer& r, std::vector<std::uint8_t>& rgb) const {
    r.beginFrame();
    if (organ) {
      r.setMaterial(tt_render::wetTissue());
      r.drawMesh(liver.positions, normals, liver.triangles, Rgb{0.62f, 0.22f, 0.18f});
    }
    if (instrument) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();  // +z -> -z
      pose.translation() = tip;
      std::vector<Eigen::Isometry3d> poses;
      for (const auto& s : shapes) poses.push_back(tt_render::defaultInstrumentLinkPose(s, pose, jaw));
      r.setMaterial(tt_render::steel());
      tt_render::drawShapes(r, shapes, poses);
    }
    if (cavity) {  // last, as the node draws it
      r.setMaterial(tt_render::cavityWall());
      r.drawCavity(Eigen::Vector3d(-0.036, 0.06, 0.03), Eigen::Vector3d(0.2, 0.16, 0.25), Rgb{0.78f, 0.42f, 0.38f});
    }
    r.readRgb(rgb);
  }
};

double meanBrightness(const std::vector<std::uint8_t>& rgb, const std::vector<bool>& mask) {
  double sum = 0.0;
  long n = 0;
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) {
      sum += rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2];
      ++n;
    }
  return n ? sum / n : 0.0;
}

// Pixels the organ covers: drawn alone in flat, unlit colour on black.
std::vector<bool> organMask(OffscreenRenderer& r, const Scene& scene) {
  Scene alone = scene;
  alone.cavity = alone.instrument = false;
  const tt_render::Lighting saved = r.lighting();
  r.setLighting(tt_render::Lighting{0.0, 1.0, 1.0, 0.0});  // ambient only
  r.setBackground(Rgb{0, 0, 0});
  std::vector<std::uint8_t> rgb;
  alone.draw(r, rgb);
  r.setLighting(saved);
  std::vector<bool> mask(rgb.size() / 3);
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2] > 0;
  return mask;
}

TEST(Renderer, LaparoscopeViewHasHighlightsFallOffAVignetteAndNoVoid) {
  OffscreenRenderer r(640, 480);
  ASSERT_TRUE(r.shaded()) << "no GLSL in " << r.glRenderer();
  const Scene scene;
  const std::vector<bool> organ = organMask(r, scene);
  std::vector<std::uint8_t> rgb;
  r.setBackground(Rgb{0, 0, 0});
  scene.draw(r, rgb);
  tt_render::writePng(outPath("laparoscope_view.png"), r.width(), r.height(), rgb);

  // Wet tissue: near-white highlight pixels on the organ (its own colour never gets the
  // green and blue channels this high).
  long organPixels = 0, highlights = 0, black = 0;
  for (std::size_t i = 0; i < organ.size(); ++i) {
    const int red = rgb[3 * i], green = rgb[3 * i + 1], blue = rgb[3 * i + 2];
    if (red + green + blue < 10) ++black;
    if (!organ[i]) continue;
    ++organPixels;
    if (green > 170 && blue > 160) ++highlights;
  }
  const long pixels = long(organ.size());
  std::printf("[renderer] laparoscope view: organ %.0f%% of the frame, %ld highlight pixels (%.2f%% of the organ), "
              "%.2f%% black\n", 100.0 * organPixels / pixels, highlights, 100.0 * highlights / organPixels,
              100.0 * black / pixels);
  EXPECT_GT(organPixels, pixels / 8);
  EXPECT_GE(highlights, 30);
  EXPECT_LT(highlights, organPixels / 5) << "a highlight, not a washed-out organ";
  EXPECT_LE(black, pixels / 3) << "the organ floats on black";
  EXPECT_EQ(black, 0) << "the cavity fills the frame";

  // Fall-off: the scope twice as far away sees the organ darker; with a range so long that
  // the light does not fall off, about as bright.
  auto organBrightness = [&](double range, double distanceFactor) {
    OffscreenRenderer far(320, 240);
    tt_render::Camera c = far.camera();
    c.position = c.target + distanceFactor * (c.position - c.target);
    c.fovDeg = 2.0 * std::atan(std::tan(0.5 * c.fovDeg * M_PI / 180.0) / distanceFactor) * 180.0 / M_PI;
    far.setCamera(c);  // the same framing from further away
    tt_render::Lighting l;
    l.range = range;
    l.vignette = 0.0;
    far.setLighting(l);
    Scene s = scene;
    s.cavity = s.instrument = false;
    const std::vector<bool> mask = organMask(far, s);
    std::vector<std::uint8_t> image;
    far.setLighting(l);
    s.draw(far, image);
    return meanBrightness(image, mask);
  };
  const double nearLit = organBrightness(0.18, 1.0), farLit = organBrightness(0.18, 2.0);
  const double nearFlat = organBrightness(1e3, 1.0), farFlat = organBrightness(1e3, 2.0);
  std::printf("[renderer] organ brightness near %.0f, twice as far %.0f (no fall-off: %.0f, %.0f)\n", nearLit,
              farLit, nearFlat, farFlat);
  EXPECT_LT(farLit, 0.6 * nearLit);
  EXPECT_NEAR(farFlat, nearFlat, 0.1 * nearFlat);

  // Vignette: the corners of the cavity darker than without it, the centre the same.
  Scene walls = scene;
  walls.organ = walls.instrument = false;
  std::vector<std::uint8_t> with, without;
  walls.draw(r, with);
  tt_render::Lighting plain = r.lighting();
  plain.vignette = 0.0;
  r.setLighting(plain);
  walls.draw(r, without);
  r.setLighting(tt_render::Lighting{});
  const Pixel cornerWith = at(with, r.width(), 3, 3), cornerWithout = at(without, r.width(), 3, 3);
  const Pixel centreWith = at(with, r.width(), 320, 240), centreWithout = at(without, r.width(), 320, 240);
  EXPECT_LT(cornerWith.sum(), 0.6 * cornerWithout.sum());
  EXPECT_NEAR(centreWith.sum(), centreWithout.sum(), 3);
}

TEST(Renderer, JawsOpenAndClose) {
  // The tip close to the scope so the jaws are large in the image.
  OffscreenRenderer r(320, 240);
  Scene scene;
  scene.cavity = scene.organ = false;
  scene.tip = Eigen::Vector3d(-0.01, 0.11, 0.16);
  std::vector<std::uint8_t> closed, open;
  scene.jaw = 0.0;
  scene.draw(r, closed);
  scene.jaw = 1.0;
  scene.draw(r, open);
  tt_render::writePng(outPath("jaws_closed.png"), r.width(), r.height(), closed);
  tt_render::writePng(outPath("jaws_open.png"), r.width(), r.height(), open);
  long changed = 0;
  for (std::size_t i = 0; i < closed.size(); i += 3)
    if (std::abs(closed[i] - open[i]) + std::abs(closed[i + 1] - open[i + 1]) > 30) ++changed;
  std::printf("[renderer] opening the jaws by 1 rad changes %ld pixels\n", changed);
  EXPECT_GT(changed, 150);
  // Both jaws turn by half the angle, in opposite directions about the tip frame's x.
  const auto shapes = tt_render::defaultInstrument("t", 0.3);
  const Eigen::Isometry3d tip = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d upperEnd = tt_render::defaultInstrumentLinkPose(shapes[2], tip, 1.0) * Eigen::Vector3d(0, 0, 0.018);
  const Eigen::Vector3d lowerEnd = tt_render::defaultInstrumentLinkPose(shapes[3], tip, 1.0) * Eigen::Vector3d(0, 0, 0.018);
  EXPECT_NEAR(upperEnd.y(), 0.018 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(lowerEnd.y(), -0.018 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(std::acos(upperEnd.normalized().dot(lowerEnd.normalized())), 1.0, 1e-12);
}

TEST(Renderer, UrdfShapesAreParsed) {
  const std::string urdf = R"(<robot name="t">
    <link name="a"><visual><origin xyz="0 0 0.1" rpy="0 0 0"/><geometry><cylinder radius="0.01" length="0.2"/></geometry></visual></link>
    <link name="b"><collision><geometry><box size="0.01 0.02 0.03"/></geometry></collision></link>
    <link name="c"/>
    <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
    <joint name="k" type="fixed"><parent link="a"/><child link="c"/></joint>
  </robot>)";
  const auto shapes = tt_render::shapesFromUrdf(urdf);
  ASSERT_EQ(shapes.size(), 2u);
  for (const auto& s : shapes) {
    if (s.link == "a") {
      EXPECT_EQ(s.type, tt_render::Shape::kCylinder);
      EXPECT_NEAR(s.origin.translation().z(), 0.1, 1e-12);
      EXPECT_NEAR(s.size.y(), 0.2, 1e-12);
    } else {
      EXPECT_EQ(s.link, "b");
      EXPECT_EQ(s.type, tt_render::Shape::kBox);
      EXPECT_NEAR(s.size.z(), 0.03, 1e-12);
    }
  }
  EXPECT_THROW(tt_render::shapesFromUrdf("<robot"), std::runtime_error);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
