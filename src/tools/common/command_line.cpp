#include "command_line.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace tt {
namespace tools {

namespace {

std::string baseName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

}  // namespace

CommandLine::CommandLine(int argc, char** argv, std::string usage)
    : CommandLine(baseName(argc > 0 ? argv[0] : "tool"),
                  std::vector<std::string>(argv + std::min(argc, 1), argv + argc),
                  std::move(usage)) {}

CommandLine::CommandLine(std::string tool, std::vector<std::string> args, std::string usage)
    : tool_(std::move(tool)), usage_(std::move(usage)), args_(std::move(args)),
      used_(args_.size(), false) {
  for (const std::string& arg : args_) {
    if (arg == "--help" || arg == "-h") {
      std::printf("usage: %s\n", usage_.c_str());
      std::exit(0);
    }
  }
}

void CommandLine::fail(const std::string& message) const {
  std::fprintf(stderr, "%s: %s (usage: %s)\n", tool_.c_str(), message.c_str(), usage_.c_str());
  std::exit(2);
}

bool CommandLine::flag(const std::string& name) {
  known_.push_back(name);
  bool found = false;
  for (std::size_t k = 0; k < args_.size(); ++k) {
    if (args_[k] != name) continue;
    used_[k] = true;
    found = true;
  }
  return found;
}

const std::string* CommandLine::valueOf(const std::string& name) {
  known_.push_back(name);
  const std::string* value = nullptr;
  for (std::size_t k = 0; k < args_.size(); ++k) {
    if (args_[k] != name) continue;
    if (k + 1 >= args_.size()) fail(name + " expects a value");
    used_[k] = used_[k + 1] = true;
    value = &args_[k + 1];
  }
  return value;
}

std::string CommandLine::text(const std::string& name, const std::string& fallback) {
  const std::string* value = valueOf(name);
  return value ? *value : fallback;
}

std::vector<std::string> CommandLine::texts(const std::string& name) {
  known_.push_back(name);
  std::vector<std::string> values;
  for (std::size_t k = 0; k < args_.size(); ++k) {
    if (args_[k] != name || used_[k]) continue;
    if (k + 1 >= args_.size()) fail(name + " expects a value");
    used_[k] = used_[k + 1] = true;
    values.push_back(args_[k + 1]);
  }
  return values;
}

int CommandLine::positiveInteger(const std::string& name, int fallback) {
  const std::string* value = valueOf(name);
  if (!value) return fallback;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(value->c_str(), &end, 10);
  if (value->empty() || *end != '\0' || errno == ERANGE || v < 1 || v > 100000000)
    fail(name + " expects a positive whole number, got '" + *value + "'");
  return static_cast<int>(v);
}

double CommandLine::positiveNumber(const std::string& name, double fallback) {
  const std::string* value = valueOf(name);
  if (!value) return fallback;
  char* end = nullptr;
  const double v = std::strtod(value->c_str(), &end);
  if (value->empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0))
    fail(name + " expects a positive number, got '" + *value + "'");
  return v;
}

std::vector<std::string> CommandLine::list(const std::string& name,
                                           const std::vector<std::string>& fallback) {
  const std::string* value = valueOf(name);
  if (!value) return fallback;
  std::vector<std::string> items;
  std::stringstream in(*value);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  if (items.empty()) fail(name + " expects a comma-separated list, got '" + *value + "'");
  return items;
}

std::vector<std::string> CommandLine::positional(std::size_t most) {
  std::vector<std::string> found;
  for (std::size_t k = 0; k < args_.size(); ++k) {
    if (used_[k] || (args_[k].size() > 1 && args_[k][0] == '-')) continue;
    used_[k] = true;
    found.push_back(args_[k]);
  }
  if (found.size() > most)
    fail("expected at most " + std::to_string(most) + " arguments, got '" + found[most] + "'");
  return found;
}

void CommandLine::finish() {
  for (std::size_t k = 0; k < args_.size(); ++k) {
    if (used_[k]) continue;
    const bool option = args_[k].size() > 1 && args_[k][0] == '-';
    if (!option) fail("unexpected argument '" + args_[k] + "', expected options only");
    std::string expected;
    for (std::size_t n = 0; n < known_.size(); ++n)
      if (std::find(known_.begin(), known_.begin() + n, known_[n]) == known_.begin() + n)
        expected += known_[n] + ", ";
    fail("unknown option '" + args_[k] + "', expected " +
         (expected.empty() ? "none" : "one of " + expected.substr(0, expected.size() - 2)));
  }
}

}  // namespace tools
}  // namespace tt
