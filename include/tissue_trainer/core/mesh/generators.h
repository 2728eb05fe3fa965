#pragma once
// Mesh generators: structured box grids split into tets ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.3.1.3), a cantilever beam, a fusiform (spindle) muscle like the
// demo of Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation",
// Sec. 3, all positively oriented with the surface extracted and defaults filled.
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

enum class TetSplit {
  kFive,          // 5 tets per hex, same orientation in every cell (faces do NOT conform)
  kFiveMirrored,  // 5 tets per hex, mirrored 2x2x2 kernel (conforming faces)
  kSix,           // 6 tets per hex around the main diagonal, same in every cell (conforming)
  kSixMirrored,   // 6 tets per hex, mirrored 2x2x2 kernel (conforming)
  kNone,          // no split: the hexes are the elements
};

// A grid of nodesX x nodesY x nodesZ nodes spanning [0,size.x] x [0,size.y] x [0,size.z],
// node (i,j,k) at index i + nodesX * (j + nodesY * k), with (nodesX-1)(nodesY-1)(nodesZ-1)
// cells. Each cell is split into tets (the tets of cell h are tets[h * perHex .. h * perHex +
// perHex - 1], perHex = 5 or 6), or with TetSplit::kNone kept as one hex (VTK node order,
// Mesh::hexes). A mesh holds one or the other, never both: both would be simulated.
Mesh boxGrid(int nodesX, int nodesY, int nodesZ, const Eigen::Vector3d& size, TetSplit split);

// A beam along +x of length L and square section w x w centred on the x axis
// (y, z in [-w/2, w/2]); the nodes of the end x = 0 are tagged kFixedAll.
Mesh cantileverBeam(double length, double width, int cellsAlong, int cellsAcross,
                    TetSplit split = TetSplit::kSixMirrored);

// A fusiform muscle along +z, z in [0, length], with radius
//   r(z) = tendonRadius + (maxRadius - tendonRadius) * sin(pi z / length)^2,
// so the belly is maxRadius at mid-length and it tapers smoothly (r' = 0) into tendon ends of
// radius tendonRadius. Built from `layers` cross-sections, each an axis node plus a ring of
// `segments` nodes (the same angles on every layer); each wedge between two layers is split
// into 3 tets with the lowest-index diagonal rule, so neighbouring wedges share faces.
// Nodes: layers * (segments + 1); tets: 3 * segments * (layers - 1).
// The defaults give 861 nodes and 2400 tets (Jeffrey's muscle demo has 861 and 2552).
// Fibre frame per tet: column 0 is the unit tangent of the scaled meridian through the tet
// centroid (the fibres follow the spindle shape), column 2 the circumferential direction,
// column 1 = column 2 x column 0. The nodes of both tendon end layers are tagged kFixedAll.
struct SpindleShape {
  double length = 0.1;
  double maxRadius = 0.015;
  double tendonRadius = 0.003;
  int segments = 20;
  int layers = 41;
};

// r(z) of the shape above.
double spindleRadius(const SpindleShape& shape, double z);

Mesh spindleMuscle(const SpindleShape& shape);
Mesh spindleMuscle(double length = 0.1, double maxRadius = 0.015);

// The truncated ellipsoid of the left ventricle of Land et al., "Verification of cardiac
// mechanics software: benchmark problems and solutions for testing active and passive material
// behaviour" (2015), Sec. 2c(ii), in the prolate-spheroidal parametrisation the paper gives:
//   x = r_s(t) sin u cos v,  y = r_s(t) sin u sin v,  z = r_l(t) cos u,
// r_s and r_l linear in the transmural coordinate t in [0, 1] from the endocardium (t = 0) to
// the epicardium (t = 1), v in [0, 2 pi), u from the apex u = -pi to the base
// u = -arccos(baseZ / r_l(t)), so every layer ends on the plane z = baseZ. Nodes: the apex of
// each layer (indices 0 .. transmural: layer k's apex is node k), then the rings
// (transmural + 1) * meridional * circumferential, ring i (1 .. meridional) of layer k at
// index (transmural + 1) + (k * meridional + i - 1) * circumferential + j.
// split kNone: hexes (VTK order), those at the apex with their apex face collapsed onto the
// apex nodes (a wedge; its Gauss points lie inside, where the map is regular); kSix: each cell
// split into the six tets of boxGrid around its diagonal, the apex cells' flat tets dropped
// (three remain, conforming with their neighbours). The base nodes (z = baseZ) are tagged
// kFixedAll. Fibre frames are the identity.
struct EllipsoidShape {
  double endoShort = 0.007, endoLong = 0.017;  // r_s, r_l at t = 0 (m)
  double epiShort = 0.010, epiLong = 0.020;    // at t = 1
  double baseZ = 0.005;
  int transmural = 2;        // cells through the wall
  int meridional = 8;        // cells from apex to base
  int circumferential = 16;  // cells around

  // The radii of the spheroid of transmural coordinate t (linear from endocardium to epicardium).
  double shortRadiusAt(double t) const { return endoShort + t * (epiShort - endoShort); }
  double longRadiusAt(double t) const { return endoLong + t * (epiLong - endoLong); }
};

Mesh truncatedEllipsoid(const EllipsoidShape& shape, TetSplit split = TetSplit::kNone);
// The index of the node of layer k (0 .. transmural), ring i (0 = the apex .. meridional),
// column j (0 .. circumferential - 1; any j at the apex).
int ellipsoidNode(const EllipsoidShape& shape, int k, int i, int j);

}  // namespace tt
