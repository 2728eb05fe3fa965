// The scene registry (include/tissue_trainer/core/registry/registry.h): nothing registered is
// lost or undocumented, names are unique, and an unknown name is one error listing the
// known ones, in scenes and outside them.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/time_curve.h"
#include "tissue_trainer/core/model/law_model_request.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  return std::string(std::istreambuf_iterator<char>(in), {});
}

const fs::path kRegistryRoot = TT_SOURCE_DIR;

// A YAML entry over text; `file` must outlive the entry.
YamlEntry entryOf(const YAML::Node& node, const std::string& file) { return YamlEntry(node, "spec", &file); }

std::string thrownMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

ForceModelEntry dummyModel(const std::string& name) {
  ForceModelEntry e;
  e.name = name;
  e.make = [](const YamlEntry&, const ModelContext&) -> std::unique_ptr<ForceModel> { return nullptr; };
  return e;
}

IntegratorEntry dummyIntegrator(const std::string& name) {
  IntegratorEntry e;
  e.name = name;
  e.make = [](const YamlEntry&, Notes&) -> std::unique_ptr<Integrator> { return nullptr; };
  return e;
}

LawEntry dummyLaw(const std::string& name, bool standalone = false) {
  LawEntry e;
  e.name = name;
  e.standalone = standalone;
  e.makeModel = [](const ModelContext&, const LawModelRequest&) -> std::unique_ptr<ForceModel> {
    return nullptr;
  };
  return e;
}

// Every register*(Registry&) function defined in a *_registration.cpp under src/core is called
// from the one list, so no registration can be dropped by the linker or forgotten.
TEST(Registry, EveryRegistrationFunctionIsCalledFromTheList) {
  const std::string list = readText(kRegistryRoot / "src/core/scene/builtin_registrations.cpp");
  const std::regex definition(R"(void\s+(register\w+)\s*\(\s*Registry\s*&\s*\w*\s*\)\s*\{)");
  int found = 0;
  for (const auto& file : fs::recursive_directory_iterator(kRegistryRoot / "src/core")) {
    const std::string name = file.path().filename().string();
    if (name.size() < 17 || name.substr(name.size() - 17) != "_registration.cpp") continue;
    const std::string text = readText(file.path());
    int inFile = 0;
    for (std::sregex_iterator m(text.begin(), text.end(), definition), end; m != end; ++m) {
      ++inFile;
      const std::string call = (*m)[1].str() + "(registry);";
      EXPECT_NE(list.find(call), std::string::npos)
          << file.path() << " defines " << (*m)[1] << " but builtin_registrations.cpp never calls it";
    }
    EXPECT_GT(inFile, 0) << file.path() << " defines no register*(Registry&) function";
    found += inFile;
  }
  EXPECT_GE(found, 14);  // 4 force models, 4 law files (5 laws), 5 integrator files today
}

// docs/registry.md lists every registered name (rows "| force_model | `name` | ..."), and
// nothing it lists is missing from the registry.
TEST(Registry, DocumentedNamesAreExactlyTheRegisteredOnes) {
  const std::string doc = readText(kRegistryRoot / "docs/registry.md");
  const std::regex row(R"(\|\s*(force_model|preset|law|integrator)\s*\|\s*`([a-z0-9_]+)`)");
  std::set<std::string> documented;
  for (std::sregex_iterator m(doc.begin(), doc.end(), row), end; m != end; ++m)
    documented.insert((*m)[1].str() + " " + (*m)[2].str());
  std::set<std::string> registered;
  const Registry& r = registry();
  for (const auto& m : r.forceModels()) registered.insert("force_model " + m.name);
  for (const auto& p : r.presetNames()) registered.insert("preset " + p);
  for (const auto& l : r.laws()) registered.insert("law " + l.name);
  for (const auto& i : r.integrators()) registered.insert("integrator " + i.name);
  EXPECT_EQ(documented, registered);
}

// Every `type: a | b` a documentation page or the README names in its scene examples is a
// registered model or integrator, or a time curve's type (model/time_curve.h).
TEST(Registry, TypesNamedInTheDocumentationAreRegistered) {
  std::vector<fs::path> pages{kRegistryRoot / "README.md"};
  for (const auto& file : fs::directory_iterator(kRegistryRoot / "docs"))
    if (file.path().extension() == ".md") pages.push_back(file.path());
  // A YAML key `type:`, not the `...].type:` key path of a quoted error message.
  const std::regex typeLine(R"((?:^|[^.\w])type:[ \t]*([a-z_]+([ \t]*\|[ \t]*[a-z_]+)*))");
  const std::regex word("[a-z_]+");
  int checked = 0;
  for (const fs::path& page : pages) {
    const std::string text = readText(page);
    for (std::sregex_iterator m(text.begin(), text.end(), typeLine), end; m != end; ++m) {
      const std::string names = (*m)[1].str();
      for (std::sregex_iterator w(names.begin(), names.end(), word); w != end; ++w) {
        const std::string name = w->str();
        ++checked;
        EXPECT_TRUE(registry().findForceModel(name) || registry().findIntegrator(name) ||
                    isTimeCurveType(name))
            << page.filename() << " names type '" << name << "', which is not registered";
      }
    }
  }
  EXPECT_GT(checked, 5);
}

TEST(Registry, RepeatedNamesAndBrokenEntriesAreRejected) {
  Registry r;
  r.add(dummyModel("spring"));
  EXPECT_THROW(r.add(dummyModel("spring")), std::logic_error);
  EXPECT_THROW(r.add(dummyModel("")), std::logic_error);
  ForceModelEntry noFactory;
  noFactory.name = "lonely";
  EXPECT_THROW(r.add(noFactory), std::logic_error);
  ForceModelEntry twiceKey = dummyModel("twice");
  twiceKey.keys = {{"a", ""}, {"a", ""}};
  EXPECT_THROW(r.add(twiceKey), std::logic_error);
  ForceModelEntry typeKey = dummyModel("typed");
  typeKey.keys = {{"type", ""}};
  EXPECT_THROW(r.add(typeKey), std::logic_error);
  ForceModelEntry presetClash = dummyModel("other");
  presetClash.presets = {{"p", "", ""}};
  r.add(presetClash);
  ForceModelEntry presetAgain = dummyModel("third");
  presetAgain.presets = {{"p", "", ""}};
  EXPECT_THROW(r.add(presetAgain), std::logic_error);

  r.add(dummyIntegrator("stepper"));
  EXPECT_THROW(r.add(dummyIntegrator("stepper")), std::logic_error);
  r.add(dummyLaw("rubber"));
  EXPECT_THROW(r.add(dummyLaw("rubber")), std::logic_error);
  // One name may appear in different sections (a model and a law called alike).
  EXPECT_NO_THROW(r.add(dummyLaw("spring")));
  EXPECT_EQ(r.forceModelNames(), "spring, other");
  EXPECT_EQ(r.lawNames(), "rubber, spring");
}

// A standalone law gives the law model its preset; adding a law takes no edit elsewhere.
TEST(Registry, AStandaloneLawAddsItsPresetToTheLawModel) {
  Registry r;
  EXPECT_THROW(r.add(dummyLaw("early", true)), std::logic_error) << "before the law model";
  r.add(dummyModel(kLawModel));
  r.add(dummyLaw("rubber", true));
  r.add(dummyLaw("term", false));
  ASSERT_EQ(r.forceModels().size(), 1u);
  ASSERT_EQ(r.forceModels()[0].presets.size(), 1u);
  EXPECT_EQ(r.forceModels()[0].presets[0].name, std::string(kLawModel) + "_rubber");
  EXPECT_EQ(r.forceModels()[0].presets[0].options, "{law: rubber}");
  EXPECT_EQ(r.presetNames(), std::vector<std::string>{std::string(kLawModel) + "_rubber"});
  const Registry& builtIn = registry();
  for (const LawEntry& law : builtIn.laws()) {
    const std::vector<std::string> names = builtIn.presetNames();
    EXPECT_EQ(std::count(names.begin(), names.end(), std::string(kLawModel) + "_" + law.name),
              law.standalone ? 1 : 0)
        << law.name;
  }
}

TEST(Registry, TheBuiltInRegistryHasNoDuplicates) {
  Registry fresh;
  EXPECT_NO_THROW(registerBuiltIns(fresh));
  EXPECT_THROW(registerBuiltIns(fresh), std::logic_error);  // a second round repeats every name
  EXPECT_EQ(fresh.forceModels().size(), registry().forceModels().size());
}

TEST(Registry, UnknownTypeInASpecListsTheKnownOnes) {
  const std::string file = "inline.yaml";
  const YAML::Node model = YAML::Load("{type: spring_mass}");
  const std::string message = thrownMessage([&] {
    const Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d(1, 1, 1), TetSplit::kFive);
    const std::vector<Material> materials(1);
    registry().makeForceModel(entryOf(model, file), ModelContext{mesh, materials, {}});
  });
  EXPECT_NE(message.find("inline.yaml:1: spec.type: unknown force model 'spring_mass'"),
            std::string::npos) << message;
  for (const auto& m : registry().forceModels())
    EXPECT_NE(message.find(m.name), std::string::npos) << message;

  const YAML::Node integrator = YAML::Load("{type: rk4}");
  const std::string other =
      thrownMessage([&] { registry().makeIntegrator(entryOf(integrator, file)); });
  EXPECT_NE(other.find("unknown integrator 'rk4'"), std::string::npos) << other;
  EXPECT_NE(other.find(registry().integratorNames()), std::string::npos) << other;

  const YAML::Node law = YAML::Load("mooney");
  const std::string lawMessage = thrownMessage([&] { registry().law(entryOf(law, file)); });
  EXPECT_NE(lawMessage.find("unknown law 'mooney'"), std::string::npos) << lawMessage;
}

// The registry checks the declared keys before the factory runs: a key of another model is
// rejected, with the keys this one accepts.
TEST(Registry, UndeclaredKeysAreRejected) {
  const std::string file = "inline.yaml";
  const Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d(1, 1, 1), TetSplit::kFive);
  const std::vector<Material> materials(1);
  const YAML::Node spec = YAML::Load("{type: tensor_mass, path: literal}");
  const std::string message = thrownMessage(
      [&] { registry().makeForceModel(entryOf(spec, file), ModelContext{mesh, materials, {}}); });
  EXPECT_NE(message.find("spec.path: unknown key 'path' (expected one of: type)"),
            std::string::npos) << message;
  const YAML::Node integrator = YAML::Load("{type: newtonian, substeps: 2}");
  const std::string other =
      thrownMessage([&] { registry().makeIntegrator(entryOf(integrator, file)); });
  EXPECT_NE(other.find("unknown key 'substeps' (expected one of: type, time_step"),
            std::string::npos) << other;
}

TEST(Registry, UnknownPresetListsThePresets) {
  const Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d(1, 1, 1), TetSplit::kFive);
  try {
    makeElasticModel("edge_lenght", mesh, std::vector<Material>(1));
    FAIL() << "no error for an unknown preset";
  } catch (const UnknownNameError& e) {
    const std::string message = e.what();
    for (const std::string& p : registry().modelPresetNames())  // the ones it makes
      EXPECT_NE(message.find(p), std::string::npos) << message;
  }
}

// Every preset builds the model it belongs to, and every integrator builds from its name
// alone (all keys optional) and reports that name: a registration cannot point at another
// class.
TEST(Registry, EveryPresetAndIntegratorBuildsWhatItNames) {
  Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d(0.01, 0.01, 0.01), TetSplit::kFive);
  mesh.material.assign(mesh.numTets(), 0);
  ElasticConstants k;
  k.lambda = k.lambdaL = 2000.0;
  k.mu = k.muL = 1000.0;
  const Material m = Material::withConstants(k, 1000.0);
  const std::vector<Material> materials{m};
  for (const ForceModelEntry& entry : registry().forceModels())
    for (const ModelPreset& p : entry.presets) {
      const auto model = makeElasticModel(p.name, mesh, materials);
      ASSERT_TRUE(model) << p.name;
      EXPECT_EQ(std::string(model->name()), entry.name) << p.name;
    }
  const std::string file = "inline.yaml";
  for (const IntegratorEntry& entry : registry().integrators()) {
    YAML::Node spec;
    spec["type"] = entry.name;
    const auto integrator = registry().makeIntegrator(entryOf(spec, file));
    ASSERT_TRUE(integrator) << entry.name;
    EXPECT_EQ(std::string(integrator->name()), entry.name);
  }
}

// The literal presets select their option; the plain names keep the defaults.
TEST(Registry, ThePreconditionerKeySelectsEachAndATypoNamesTheAcceptedValues) {
  using Preconditioning = BackwardEulerParams::Preconditioning;
  const std::string file = "inline.yaml";
  const std::pair<const char*, Preconditioning> choices[] = {
      {"jacobi", Preconditioning::kJacobi},
      {"cholesky", Preconditioning::kCholesky},
      {"amg", Preconditioning::kAmg}};
  for (const auto& [name, expected] : choices) {
    const YAML::Node spec = YAML::Load(std::string("{type: backward_euler, preconditioner: ") + name + "}");
    const auto integrator = registry().makeIntegrator(YamlEntry(spec, "integrator", &file));
    const auto* be = dynamic_cast<const BackwardEulerIntegrator*>(integrator.get());
    ASSERT_NE(be, nullptr) << name;
    EXPECT_EQ(be->params.preconditioner, expected) << name;
  }
  const YAML::Node typo = YAML::Load("{type: backward_euler, preconditioner: amgg}");
  const std::string message =
      thrownMessage([&] { registry().makeIntegrator(YamlEntry(typo, "integrator", &file)); });
  EXPECT_NE(message.find("integrator.preconditioner: expected one of: jacobi, cholesky, amg"),
            std::string::npos) << message;
  EXPECT_NE(message.find("amgg"), std::string::npos) << message;
}

TEST(Registry, PresetOptionsReachTheModel) {
  Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d(0.01, 0.01, 0.01), TetSplit::kFive);
  mesh.material.assign(mesh.numTets(), 0);
  const std::vector<Material> materials{Material::isotropic(3000.0, 0.3, 1000.0)};
  auto path = [&](const std::string& preset) {
    const auto model = makeElasticModel(preset, mesh, materials);
    return dynamic_cast<const EdgeLengthModel&>(*model).path();
  };
  auto sign = [&](const std::string& preset) {
    const auto model = makeElasticModel(preset, mesh, materials);
    return dynamic_cast<const StvkDisplacementModel&>(*model).alphaSign();
  };
  EXPECT_EQ(path("edge_length"), EdgeLengthPath::kFast);
  EXPECT_EQ(path("edge_length_literal"), EdgeLengthPath::kLiteral);
  EXPECT_EQ(sign("stvk_displacement"), AlphaSign::kCorrect);
  EXPECT_EQ(sign("stvk_displacement_paper_literal"), AlphaSign::kPaperLiteral);
}

TEST(Registry, SceneWithAnUnknownTypeNamesTheLineAndTheKnownTypes) {
  const fs::path dir = fs::temp_directory_path() / "tt_registry_tests";
  fs::create_directories(dir);
  const fs::path path = dir / "unknown_type.yaml";
  std::ofstream(path) << "mesh: {generator: box, nodes: [2, 2, 2], size: [0.01, 0.01, 0.01]}\n"
                         "materials: [{young_modulus: 3000, poisson_ratio: 0.3}]\n"
                         "force_models:\n"
                         "  - type: hyperelastik\n"
                         "integrator: {type: backward_euler}\n";
  try {
    loadScene(path.string());
    FAIL() << "an unknown type loaded";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(e.line(), 4);
    EXPECT_NE(message.find("force_models[0].type: unknown force model 'hyperelastik' (expected "
                           "one of: " + registry().forceModelNames() + ")"),
              std::string::npos) << message;
  }
}

}  // namespace
}  // namespace tt
