// The tissue presets (registry.h, TissuePreset): each makes the forces the benchmarks' own
// construction of the tissue made before it became a preset (rebuilt here from the model
// classes), names are unique across both kinds of preset, and an unknown name lists them all.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../model_test_util.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"
#include "tissue_trainer/core/model/muscle_groups.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using Models = std::vector<std::unique_ptr<ForceModel>>;

// A jittered 2 x 2 x 2 cm block of one material, random fibres.
Mesh tissueTestMesh() {
  std::mt19937 rng(7);
  Mesh mesh = testutil::boxMesh(2, 2, 2, 0.01, rng);
  mesh.material.assign(mesh.numTets(), 0);
  return mesh;
}

Eigen::VectorXd summedForce(const Models& models, const Eigen::VectorXd& x) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  for (const auto& m : models) m->addForce(x, Eigen::VectorXd::Zero(x.size()), f);
  return f;
}

// --- the tissues as the benchmarks built them before the presets -----------------------------

template <class Law>
std::unique_ptr<ForceModel> oldVirtualHexahedron(const Mesh& mesh,
                                                 const typename Law::Constants& k) {
  return std::make_unique<adamss::VirtualHexahedronModel<Law>>(
      mesh, std::vector<typename Law::Constants>{k}, LawOptions{},
      adamss::DeformationGradientSource::kShapeFunctions);
}

std::string oldScaledCoefficients(const double (&k)[3][3], double scale) {
  std::string text = "[";
  char item[64];
  for (int row = 0; row < 3; ++row) {
    std::snprintf(item, sizeof item, "%s[%.9g, %.9g, %.9g]", row ? ", " : "", scale * k[row][0],
                  scale * k[row][1], scale * k[row][2]);
    text += item;
  }
  return text + "]";
}

std::unique_ptr<ForceModel> oldRegisteredModel(const std::string& entry, const Mesh& mesh,
                                               const std::vector<Material>& materials) {
  static const std::string origin = "old benchmark model";
  return registry().makeForceModel(YamlEntry(YAML::Load(entry), "", &origin),
                                   ModelContext{mesh, materials, {}});
}

// adamss_hunter or adamss_springs with stiffness x E / 10 kPa and, when `volume`, the volume
// term p = E / (6 (1 - 2 nu)).
Models oldAdamss(const std::string& name, const Mesh& mesh, const std::vector<Material>& materials,
                 double young, double poisson, bool volume) {
  const double scale = young / 10e3;
  Models models;
  if (name == "adamss_hunter") {
    HunterConstants k = HunterConstants::table21();
    for (double& v : k.k) v *= scale;
    models.push_back(oldVirtualHexahedron<HunterLaw>(mesh, k));
  } else {
    static const double axial[3][3] = {{6.358, 0, 768}, {0, 0, 288.525}, {0.305, 0, 5.699}};
    static const double torsion[3][3] = {
        {3.355, 0, 97.374}, {97.374, 0, 3.355}, {45.896, 0, 2.261}};
    models.push_back(oldRegisteredModel(
        "{type: adamss_axial_springs, area: true, stress_unit: kPa, stiffness: " +
            oldScaledCoefficients(axial, scale) + "}",
        mesh, materials));
    models.push_back(oldRegisteredModel(
        "{type: adamss_torsion_springs, form: gradient, measure: angle, area: true, "
        "stress_unit: kPa, stiffness: " + oldScaledCoefficients(torsion, scale) + "}",
        mesh, materials));
  }
  if (volume) {
    VolumeLaw::Constants k;
    k.stiffness = young / (6.0 * (1.0 - 2.0 * poisson));
    models.push_back(oldVirtualHexahedron<VolumeLaw>(mesh, k));
  }
  return models;
}

// The muscle tissue: one muscle over every tet at activation 0.5.
Models oldMuscle(const std::string& name, const Mesh& mesh, double young, double poisson) {
  const double mu = young / (2.0 * (1.0 + poisson));
  TeranMuscleLaw::Constants k;
  k.A = 0.375 * mu;
  k.B = 0.125 * mu;
  k.K = young / (3.0 * (1.0 - 2.0 * poisson));
  k.sigmaMax = mu;
  LawOptions o;
  if (name != "teran_muscle") o.inversionThreshold = 0.25;
  o.psdProjection = name == "teran_muscle_inversion_psd";
  MuscleGroup block;
  block.name = "block";
  block.activation = 0.5;
  for (int e = 0; e < mesh.numTets(); ++e) block.elements.push_back(e);
  Models models;
  models.push_back(std::make_unique<MuscleGroupsModel>(
      mesh, std::vector<TeranMuscleLaw::Constants>{k}, std::vector<MuscleGroup>{block}, o));
  return models;
}

void expectSameForces(const std::string& preset, const Models& expected, const Mesh& mesh,
                      const std::vector<Material>& materials) {
  SCOPED_TRACE(preset);
  const Models made = makePresetModels(preset, mesh, materials);
  ASSERT_EQ(made.size(), expected.size());
  for (std::size_t m = 0; m < made.size(); ++m)
    EXPECT_STREQ(made[m]->name(), expected[m]->name());
  std::mt19937 rng(11);
  const Eigen::VectorXd x = testutil::perturbed(mesh, 2e-4, rng);
  const Eigen::VectorXd f = summedForce(expected, x);
  EXPECT_GT(f.norm(), 0.0);
  EXPECT_LT(testutil::relDiff(summedForce(made, x), f), 1e-13);
  // The stiffness too (the PSD projection changes it alone).
  for (std::size_t m = 0; m < made.size(); ++m) {
    ASSERT_EQ(made[m]->hasStiffness(), expected[m]->hasStiffness());
    if (!made[m]->hasStiffness()) continue;
    const Eigen::MatrixXd K = testutil::denseStiffness(*expected[m], mesh, x);
    EXPECT_LT(testutil::relDiff(testutil::denseStiffness(*made[m], mesh, x), K), 1e-13) << m;
  }
}

TEST(TissuePresets, AdamssPresetsMakeTheBenchmarksForcesWithTheVolumeTerm) {
  const Mesh mesh = tissueTestMesh();
  for (const auto& [young, poisson] : {std::pair{1e3, 0.3}, std::pair{1e6, 0.4999}}) {
    const std::vector<Material> materials{Material::isotropic(young, poisson, 1000.0)};
    for (const std::string name : {"adamss_hunter", "adamss_springs"})
      expectSameForces(name, oldAdamss(name, mesh, materials, young, poisson, true), mesh,
                       materials);
  }
}

// At nu = 0 (and E = 10 kPa: Tables 2.1 and 2.2 unscaled) the laws alone, as bench_work_precision
// and bench_adamss ran them.
TEST(TissuePresets, AdamssPresetsAtPoissonZeroHaveNoVolumeTerm) {
  const Mesh mesh = tissueTestMesh();
  const std::vector<Material> materials{Material::isotropic(10e3, 0.0, 1000.0)};
  for (const std::string name : {"adamss_hunter", "adamss_springs"})
    expectSameForces(name, oldAdamss(name, mesh, materials, 10e3, 0.0, false), mesh, materials);
}

TEST(TissuePresets, MusclePresetsMakeTheBenchmarksForces) {
  const Mesh mesh = tissueTestMesh();
  const std::vector<Material> materials{Material::isotropic(30e3, 0.45, 1060.0)};
  for (const std::string name :
       {"teran_muscle", "teran_muscle_inversion", "teran_muscle_inversion_psd"}) {
    expectSameForces(name, oldMuscle(name, mesh, 30e3, 0.45), mesh, materials);
  }
}

// A model's preset is a list of one: the model makePreset makes.
TEST(TissuePresets, AModelPresetIsAListOfOne) {
  const Mesh mesh = tissueTestMesh();
  const std::vector<Material> materials{Material::isotropic(3e3, 0.3, 1000.0)};
  const Models made = makePresetModels("edge_length", mesh, materials);
  ASSERT_EQ(made.size(), 1u);
  std::mt19937 rng(3);
  const Eigen::VectorXd x = testutil::perturbed(mesh, 1e-3, rng);
  EXPECT_EQ(summedForce(made, x), testutil::force(*makeElasticModel("edge_length", mesh, materials), x));
}

TEST(TissuePresets, TheTissuePresetsAreListedAfterTheModelPresets) {
  const std::vector<std::string> all = registry().presetNames();
  std::vector<std::string> expected = registry().modelPresetNames();
  for (const std::string name : {"adamss_hunter", "adamss_springs", "teran_muscle",
                                 "teran_muscle_inversion", "teran_muscle_inversion_psd"})
    expected.push_back(name);
  EXPECT_EQ(all, expected);
}

TissuePreset dummyTissue(const std::string& name) {
  return {name, "", [](const ModelContext&) { return Models{}; }};
}

TEST(TissuePresets, ARepeatedPresetNameIsRefused) {
  Registry r;
  ForceModelEntry spring;
  spring.name = "spring";
  spring.presets = {{"soft_spring", "", ""}};
  spring.make = [](const YamlEntry&, const ModelContext&) -> std::unique_ptr<ForceModel> {
    return nullptr;
  };
  r.add(spring);
  r.add(dummyTissue("tissue"));
  EXPECT_THROW(r.add(dummyTissue("tissue")), std::logic_error);
  EXPECT_THROW(r.add(dummyTissue("soft_spring")), std::logic_error) << "a model's preset name";
  EXPECT_THROW(r.add(dummyTissue("")), std::logic_error);
  EXPECT_THROW(r.add(TissuePreset{"no_factory", "", nullptr}), std::logic_error);
  ForceModelEntry later = spring;
  later.name = "later";
  later.presets = {{"tissue", "", ""}};
  EXPECT_THROW(r.add(later), std::logic_error) << "a tissue preset's name";
  EXPECT_EQ(r.presetNames(), (std::vector<std::string>{"soft_spring", "tissue"}));
}

TEST(TissuePresets, AnUnknownNameListsEveryPreset) {
  const Mesh mesh = tissueTestMesh();
  const std::vector<Material> materials{Material::isotropic(3e3, 0.3, 1000.0)};
  try {
    makePresetModels("adamss_hunterr", mesh, materials);
    FAIL() << "no error for an unknown preset";
  } catch (const UnknownNameError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("unknown force model 'adamss_hunterr'"), std::string::npos) << message;
    for (const std::string& p : registry().presetNames())
      EXPECT_NE(message.find(p), std::string::npos) << p << ": " << message;
  }
  // makePreset makes one model: a tissue's name says why it is not one of its names.
  try {
    makeElasticModel("adamss_hunter", mesh, materials);
    FAIL() << "no error for a tissue preset";
  } catch (const UnknownNameError& e) {
    EXPECT_NE(std::string(e.what()).find("'adamss_hunter' is a tissue of several force models"),
              std::string::npos) << e.what();
  }
}

TEST(TissuePresets, AMaterialWithoutYoungsModulusOrABadPoissonRatioIsRefused) {
  const Mesh mesh = tissueTestMesh();
  ElasticConstants k;
  k.lambda = k.lambdaL = 2000.0;
  k.mu = k.muL = 1000.0;
  const std::vector<Material> lame{Material::withConstants(k, 1000.0)};
  const std::vector<Material> two(2, Material::isotropic(3e3, 0.3, 1000.0));
  const std::vector<Material> negative{Material::isotropic(3e3, -0.2, 1000.0)};
  for (const std::string name : {"adamss_hunter", "adamss_springs", "teran_muscle"}) {
    for (const auto* materials : {&lame, &two}) {
      try {
        makePresetModels(name, mesh, *materials);
        ADD_FAILURE() << name << ": no error";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("preset '" + name + "' expects one material with a "
                                             "Young's modulus and a Poisson ratio"),
                  std::string::npos) << e.what();
      }
    }
  }
  for (const std::string name : {"adamss_hunter", "adamss_springs"})
    EXPECT_THROW(makePresetModels(name, mesh, negative), std::invalid_argument) << name;
}

}  // namespace
}  // namespace tt
