#include "tissue_trainer/core/registry/registry.h"

#include <algorithm>
#include <iostream>
#include <set>

#include "tissue_trainer/core/registry/model_context.h"

namespace tt {
namespace {

template <class Entry>
const Entry* findByName(const std::vector<Entry>& entries, const std::string& name) {
  for (const Entry& e : entries)
    if (e.name == name) return &e;
  return nullptr;
}

template <class Entry>
std::string joinNames(const std::vector<Entry>& entries) {
  std::string out;
  for (const Entry& e : entries) out += (out.empty() ? "" : ", ") + e.name;
  return out;
}

void requireName(const std::string& section, const std::string& name, bool hasFactory) {
  if (name.empty()) throw std::logic_error("registry: a " + section + " without a name");
  if (!hasFactory) throw std::logic_error("registry: " + section + " '" + name + "' has no factory");
}

void requireDistinctKeys(const std::string& section, const std::string& name,
                         const std::vector<KeyDoc>& keys) {
  std::set<std::string> seen{"type"};
  for (const KeyDoc& k : keys)
    if (k.key.empty() || !seen.insert(k.key).second)
      throw std::logic_error("registry: " + section + " '" + name + "' declares key '" + k.key +
                             "' twice (or 'type', or an empty key)");
}

// "a, b, c".
std::string joinPresetNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// `type` plus the entry's declared keys.
std::vector<std::string> allowedKeys(const std::vector<KeyDoc>& keys) {
  std::vector<std::string> allowed{"type"};
  for (const KeyDoc& k : keys) allowed.push_back(k.key);
  return allowed;
}

// The entry named by spec.type, or an InputError at `type` listing the known names.
template <class Entry>
const Entry& entryOfType(const YamlEntry& spec, const std::vector<Entry>& entries,
                         const char* what) {
  const YamlEntry type = spec["type"];
  const std::string name = type.text();
  const Entry* entry = findByName(entries, name);
  if (!entry)
    type.fail("unknown " + std::string(what) + " '" + name + "' (expected one of: " +
              joinNames(entries) + ")");
  spec.expectMap(allowedKeys(entry->keys));
  return *entry;
}

}  // namespace

void Registry::add(ForceModelEntry entry) {
  requireName("force model", entry.name, static_cast<bool>(entry.make));
  if (findForceModel(entry.name))
    throw std::logic_error("registry: force model '" + entry.name + "' registered twice");
  requireDistinctKeys("force model", entry.name, entry.keys);
  const std::vector<std::string> presets = presetNames();
  for (const ModelPreset& p : entry.presets)
    if (p.name.empty() || std::count(presets.begin(), presets.end(), p.name) ||
        std::count_if(entry.presets.begin(), entry.presets.end(),
                      [&](const ModelPreset& q) { return q.name == p.name; }) > 1)
      throw std::logic_error("registry: preset '" + p.name + "' of force model '" + entry.name +
                             "' is empty or registered twice");
  models_.push_back(std::move(entry));
}

void Registry::add(LawEntry entry) {
  requireName("law", entry.name, static_cast<bool>(entry.makeModel));
  if (findLaw(entry.name)) throw std::logic_error("registry: law '" + entry.name + "' registered twice");
  requireDistinctKeys("law", entry.name, entry.materialKeys);
  if (entry.standalone) {
    auto model = std::find_if(models_.begin(), models_.end(),
                              [](const ForceModelEntry& m) { return m.name == kLawModel; });
    if (model == models_.end())
      throw std::logic_error("registry: law '" + entry.name + "' registered before the " +
                             std::string(kLawModel) + " model that builds it");
    const std::string preset = std::string(kLawModel) + "_" + entry.name;
    const std::vector<std::string> presets = presetNames();
    if (std::count(presets.begin(), presets.end(), preset))
      throw std::logic_error("registry: preset '" + preset + "' of law '" + entry.name +
                             "' registered twice");
    model->presets.push_back({preset, "{law: " + entry.name + "}",
                              "the " + entry.name + " law, no options"});
  }
  laws_.push_back(std::move(entry));
}

void Registry::add(IntegratorEntry entry) {
  requireName("integrator", entry.name, static_cast<bool>(entry.make));
  if (findIntegrator(entry.name))
    throw std::logic_error("registry: integrator '" + entry.name + "' registered twice");
  requireDistinctKeys("integrator", entry.name, entry.keys);
  integrators_.push_back(std::move(entry));
}

void Registry::add(TissuePreset preset) {
  requireName("tissue preset", preset.name, static_cast<bool>(preset.make));
  const std::vector<std::string> presets = presetNames();
  if (std::count(presets.begin(), presets.end(), preset.name))
    throw std::logic_error("registry: preset '" + preset.name + "' registered twice");
  tissues_.push_back(std::move(preset));
}

const ForceModelEntry* Registry::findForceModel(const std::string& name) const {
  return findByName(models_, name);
}
const LawEntry* Registry::findLaw(const std::string& name) const { return findByName(laws_, name); }
const IntegratorEntry* Registry::findIntegrator(const std::string& name) const {
  return findByName(integrators_, name);
}

std::string Registry::forceModelNames() const { return joinNames(models_); }
std::string Registry::lawNames() const { return joinNames(laws_); }
std::string Registry::integratorNames() const { return joinNames(integrators_); }

std::vector<std::string> Registry::presetNames() const {
  std::vector<std::string> names = modelPresetNames();
  for (const TissuePreset& t : tissues_) names.push_back(t.name);
  return names;
}

std::vector<std::string> Registry::modelPresetNames() const {
  std::vector<std::string> names;
  for (const ForceModelEntry& m : models_)
    for (const ModelPreset& p : m.presets) names.push_back(p.name);
  return names;
}

std::unique_ptr<ForceModel> Registry::makeForceModel(const YamlEntry& spec,
                                                     const ModelContext& context) const {
  const ForceModelEntry& entry = entryOfType(spec, models_, "force model");
  if (!entry.coversHexes && context.mesh.numHexes() > 0)
    spec["type"].fail("force model '" + entry.name + "' covers tetrahedra only, and the mesh has " +
                      std::to_string(context.mesh.numHexes()) +
                      " hexahedra (hyperelastic covers both)");
  return entry.make(spec, context);
}

std::unique_ptr<Integrator> Registry::makeIntegrator(const YamlEntry& spec, Notes& notes) const {
  return entryOfType(spec, integrators_, "integrator").make(spec, notes);
}

std::unique_ptr<Integrator> Registry::makeIntegrator(const YamlEntry& spec) const {
  Notes notes;
  std::unique_ptr<Integrator> integrator = makeIntegrator(spec, notes);
  for (const std::string& note : notes) std::cerr << note << "\n";
  return integrator;
}

const LawEntry& Registry::law(const YamlEntry& entry) const {
  const std::string name = entry.text();
  const LawEntry* law = findLaw(name);
  if (!law)
    entry.fail("unknown law '" + name + "' (expected one of: " +
               (laws_.empty() ? std::string("none registered") : lawNames()) + ")");
  return *law;
}

std::unique_ptr<ForceModel> Registry::makePreset(const std::string& name,
                                                 const ModelContext& context) const {
  for (const ForceModelEntry& m : models_)
    for (const ModelPreset& p : m.presets) {
      if (p.name != name) continue;
      YAML::Node spec = p.options.empty() ? YAML::Node(YAML::NodeType::Map) : YAML::Load(p.options);
      spec["type"] = m.name;
      const std::string origin = "preset " + p.name;
      return makeForceModel(YamlEntry(spec, "", &origin), context);
    }
  const std::string what = findByName(tissues_, name)
                               ? "'" + name + "' is a tissue of several force models, not one"
                               : "unknown force model '" + name + "'";
  throw UnknownNameError(what + " (expected one of: " + joinPresetNames(modelPresetNames()) + ")");
}

std::vector<std::unique_ptr<ForceModel>> Registry::makePresetModels(
    const std::string& name, const ModelContext& context) const {
  std::vector<std::unique_ptr<ForceModel>> models;
  if (const TissuePreset* tissue = findByName(tissues_, name)) {
    models = tissue->make(context);
  } else {
    const std::vector<std::string> single = modelPresetNames();
    if (!std::count(single.begin(), single.end(), name))
      throw UnknownNameError("unknown force model '" + name + "' (expected one of: " +
                             joinPresetNames(presetNames()) + ")");
    models.push_back(makePreset(name, context));
  }
  return models;
}

std::unique_ptr<ForceModel> makeElasticModel(const std::string& preset, const Mesh& mesh,
                                             const std::vector<Material>& materials) {
  return registry().makePreset(preset, ModelContext{mesh, materials, {}});
}

std::vector<std::unique_ptr<ForceModel>> makePresetModels(const std::string& preset,
                                                          const Mesh& mesh,
                                                          const std::vector<Material>& materials) {
  return registry().makePresetModels(preset, ModelContext{mesh, materials, {}});
}

const Registry& registry() {
  static const Registry instance = [] {
    Registry r;
    registerBuiltIns(r);
    return r;
  }();
  return instance;
}

}  // namespace tt
