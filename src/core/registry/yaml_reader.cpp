#include "tissue_trainer/core/registry/yaml_reader.h"

#include <cmath>
#include <cstdlib>

namespace tt {
namespace {

std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Null: return "nothing";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
    default: return "an undefined value";
  }
}

template <class Words>
std::string joinWords(const Words& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + std::string(w);
  return out;
}

}  // namespace

void YamlEntry::fail(const std::string& expected) const {
  throw InputError(*file_, line(), (path_.empty() ? "" : path_ + ": ") + expected);
}

long YamlEntry::line() const { return node_.Mark().line >= 0 ? node_.Mark().line + 1 : 0; }

std::string YamlEntry::where() const { return *file_ + ":" + std::to_string(line()); }

void YamlEntry::expectMap(std::initializer_list<const char*> allowed) const {
  expectMap(std::vector<std::string>(allowed.begin(), allowed.end()));
}

void YamlEntry::expectMap(const std::vector<std::string>& allowed) const {
  if (!node_.IsMap()) fail("expected a map, got " + describe(node_));
  for (const auto& item : node_) {
    const std::string key = item.first.Scalar();
    bool known = false;
    for (const std::string& a : allowed) known = known || key == a;
    if (!known)
      YamlEntry(item.first, path_.empty() ? key : path_ + "." + key, file_)
          .fail("unknown key '" + key + "' (expected one of: " + joinWords(allowed) + ")");
  }
}

YamlEntry YamlEntry::operator[](const char* key) const {
  const std::string child = path_.empty() ? key : path_ + "." + key;
  if (!node_.IsMap()) fail("expected a map with key '" + std::string(key) + "'");
  const YAML::Node value = node_[key];
  if (!value) fail("missing required key '" + std::string(key) + "'");
  return YamlEntry(value, child, file_);
}

YamlEntry YamlEntry::operator[](int index) const {
  return YamlEntry(node_[static_cast<size_t>(index)], path_ + "[" + std::to_string(index) + "]", file_);
}

size_t YamlEntry::size() const {
  if (!node_.IsSequence()) fail("expected a list, got " + describe(node_));
  return node_.size();
}

double YamlEntry::number() const {
  if (!node_.IsScalar()) fail("expected a number, got " + describe(node_));
  const std::string& text = node_.Scalar();
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value))
    fail("expected a finite number, got " + describe(node_));
  return value;
}

double YamlEntry::positive() const {
  const double value = number();
  if (value <= 0.0) fail("expected a positive number, got " + describe(node_));
  return value;
}

int YamlEntry::integer() const {
  const double value = number();
  if (value != std::floor(value) || std::abs(value) > 2e9)
    fail("expected an integer, got " + describe(node_));
  return static_cast<int>(value);
}

int YamlEntry::integerAtLeast(int minimum) const {
  const int value = integer();
  if (value < minimum)
    fail("expected an integer >= " + std::to_string(minimum) + ", got " + describe(node_));
  return value;
}

bool YamlEntry::boolean() const {
  const std::string s = node_.IsScalar() ? node_.Scalar() : "";
  if (s == "true" || s == "yes" || s == "on") return true;
  if (s == "false" || s == "no" || s == "off") return false;
  fail("expected true or false, got " + describe(node_));
}

std::string YamlEntry::text() const {
  if (!node_.IsScalar()) fail("expected a string, got " + describe(node_));
  return node_.Scalar();
}

std::string YamlEntry::choice(std::initializer_list<const char*> words) const {
  const std::string value = node_.IsScalar() ? node_.Scalar() : "";
  for (const char* w : words)
    if (value == w) return value;
  fail("expected one of: " + joinWords(words) + "; got " + describe(node_));
}

Eigen::Vector3d YamlEntry::vector3() const {
  if (!node_.IsSequence() || node_.size() != 3)
    fail("expected a list of 3 numbers, got " + describe(node_));
  Eigen::Vector3d v;
  for (size_t i = 0; i < 3; ++i) v[i] = (*this)[i].number();
  return v;
}

std::vector<int> YamlEntry::integers() const {
  std::vector<int> out(size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = (*this)[i].integer();
  return out;
}

double YamlEntry::number(const char* key, double fallback) const {
  return has(key) ? (*this)[key].number() : fallback;
}

double YamlEntry::positive(const char* key, double fallback) const {
  return has(key) ? (*this)[key].positive() : fallback;
}

int YamlEntry::integerAtLeast(const char* key, int minimum, int fallback) const {
  return has(key) ? (*this)[key].integerAtLeast(minimum) : fallback;
}

bool YamlEntry::boolean(const char* key, bool fallback) const {
  return has(key) ? (*this)[key].boolean() : fallback;
}

std::optional<YamlEntry> renamedKey(const YamlEntry& spec, const char* name, const char* oldName,
                                    std::vector<std::string>& notes) {
  const std::string newName = name;
  if (oldName && spec.has(oldName)) {
    const YamlEntry old = spec[oldName];
    if (spec.has(name))
      old.fail("is the deprecated name of " + newName + "; give " + newName + " only");
    notes.push_back(old.where() + ": " + old.path() + " is deprecated: write " + newName +
                    " (the same meaning)");
    return old;
  }
  if (spec.has(name)) return spec[name];
  return std::nullopt;
}

double stressUnit(const YamlEntry& unit) {
  const std::string name = unit.choice({"Pa", "kPa", "MPa"});
  return name == "Pa" ? 1.0 : name == "kPa" ? 1e3 : 1e6;
}

}  // namespace tt
