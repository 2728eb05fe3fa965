#pragma once
// The two Adamss tissue models of "Adamss: Advanced Anisotropic Mass-Spring System" that
// bench_work_precision and bench_stability_sweep run beside the registry's presets. Each is
// more than one force model, so it has no preset:
//   adamss_hunter   the Hunter law of Table 2.1 (Eq. 2.153) through the virtual hexahedron
//                   (Sec. 2.4.2), plus, when asked, the volume term p (det F - 1)^2 (Eq. 2.86);
//   adamss_springs  the cubic axial springs and the torsion springs of Table 2.2 (area form,
//                   kPa; torsion in the gradient form on the angle, which has a stiffness, so
//                   implicit integrators take it), plus the same volume term when asked.
// For a sweep over Young's modulus and Poisson's ratio the stiffnesses are scaled by
// E / 10 kPa (Table 2.1 has a small-strain fibre modulus 2 k11 a11^-b11 = 11.6 kPa) and the
// volume term gets p = K / 2 = E / (6 (1 - 2 nu)), the bulk modulus of the small-strain
// energy p (J - 1)^2.
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/registry/yaml_reader.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace adamss_bench {

inline const std::vector<std::string>& modelNames() {
  static const std::vector<std::string> names = {"adamss_hunter", "adamss_springs"};
  return names;
}

inline bool isAdamssModel(const std::string& name) {
  for (const std::string& n : modelNames())
    if (n == name) return true;
  return false;
}

struct Scaling {
  double stiffness = 1.0;  // factor on Table 2.1's k and Table 2.2's coefficients
  double volume = 0.0;     // p of the volume term, Pa (0: none)
};

// The scaling for Young's modulus E and Poisson's ratio nu (see the top of the file).
inline Scaling scalingFor(double young, double poisson) {
  return {young / 10e3, young / (6.0 * (1.0 - 2.0 * poisson))};
}

template <class Law>
std::unique_ptr<ForceModel> virtualHexahedron(const Mesh& mesh, const typename Law::Constants& k) {
  return std::make_unique<adamss::VirtualHexahedronModel<Law>>(
      mesh, std::vector<typename Law::Constants>{k}, LawOptions{},
      adamss::DeformationGradientSource::kShapeFunctions);
}

// A registered force model from its scene entry written as a YAML flow map.
inline std::unique_ptr<ForceModel> registeredModel(const std::string& entry, const System& s) {
  static const std::string origin = "Adamss benchmark model";
  return registry().makeForceModel(YamlEntry(YAML::Load(entry), "", &origin),
                                   ModelContext{s.mesh, s.materials, {}});
}

// "[[a, b, c], ...]" with every coefficient times `scale`.
inline std::string scaledCoefficients(const double (&k)[3][3], double scale) {
  std::string text = "[";
  char item[64];
  for (int row = 0; row < 3; ++row) {
    std::snprintf(item, sizeof item, "%s[%.9g, %.9g, %.9g]", row ? ", " : "", scale * k[row][0],
                  scale * k[row][1], scale * k[row][2]);
    text += item;
  }
  return text + "]";
}

// Adds the models of `name` (one of modelNames()) to the system.
inline void addModel(System& s, const std::string& name, const Scaling& scaling = {}) {
  if (name == "adamss_hunter") {
    HunterConstants k = HunterConstants::table21();
    for (double& v : k.k) v *= scaling.stiffness;
    s.models.push_back(virtualHexahedron<HunterLaw>(s.mesh, k));
  } else {
    // Table 2.2 (kPa): axial k_l1, k_l2, k_l3 per axis; torsion per axis pair.
    static const double axial[3][3] = {{6.358, 0, 768}, {0, 0, 288.525}, {0.305, 0, 5.699}};
    static const double torsion[3][3] = {
        {3.355, 0, 97.374}, {97.374, 0, 3.355}, {45.896, 0, 2.261}};
    s.models.push_back(registeredModel(
        "{type: adamss_axial_springs, area: true, stress_unit: kPa, stiffness: " +
            scaledCoefficients(axial, scaling.stiffness) + "}",
        s));
    s.models.push_back(registeredModel(
        "{type: adamss_torsion_springs, form: gradient, measure: angle, area: true, "
        "stress_unit: kPa, stiffness: " +
            scaledCoefficients(torsion, scaling.stiffness) + "}",
        s));
  }
  if (scaling.volume > 0.0) {
    VolumeLaw::Constants k;
    k.stiffness = scaling.volume;
    s.models.push_back(virtualHexahedron<VolumeLaw>(s.mesh, k));
  }
}

}  // namespace adamss_bench
}  // namespace tt
