// Registers muscle_groups (model/muscle_groups.h). Its entry:
//   {type: muscle_groups, law: teran_muscle, inversion_threshold, psd_projection,
//    muscles: [{name, region, fibres, activation}, ...]}
// The law's constants come from the `materials` entries (their teran_muscle map); the
// activations only from `muscles`. Beside it, the muscle tissue presets (teran_muscle,
// teran_muscle_inversion, teran_muscle_inversion_psd).
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "../material/teran_muscle_reader.h"
#include "../scene/scene_fibres.h"
#include "tissue_trainer/core/model/law_model_factory.h"
#include "tissue_trainer/core/model/muscle_groups.h"
#include "tissue_trainer/core/registry/selection.h"

namespace tt {
namespace {

// An activation in [0, 1]: a number, or a time curve whose values stay in [0, 1].
void readActivation(const YamlEntry& a, MuscleGroup& group) {
  const auto inRange = [](const YamlEntry& v) {
    const double x = v.number();
    if (!(x >= 0.0 && x <= 1.0))
      v.fail("expected an activation in [0, 1], got '" + v.node().Scalar() + "'");
    return x;
  };
  if (!a.node().IsMap()) {
    group.activation = inRange(a);
    return;
  }
  group.curve = readTimeCurve(a);
  group.followsCurve = true;
  const std::string type = a["type"].text();
  if (type == "constant") inRange(a["value"]);
  if (type == "twitch") inRange(a["peak"]);  // a twitch runs between 0 and its peak
  if (type == "piecewise_linear")
    for (size_t k = 0; k < a["values"].size(); ++k) inRange(a["values"][static_cast<int>(k)]);
  group.activation = std::min(1.0, std::max(0.0, group.curve.value(0.0)));
}

// The activation belongs to the muscles; a material's own would be read by nothing.
void rejectMaterialActivations(const ModelContext& context) {
  for (const YamlEntry& m : context.materialEntries)
    if (m.has("teran_muscle") && m["teran_muscle"].has("activation"))
      m["teran_muscle"]["activation"].fail(
          "muscle_groups takes the activations from its 'muscles' list; remove this key");
}

std::vector<MuscleGroup> readGroups(const YamlEntry& list, Mesh& mesh) {
  if (list.size() == 0) list.fail("expected at least one muscle {name, region, fibres, activation}");
  std::vector<MuscleGroup> groups;
  std::vector<int> owner(mesh.numTets() + mesh.numHexes(), -1);
  for (size_t k = 0; k < list.size(); ++k) {
    const YamlEntry item = list[static_cast<int>(k)];
    item.expectMap({"name", "region", "fibres", "activation"});
    MuscleGroup g;
    g.name = item["name"].text();
    if (g.name.empty()) item["name"].fail("expected a non-empty name");
    for (const MuscleGroup& other : groups)
      if (other.name == g.name)
        item["name"].fail("expected a name not used by another muscle, got '" + g.name + "' twice");
    g.elements = regionElements(item["region"], mesh);
    for (int e : g.elements) {
      if (owner[e] >= 0)
        item["region"].fail("expected elements of no other muscle: element " +
                            std::to_string(elementToFile(mesh, e)) +
                            " is also in muscle '" + groups[owner[e]].name +
                            "' (muscles may not overlap)");
      owner[e] = static_cast<int>(k);
    }
    if (item.has("fibres")) applyFibres(item["fibres"], g.elements, mesh);
    if (item.has("activation")) readActivation(item["activation"], g);
    groups.push_back(std::move(g));
  }
  return groups;
}

// The tissue presets over muscle_groups: the teran_muscle law (M. Bao, "Derivation of
// Quasistatics and Landmark Optimization for Muscles", Sec. 4.3, Eq. 10) with one muscle over
// every element, its fibres along each element's fibre axis, at activation 0.5. For Young's
// modulus E and Poisson ratio nu the law's constants give the same small-strain response as the
// isotropic material: shear modulus mu = 2 (A + B) with A = 3 B (FACE_3D's ratio 6e4 : 2e4),
// bulk modulus K = E / (3 (1 - 2 nu)); the peak stress sigma_max = mu.
constexpr double kMusclePresetActivation = 0.5;

TeranMuscleLaw::Constants musclePresetConstants(const std::string& preset,
                                                const ModelContext& context) {
  const IsotropicModuli m = context.tissueModuli(preset);
  if (!(m.young > 0.0) || !(m.poisson > -1.0 && m.poisson < 0.5))
    throw std::invalid_argument("preset '" + preset +
                                "' expects a Young's modulus > 0 and a Poisson ratio in (-1, 0.5), "
                                "got " + std::to_string(m.young) + " and " +
                                std::to_string(m.poisson));
  const double mu = m.young / (2.0 * (1.0 + m.poisson));
  TeranMuscleLaw::Constants k;
  k.A = 0.375 * mu;
  k.B = 0.125 * mu;
  k.K = m.young / (3.0 * (1.0 - 2.0 * m.poisson));
  k.sigmaMax = mu;
  return k;
}

// The muscle tissue preset `preset` with the law's options `options`.
TissuePreset musclePreset(const std::string& preset, const LawOptions& options,
                          const std::string& description) {
  auto make = [preset, options](const ModelContext& context) {
    Mesh mesh = context.mesh;
    mesh.fillDefaults();
    MuscleGroup block;
    block.name = "block";
    block.activation = kMusclePresetActivation;
    for (int e = 0; e < mesh.numTets() + mesh.numHexes(); ++e) block.elements.push_back(e);
    std::vector<std::unique_ptr<ForceModel>> models;
    models.push_back(std::make_unique<MuscleGroupsModel>(
        mesh, std::vector<TeranMuscleLaw::Constants>{musclePresetConstants(preset, context)},
        std::vector<MuscleGroup>{block}, options));
    return models;
  };
  return {preset, description, make};
}

void addMusclePresets(Registry& registry) {
  LawOptions inversion;
  inversion.inversionThreshold = 0.25;  // PhysBAM's value
  LawOptions psd = inversion;
  psd.psdProjection = true;
  const std::string tissue = "muscle_groups with the teran_muscle law, its constants from the "
                             "material's E and nu, one muscle over every element at activation "
                             "0.5";
  registry.add(musclePreset("teran_muscle", LawOptions{}, tissue + "; no inversion handling"));
  registry.add(musclePreset("teran_muscle_inversion", inversion,
                            tissue + "; inversion_threshold 0.25"));
  registry.add(musclePreset("teran_muscle_inversion_psd", psd,
                            tissue + "; inversion_threshold 0.25, tangents projected to PSD"));
}

}  // namespace

void registerMuscleGroupsModel(Registry& registry) {
  ForceModelEntry e;
  e.name = "muscle_groups";
  e.description = "the teran_muscle law on every element plus named muscle groups, each with "
                  "its elements, fibres and activation; f = f_0 + sum_i a_i f_i (\"Derivation "
                  "of Quasistatics and Landmark Optimization for Muscles\", Eq. 4)";
  e.keys = {{"law", "required: teran_muscle (the law with an active term)"},
            {"muscles",
             "required: a list of {name, region (all | {box: {min, max}} | {elements: [i, ...]}), "
             "fibres (as a materials entry's; default the element's frame), activation (in [0, 1] "
             "or a time curve with values in [0, 1]; default 0)}; no element in two muscles"}};
  for (KeyDoc& key : lawOptionKeys()) e.keys.push_back(std::move(key));
  e.coversHexes = true;
  e.make = [](const YamlEntry& spec, const ModelContext& context) -> std::unique_ptr<ForceModel> {
    spec["law"].choice({TeranMuscleLaw::kName});
    const LawOptions options = readLawOptions(spec);
    rejectMaterialActivations(context);
    Mesh mesh = context.mesh;
    mesh.fillDefaults();
    std::vector<MuscleGroup> groups = readGroups(spec["muscles"], mesh);
    std::vector<TeranMuscleLaw::Constants> constants;
    for (std::size_t m = 0; m < context.materials.size(); ++m)
      constants.push_back(readTeranMuscleConstants(context.entry(m)));
    try {
      return std::make_unique<MuscleGroupsModel>(mesh, constants, std::move(groups), options);
    } catch (const std::invalid_argument& e) {  // an element inverted or flat at rest
      spec.fail(e.what());
    }
  };
  registry.add(std::move(e));
  addMusclePresets(registry);
}

}  // namespace tt
