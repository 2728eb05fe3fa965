#pragma once
// Shared by the scene tests: a text substitution, a scene text written to a file of the
// temporary directory, and the check that each of a list of malformed scenes fails with one
// clear line.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <string>
#include <vector>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace testutil {

// `text` with the first `from` replaced by `to` (a test failure when there is none).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// Writes `text` to <temp>/tt_scene_tests/<name> and returns that path.
inline std::string writeScene(const std::string& name, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tt_scene_tests";
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

struct BadScene {
  const char* what;
  std::string text;
  long line;           // expected line (1-based); 0: not checked
  const char* phrase;  // must appear in the message
};

// Each text, written to `fileName` and given to `read`, fails with one InputError line naming
// the file, the line and the phrase.
inline void expectEachFileFailsClearly(const std::vector<BadScene>& cases,
                                       const std::string& fileName,
                                       const std::function<void(const std::string&)>& read) {
  for (const BadScene& c : cases) {
    const std::string path = writeScene(fileName, c.text);
    try {
      read(path);
      ADD_FAILURE() << c.what << ": no error";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.file(), path) << c.what;
      if (c.line > 0) EXPECT_EQ(e.line(), c.line) << c.what << ": " << message;
      EXPECT_NE(message.find(c.phrase), std::string::npos) << c.what << ": " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << c.what << ": one line";
    }
  }
}

// Each scene, written to `fileName`, fails to load with one InputError line naming the file,
// the line and the phrase.
inline void expectEachSceneFailsClearly(const std::vector<BadScene>& cases,
                                        const std::string& fileName) {
  expectEachFileFailsClearly(cases, fileName, [](const std::string& path) { loadScene(path); });
}

// The integrator entry "type: TYPE" followed by `keys` (one per line; line 2 is the first), as
// read from the file named `file` (a constant of the test: the entry refers to it).
inline YamlEntry integratorEntry(const std::string& type, const std::string& keys,
                                 const std::string& file) {
  static std::vector<YAML::Node> kept;  // YamlEntry refers to its node
  kept.push_back(YAML::Load("type: " + type + "\n" + keys));
  return YamlEntry(kept.back(), "integrator", &file);
}

// The InputError line of making that integrator; "" when it is made.
inline std::string integratorErrorOf(const std::string& type, const std::string& keys,
                                     const std::string& file) {
  Notes notes;
  try {
    registry().makeIntegrator(integratorEntry(type, keys, file), notes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace testutil
}  // namespace tt
