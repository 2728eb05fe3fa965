#pragma once
// Mesh generators: structured box grids split into tets (seed 001 section 2.3.1.3), a
// cantilever beam, a fusiform (spindle) muscle like seed 000's demo, all positively oriented
// with the surface extracted.
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

enum class TetSplit {
  kFive,          // 5 tets per hex, same orientation in every cell
  kFiveMirrored,  // 5 tets per hex, mirrored 2x2x2 kernel (conforming faces)
  kSix,           // 6 tets per hex around the main diagonal, same in every cell
  kSixMirrored,   // 6 tets per hex, mirrored 2x2x2 kernel
};

// A grid of nodesX x nodesY x nodesZ nodes spanning [0,size.x] x [0,size.y] x [0,size.z],
// with (nodesX-1)(nodesY-1)(nodesZ-1) hexes, each split into tets. Hexes are kept too.
Mesh boxGrid(int nodesX, int nodesY, int nodesZ, const Eigen::Vector3d& size, TetSplit split);

// A beam along +x of length L and square section w x w, fixed end at x = 0 tagged kFixedAll.
Mesh cantileverBeam(double length, double width, int cellsAlong, int cellsAcross,
                    TetSplit split = TetSplit::kSixMirrored);

// A spindle along +z: radius(z) = maxRadius * sin(pi z / length)^p with round tendons; rings of
// nodes; fibres along the spindle axis (a0 follows the local meridian). Defaults give about
// 861 nodes and 2552 tets, like seed 000's muscle demo.
Mesh spindleMuscle(double length = 0.1, double maxRadius = 0.015);

}  // namespace tt
