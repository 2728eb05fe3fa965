#pragma once
// Running a benchmark or tool program from a test.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace tt {
namespace test {

// Runs the shell command with its stdout and stderr in `log`; the program's exit code, or -1
// when it did not exit (a signal).
inline int exitCodeOf(const std::string& command, const std::filesystem::path& log) {
  const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace test
}  // namespace tt
