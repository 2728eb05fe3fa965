#pragma once
// The one registry of everything a scene can name: force models (`force_models[].type`),
// material laws (`law`, read by element models such as `hyperelastic`) and integrators
// (`integrator.type`). Each entry is the name, a one-line description, the YAML keys it
// accepts (each with a one-line description) and its factory. The scene loader, tissue_cli
// (`tissue_cli models`), the benchmarks and the tests read this registry and nothing else;
// docs/registry.md says how to add an entry.
//
// How an entry gets in (and why it cannot silently get lost):
//   A model, law or integrator registers itself in a small file beside its own,
//   `<name>_registration.cpp`, which defines one function `void registerXxx(Registry&)`
//   calling Registry::add. The single list in src/core/scene/builtin_registrations.cpp
//   declares and calls every such function. The core is a static library in the standalone
//   build, so self-registering static objects in otherwise unreferenced object files would be
//   dropped by the linker; an explicit call is a reference, so the linker keeps the object.
//   A unit test reads the sources and fails when a `register*(Registry&)` function defined in
//   a *_registration.cpp is not called from the list, and another fails when a name
//   docs/registry.md documents is not registered (or a registered name is undocumented).
//
// Factories read their options strictly: the registry itself checks the keys of an entry
// (`type` plus the declared keys) before calling the factory, so the documented keys and the
// accepted keys are one list. An unknown name is one error that lists the known ones; there
// is no default.
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

struct Material;
struct Mesh;
struct ModelContext;     // registry/model_context.h
struct LawModelRequest;  // model/law_model_request.h

// One accepted YAML key and what it means (shown by `tissue_cli models`).
struct KeyDoc {
  std::string key;
  std::string description;
};

// A named configuration of a force model: the model with fixed options, e.g.
// edge_length_literal = edge_length {path: literal}. Benchmarks and `tissue_cli forces --model`
// take these names. A model with no required key lists its own name (options "") as one.
struct ModelPreset {
  std::string name;
  std::string options;      // YAML flow map of the options, "" or "{}" for none
  std::string description;
};

// A named tissue of one or more force models over a mesh and its materials, e.g. the Hunter law
// of Adamss Table 2.1 through the virtual hexahedron plus a volume term, scaled to the material's
// Young's modulus and Poisson ratio. It shares the preset names: benchmarks and `tissue_cli
// forces --model` take it like a ModelPreset (Registry::makePresetModels).
struct TissuePreset {
  std::string name;
  std::string description;
  std::function<std::vector<std::unique_ptr<ForceModel>>(const ModelContext& context)> make;
};

// Factories use the spec and context during the call only (they keep no YamlEntry).
using ForceModelFactory =
    std::function<std::unique_ptr<ForceModel>(const YamlEntry& spec, const ModelContext& context)>;

struct ForceModelEntry {
  std::string name;
  std::string description;
  std::vector<KeyDoc> keys;            // accepted besides `type`
  std::vector<ModelPreset> presets;    // the named configurations (may be empty)
  bool coversHexes = false;            // false: a mesh with hexahedra is refused
  ForceModelFactory make;
};

using LawModelFactory =
    std::function<std::unique_ptr<ForceModel>(const ModelContext& context,
                                              const LawModelRequest& request)>;

// A material law (psi(F), P(F), dP; material/law.h). Its entry names the keys a `materials`
// entry may carry for it beyond the common ones (density, region, name, fibres, stress_unit)
// and the Lame constants (material/elastic_constants_reader.h), and builds the element models
// over the law: model/law_model_factory.h instantiates the models' templates for the law in the
// law's registration file, and reads the law's constants per material from ModelContext (its
// materialEntries in a scene, Material::elastic elsewhere). A key of a law is accepted in every
// material entry.
struct LawEntry {
  std::string name;
  std::string description;
  std::vector<KeyDoc> materialKeys;    // the law's own keys in a `materials` entry
  LawModelFactory makeModel;           // every element model over the law
  // True: the law alone is a tissue model, and the registry gives the model kLawModel the
  // preset kLawModel_NAME = {law: NAME}. False for a term meant to add to another (volume).
  bool standalone = true;
};

// The element model over the laws ("hyperelastic"); it must be registered before the laws.
constexpr const char* kLawModel = "hyperelastic";

// What reading a scene noticed without refusing it (a deprecated key), one line each
// ("FILE:LINE: ..."); the scene keeps them (Scene::notes).
using Notes = std::vector<std::string>;
using IntegratorFactory =
    std::function<std::unique_ptr<Integrator>(const YamlEntry& spec, Notes& notes)>;

struct IntegratorEntry {
  std::string name;
  std::string description;
  std::vector<KeyDoc> keys;            // accepted besides `type`
  IntegratorFactory make;
};

// An unknown name outside a scene file (benchmark or CLI option); the message lists the
// known names. Inside a scene, an unknown `type` is an InputError at the key's line.
struct UnknownNameError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class Registry {
 public:
  // Each throws std::logic_error for an empty name, a missing factory, a repeated key or a
  // name already registered in the same section (the presets of the models and the tissue
  // presets are one section): a programming error the first run of any test finds.
  void add(ForceModelEntry entry);
  void add(LawEntry entry);
  void add(IntegratorEntry entry);
  void add(TissuePreset preset);

  const std::vector<ForceModelEntry>& forceModels() const { return models_; }
  const std::vector<LawEntry>& laws() const { return laws_; }
  const std::vector<IntegratorEntry>& integrators() const { return integrators_; }
  const std::vector<TissuePreset>& tissuePresets() const { return tissues_; }

  // nullptr when unknown.
  const ForceModelEntry* findForceModel(const std::string& name) const;
  const LawEntry* findLaw(const std::string& name) const;
  const IntegratorEntry* findIntegrator(const std::string& name) const;

  // "a, b, c" in registration order.
  std::string forceModelNames() const;
  std::string lawNames() const;
  std::string integratorNames() const;
  // Every preset: those of every model, in order, then the tissue presets, in order.
  std::vector<std::string> presetNames() const;
  // The presets of the models alone (each one force model), in order.
  std::vector<std::string> modelPresetNames() const;

  // Scene entries {type: NAME, ...}: the type must be registered (else InputError at `type`
  // listing the known names) and every other key declared by the entry.
  std::unique_ptr<ForceModel> makeForceModel(const YamlEntry& spec,
                                             const ModelContext& context) const;
  std::unique_ptr<Integrator> makeIntegrator(const YamlEntry& spec, Notes& notes) const;
  // The same with the notes printed to stderr, one line each.
  std::unique_ptr<Integrator> makeIntegrator(const YamlEntry& spec) const;
  // The law named by `entry` (a `law: NAME` value), or InputError listing the known laws.
  const LawEntry& law(const YamlEntry& entry) const;

  // A model's preset by name; UnknownNameError listing those presets when there is none (or
  // the name is a tissue preset's).
  std::unique_ptr<ForceModel> makePreset(const std::string& name,
                                         const ModelContext& context) const;
  // Any preset by name as its list of force models (one for a model's preset);
  // UnknownNameError listing every preset when there is none.
  std::vector<std::unique_ptr<ForceModel>> makePresetModels(const std::string& name,
                                                            const ModelContext& context) const;

 private:
  std::vector<ForceModelEntry> models_;
  std::vector<LawEntry> laws_;
  std::vector<IntegratorEntry> integrators_;
  std::vector<TissuePreset> tissues_;
};

// The registry of the built-in models, laws and integrators, filled on first use (thread-safe)
// by registerBuiltIns.
const Registry& registry();

// A model's preset (see ModelPreset) over a mesh and its materials, outside a scene
// (benchmarks, tests, tissue_cli forces --model); UnknownNameError listing the presets.
std::unique_ptr<ForceModel> makeElasticModel(const std::string& preset, const Mesh& mesh,
                                             const std::vector<Material>& materials);

// Any preset (a model's or a tissue's) as its force models over a mesh and its materials, outside
// a scene; UnknownNameError listing every preset.
std::vector<std::unique_ptr<ForceModel>> makePresetModels(const std::string& preset,
                                                          const Mesh& mesh,
                                                          const std::vector<Material>& materials);

// Calls every registration function (src/core/scene/builtin_registrations.cpp).
void registerBuiltIns(Registry& registry);

}  // namespace tt
