#pragma once
// The spindle-muscle scene shared by bench_muscle_demo and bench_force_threshold (Jeffrey, "A
// non-linear anisotropic Finite Element Method for surgical simulation", Sec. 3): 861 nodes,
// 2400 tets, E_L 150 kPa / nu 0.4 along the fibres, E_T 20 kPa / nu 0.4 across, density 1060,
// tendon end layers fixed, mass-proportional damping 10 / s; the belly node on the +x side is
// pulled 1 cm along +x over 0.1 s and back over 0.1 s.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "tissue_trainer/core/system.h"

namespace tt {
namespace muscle_scene {

constexpr double kPeak = 0.1, kEnd = 0.2;  // s
constexpr double kPull = 0.01;             // m
constexpr double kDampingRate = 10.0;      // 1/s

using ModelMaker =
    std::function<std::unique_ptr<ForceModel>(const Mesh&, const std::vector<Material>&)>;

// The belly node on the +x side at mid-length.
int bellyNode(const Mesh& mesh);

// The scene with the model `make` makes.
std::unique_ptr<System> muscle(const ModelMaker& make);

// Largest omega of M^-1 (-K) at rest on the free DOFs, by power iteration.
double omegaMax(const System& s);

}  // namespace muscle_scene
}  // namespace tt
