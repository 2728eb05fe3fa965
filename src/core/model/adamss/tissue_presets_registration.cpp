// Registers the two Adamss tissues of "Adamss: Advanced Anisotropic Mass-Spring System" as tissue
// presets (registry.h, TissuePreset), each more than one force model:
//   adamss_hunter   the Hunter law of Table 2.1 (Eq. 2.153) through the virtual hexahedron
//                   (Sec. 2.4.2), plus the volume term p (det F - 1)^2 (Eq. 2.86);
//   adamss_springs  the cubic axial springs and the torsion springs of Table 2.2 (area form,
//                   kPa; torsion in the gradient form on the angle, which has a stiffness, so
//                   implicit integrators take it), plus the same volume term.
// Scaled to the material's Young's modulus E and Poisson ratio nu: the stiffnesses by
// E / 10 kPa (Table 2.1 has a small-strain fibre modulus 2 k11 a11^-b11 = 11.6 kPa) and the
// volume term gets p = K / 2 = E / (6 (1 - 2 nu)), the bulk modulus of the small-strain energy
// p (J - 1)^2. The laws alone have a Poisson ratio of 0 (each term of Table 2.1 is in one strain
// component, each spring along one axis), so at nu = 0 the volume term is left out.
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using Models = std::vector<std::unique_ptr<ForceModel>>;

struct AdamssScaling {
  double stiffness = 1.0;  // factor on Table 2.1's k and Table 2.2's coefficients
  double volume = 0.0;     // p of the volume term, Pa (0: none)
};

// The scaling for the material of `context` (see the top of the file).
AdamssScaling adamssScaling(const std::string& preset, const ModelContext& context) {
  const IsotropicModuli m = context.tissueModuli(preset);
  if (!(m.young > 0.0) || !(m.poisson >= 0.0 && m.poisson < 0.5))
    throw std::invalid_argument("preset '" + preset +
                                "' expects a Young's modulus > 0 and a Poisson ratio in [0, 0.5), "
                                "got " + std::to_string(m.young) + " and " +
                                std::to_string(m.poisson));
  const double volume = m.poisson == 0.0 ? 0.0 : m.young / (6.0 * (1.0 - 2.0 * m.poisson));
  return {m.young / 10e3, volume};
}

template <class Law>
std::unique_ptr<ForceModel> virtualHexahedron(const Mesh& mesh, const typename Law::Constants& k) {
  return std::make_unique<adamss::VirtualHexahedronModel<Law>>(
      mesh, std::vector<typename Law::Constants>{k}, LawOptions{},
      adamss::DeformationGradientSource::kShapeFunctions);
}

// A registered force model from its scene entry written as a YAML flow map.
std::unique_ptr<ForceModel> adamssModel(const std::string& entry, const ModelContext& context) {
  static const std::string origin = "Adamss tissue preset";
  return registry().makeForceModel(YamlEntry(YAML::Load(entry), "", &origin),
                                   ModelContext{context.mesh, context.materials, {}});
}

// "[[a, b, c], ...]" with every coefficient times `scale`.
std::string scaledCoefficients(const double (&k)[3][3], double scale) {
  std::string text = "[";
  char item[64];
  for (int row = 0; row < 3; ++row) {
    std::snprintf(item, sizeof item, "%s[%.9g, %.9g, %.9g]", row ? ", " : "", scale * k[row][0],
                  scale * k[row][1], scale * k[row][2]);
    text += item;
  }
  return text + "]";
}

void addVolumeTerm(Models& models, const Mesh& mesh, double p) {
  if (p == 0.0) return;
  VolumeLaw::Constants k;
  k.stiffness = p;
  models.push_back(virtualHexahedron<VolumeLaw>(mesh, k));
}

Models adamssHunter(const ModelContext& context) {
  const AdamssScaling scaling = adamssScaling("adamss_hunter", context);
  HunterConstants k = HunterConstants::table21();
  for (double& v : k.k) v *= scaling.stiffness;
  Models models;
  models.push_back(virtualHexahedron<HunterLaw>(context.mesh, k));
  addVolumeTerm(models, context.mesh, scaling.volume);
  return models;
}

Models adamssSprings(const ModelContext& context) {
  const AdamssScaling scaling = adamssScaling("adamss_springs", context);
  // Table 2.2 (kPa): axial k_l1, k_l2, k_l3 per axis; torsion per axis pair.
  static const double axial[3][3] = {{6.358, 0, 768}, {0, 0, 288.525}, {0.305, 0, 5.699}};
  static const double torsion[3][3] = {{3.355, 0, 97.374}, {97.374, 0, 3.355}, {45.896, 0, 2.261}};
  Models models;
  models.push_back(adamssModel("{type: adamss_axial_springs, area: true, stress_unit: kPa, "
                               "stiffness: " + scaledCoefficients(axial, scaling.stiffness) + "}",
                               context));
  models.push_back(adamssModel("{type: adamss_torsion_springs, form: gradient, measure: angle, "
                               "area: true, stress_unit: kPa, stiffness: " +
                                   scaledCoefficients(torsion, scaling.stiffness) + "}",
                               context));
  addVolumeTerm(models, context.mesh, scaling.volume);
  return models;
}

}  // namespace

void registerAdamssTissuePresets(Registry& registry) {
  registry.add(TissuePreset{
      "adamss_hunter",
      "Adamss Table 2.1's Hunter law through the virtual hexahedron plus the volume term, scaled "
      "to the material's E and nu (no volume term at nu = 0)",
      adamssHunter});
  registry.add(TissuePreset{
      "adamss_springs",
      "Adamss Table 2.2's axial and torsion springs (gradient form) plus the volume term, scaled "
      "to the material's E and nu (no volume term at nu = 0)",
      adamssSprings});
}

}  // namespace tt
