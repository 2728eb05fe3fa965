#include "common/work_precision/csv.h"

#include <algorithm>

namespace tt {
namespace work_precision {

std::string csvText(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

void writeRunRow(FILE* csv, const std::string& problem, const std::string& model,
                 const std::string& integrator, const std::string& parameterName,
                 double parameter, const RunResult& r) {
  std::fprintf(csv, "%s,%s,%s,%.6g,%.6g,%.6g,%.6g,%ld,%ld,%ld,%ld,%d,%s,%.6g,%d,%s\n",
               problem.c_str(), model.c_str(), integrator.c_str(), parameter, r.errors.error,
               r.cpu, r.wall, r.steps, r.rejected, r.newton, r.linear, r.stable ? 1 : 0,
               parameterName.c_str(), r.errors.discrete, r.tets, csvText(r.errors.note).c_str());
  std::fflush(csv);
}

}  // namespace work_precision
}  // namespace tt
