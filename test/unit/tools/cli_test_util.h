#pragma once
// Runs tissue_cli (TT_CLI_PATH, known to the builds that build it) and captures its exit
// code, stdout and stderr.
#ifdef TT_CLI_PATH
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace tt {
namespace testutil {

struct CliResult {
  int exitCode;
  std::string out, err;
};

// `prefix` goes before the program (a wrapper such as "timeout -s INT 1 ").
inline CliResult runCli(const std::string& arguments, const std::string& prefix = "") {
  const std::filesystem::path errFile =
      std::filesystem::temp_directory_path() / "tt_cli_stderr.txt";
  const std::string command =
      prefix + std::string(TT_CLI_PATH) + " " + arguments + " 2>" + errFile.string();
  CliResult r;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(errFile);
  r.err.assign(std::istreambuf_iterator<char>(err), {});
  return r;
}

}  // namespace testutil
}  // namespace tt
#endif
