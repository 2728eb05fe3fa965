#include "command_line.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace tt {
namespace tools {

CommandLine::CommandLine(int argc, char** argv, std::string usage)
    : usage_(std::move(usage)), args_(argv + 1, argv + argc), used_(args_.size(), false) {
  const std::string program = argc > 0 ? argv[0] : "tool";
  tool_ = program.substr(program.find_last_of('/') + 1);
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
  bool found = false;
  for (std::size_t k = 0; k < args_.size(); ++k) {
    if (args_[k] != name) continue;
    used_[k] = true;
    found = true;
  }
  return found;
}

const std::string* CommandLine::valueOf(const std::string& name) {
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
    fail((option ? "unknown option '" : "unexpected argument '") + args_[k] + "'");
  }
}

}  // namespace tools
}  // namespace tt
