#pragma once
// Reading the benchmarks' CSV files in tests (plain comma-separated fields, no quoting).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace tt {
namespace test {

inline std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

inline std::vector<std::vector<std::string>> readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(splitCsv(line));
  return rows;
}

}  // namespace test
}  // namespace tt
