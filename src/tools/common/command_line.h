// The command line of the tools and benchmarks, in one style:
//   TOOL [--quick] [--repeats N] [--name VALUE ...] [POSITIONAL ...]
// Each program states its usage once; an unknown option, a missing value or a value of the
// wrong kind is one line on stderr naming the option and what was expected, then exit 2;
// --help prints the usage and exits 0.
#pragma once

#include <string>
#include <vector>

namespace tt {
namespace tools {

class CommandLine {
 public:
  // `usage` is the text after "usage: ": the program's name and its options.
  CommandLine(int argc, char** argv, std::string usage);
  // The same for the arguments after a subcommand: `tool` is e.g. "bench_adamss volume".
  CommandLine(std::string tool, std::vector<std::string> args, std::string usage);

  // True when the flag was given (e.g. "--quick").
  bool flag(const std::string& name);
  // The value after `name`, or `fallback` when the option is absent.
  std::string text(const std::string& name, const std::string& fallback);
  // The values after every occurrence of a repeatable option, in order (none: empty).
  std::vector<std::string> texts(const std::string& name);
  int positiveInteger(const std::string& name, int fallback);
  double positiveNumber(const std::string& name, double fallback);
  // "a,b,c" after `name` as {a, b, c}; `fallback` when absent.
  std::vector<std::string> list(const std::string& name, const std::vector<std::string>& fallback);
  // The arguments that are not options, in order; at most `most` of them. Ask for the
  // options first: an option's value is not positional once the option was asked for.
  std::vector<std::string> positional(std::size_t most);

  // Call after every option was asked for: anything not asked for is an error (exit 2).
  void finish();

  // One error line "TOOL: message (usage: ...)" and exit 2.
  [[noreturn]] void fail(const std::string& message) const;

 private:
  const std::string* valueOf(const std::string& name);

  std::string tool_;
  std::string usage_;
  std::vector<std::string> known_;  // the options asked for, for the error on an unknown one
  std::vector<std::string> args_;
  std::vector<bool> used_;
};

}  // namespace tools
}  // namespace tt
