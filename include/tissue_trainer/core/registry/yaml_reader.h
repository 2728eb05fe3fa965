#pragma once
// Strict reading of YAML maps: every key must be known, every value of the expected type.
// Each error is one InputError line "FILE:LINE: key.path: what was expected".
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "tissue_trainer/core/error.h"

namespace tt {

// A YAML node together with its key path ("integrator.time_step") and the file it came from.
class YamlEntry {
 public:
  YamlEntry(const YAML::Node& node, std::string path, const std::string* file)
      : node_(node), path_(std::move(path)), file_(file) {}

  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }

  [[noreturn]] void fail(const std::string& expected) const;
  // "FILE:LINE", the place of this entry (as fail() names it).
  std::string where() const;
  long line() const;  // 1-based; 0 when unknown

  // This entry must be a map whose keys are all in `allowed`.
  void expectMap(std::initializer_list<const char*> allowed) const;
  void expectMap(const std::vector<std::string>& allowed) const;
  bool has(const char* key) const { return node_.IsMap() && node_[key]; }
  YamlEntry operator[](const char* key) const;  // fails if the key is absent
  YamlEntry operator[](int index) const;
  size_t size() const;                          // of a sequence (fails otherwise)

  double number() const;
  double positive() const;
  int integer() const;
  int integerAtLeast(int minimum) const;
  bool boolean() const;
  std::string text() const;
  // One of the given words.
  std::string choice(std::initializer_list<const char*> words) const;
  Eigen::Vector3d vector3() const;
  std::vector<int> integers() const;

  // Convenience: value of an optional key, or the default when absent.
  double number(const char* key, double fallback) const;
  double positive(const char* key, double fallback) const;
  int integerAtLeast(const char* key, int minimum, int fallback) const;
  bool boolean(const char* key, bool fallback) const;

 private:
  YAML::Node node_;
  std::string path_;
  const std::string* file_;
};

// The entry of the optional key `name` of `spec`, formerly called `oldName` (nullptr: never
// renamed): spec[name] when given; else spec[oldName], adding to `notes` the line
// "FILE:LINE: PATH is deprecated: write NAME (the same meaning)"; else nothing. Both names given
// is an InputError naming both.
std::optional<YamlEntry> renamedKey(const YamlEntry& spec, const char* name, const char* oldName,
                                    std::vector<std::string>& notes);

// The factor of a `stress_unit` value: Pa, kPa or MPa.
double stressUnit(const YamlEntry& unit);

}  // namespace tt
