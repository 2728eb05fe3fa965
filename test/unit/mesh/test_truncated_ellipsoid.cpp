// The truncated ellipsoid of the cardiac mechanics benchmark (mesh/generators.h): positive
// elements, the apex and base where the paper puts them, a closed boundary, the tet split
// conforming (its boundary encloses exactly the tets' volume), and the wall volume converging
// to that of the two half-spheroids cut at z = 5 mm.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tissue_trainer/core/element/hex8.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/quality.h"
#include "tissue_trainer/core/model/adamss/cavity.h"

namespace tt {
namespace {

constexpr double kEllipsoidPi = 3.14159265358979323846;

// Volume of the spheroid x^2/a^2 + y^2/a^2 + z^2/c^2 <= 1 below z = h.
double spheroidCapVolume(double a, double c, double h) {
  return kEllipsoidPi * a * a * ((h + c) - (h * h * h + c * c * c) / (3.0 * c * c));
}

double wallVolume(const EllipsoidShape& s) {
  return spheroidCapVolume(s.epiShort, s.epiLong, s.baseZ) -
         spheroidCapVolume(s.endoShort, s.endoLong, s.baseZ);
}

double meshVolume(const Mesh& m) {
  double v = 0.0;
  for (const Tet& t : m.tets) v += tetVolume(m.rest, t);
  for (const Hex& h : m.hexes) v += hexVolume(m.rest, h);
  return v;
}

std::vector<adamss::CavityFacet> facetsOf(const Mesh& m) {
  std::vector<adamss::CavityFacet> f;
  for (const Triangle& t : m.surface) f.push_back({t[0], t[1], t[2]});
  return f;
}

TEST(TruncatedEllipsoid, ApexBaseAndPositiveElements) {
  EllipsoidShape s;
  for (TetSplit split : {TetSplit::kNone, TetSplit::kSix}) {
    const Mesh m = truncatedEllipsoid(s, split);
    EXPECT_NEAR(m.rest(2, ellipsoidNode(s, 0, 0, 0)), -0.017, 1e-15);
    EXPECT_NEAR(m.rest(2, ellipsoidNode(s, s.transmural, 0, 0)), -0.020, 1e-15);
    int fixed = 0;
    for (int n = 0; n < m.numNodes(); ++n) {
      const bool onBase = std::abs(m.rest(2, n) - s.baseZ) < 1e-12;
      EXPECT_EQ(onBase, m.nodeTags[n] == kFixedAll) << n;
      fixed += onBase;
    }
    EXPECT_EQ(fixed, (s.transmural + 1) * s.circumferential);
    for (const Tet& t : m.tets) EXPECT_GT(tetVolume(m.rest, t), 0.0);
    for (const Hex& h : m.hexes)
      for (double w : Hex8::rest(m.rest, h).weight) EXPECT_GT(w, 0.0);
    EXPECT_NO_THROW(adamss::checkClosedSurface(facetsOf(m), m.numNodes()));
  }
}

// The collapsed apex hexes have check tets (the stability guard's, the equilibrium recovery's)
// with four coplanar corners: counted flat at rest, a jitter of a nanometre does not make
// them inverted elements.
TEST(TruncatedEllipsoid, CollapsedApexHexesAreNotCorruptUnderRoundOff) {
  const Mesh m = truncatedEllipsoid(EllipsoidShape{}, TetSplit::kNone);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-9, 1e-9);
  Eigen::Matrix3Xd x = m.rest;
  for (int i = 0; i < x.size(); ++i) x.data()[i] += u(rng);
  EXPECT_TRUE(corruptElements(m, m.rest, 0.0).empty());
  EXPECT_TRUE(corruptElements(m, x, 0.0).empty());
  // A real inversion of an apex wedge is still seen: the endocardial apex pushed outside.
  x = m.rest;
  x(2, ellipsoidNode(EllipsoidShape{}, 0, 0, 0)) = -0.0205;
  EXPECT_FALSE(corruptElements(m, x, 0.0).empty());
}

TEST(TruncatedEllipsoid, TetSplitConformsAndWallVolumeConverges) {
  double previousError = 1.0, previousHexError = 1.0;
  for (int n : {1, 2, 4}) {
    EllipsoidShape s;
    s.transmural = n, s.meridional = 4 * n, s.circumferential = 8 * n;
    const Mesh tets = truncatedEllipsoid(s, TetSplit::kSix);
    const double v = meshVolume(tets);
    // A conforming split: the extracted boundary encloses exactly the tets.
    EXPECT_NEAR(adamss::enclosedVolume(facetsOf(tets), tets.rest), v, 1e-12 * v) << n;
    const double error = std::abs(v - wallVolume(s)) / wallVolume(s);
    const double hexError =
        std::abs(meshVolume(truncatedEllipsoid(s, TetSplit::kNone)) - wallVolume(s)) / wallVolume(s);
    std::printf("cells %d x %d x %d: tet volume error %.3e, hex %.3e\n", n, 4 * n, 8 * n, error,
                hexError);
    EXPECT_LT(error, 0.4 * previousError) << n;  // second order: about a quarter per halving
    EXPECT_LT(hexError, 0.4 * previousHexError) << n;
    previousError = error;
    previousHexError = hexError;
  }
  EXPECT_LT(previousError, 0.01);
  EXPECT_LT(previousHexError, 0.01);
}

}  // namespace
}  // namespace tt
