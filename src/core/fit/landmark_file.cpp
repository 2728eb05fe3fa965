// The targets file of a landmark fit (docs/cli.md, "fit").
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/fit/landmark_fit.h"

namespace tt {

namespace {

bool parseNumber(const std::string& text, double& value) {
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(value);
}

}  // namespace

std::vector<Landmark> readLandmarks(const std::string& path, const Mesh& mesh) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open the targets file");
  std::vector<Landmark> landmarks;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    const auto fail = [&](const std::string& what) { throw InputError(path, number, what); };
    std::istringstream words(line.substr(0, line.find('#')));
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    if (tokens.empty()) continue;
    // `N x y z` or `T b0 b1 b2 b3 x y z`, optionally led by the word `node` or `tet`.
    const bool named = tokens[0] == "node" || tokens[0] == "tet";
    if (named) {
      if (tokens.size() != (tokens[0] == "node" ? 5u : 9u))
        fail("'" + tokens[0] + "' expects " + (tokens[0] == "node" ? "4" : "8") + " numbers, got " +
             std::to_string(tokens.size() - 1));
      tokens.erase(tokens.begin());
    } else if (tokens.size() != 4 && tokens.size() != 8) {
      fail("expected 'N x y z' (node index and target) or 'T b0 b1 b2 b3 x y z' (tet index, "
           "barycentric weights and target), got " + std::to_string(tokens.size()) + " values");
    }
    const bool isNode = tokens.size() == 4;
    const size_t expected = tokens.size();
    std::vector<double> v(expected);
    for (size_t k = 0; k < expected; ++k)
      if (!parseNumber(tokens[k], v[k])) fail("expected a finite number, got '" + tokens[k] + "'");
    const int count = isNode ? mesh.numNodes() : mesh.numTets();
    const double index = v[0];
    if (index != std::floor(index) || index < 0 || index >= count)
      fail(std::string(isNode ? "node" : "tet") + " index " + tokens[0] + " out of range [0, " +
           std::to_string(count - 1) + "]");
    Landmark l;
    // The file's numbers (mesh.numbering); a tet keeps its local node order, so the weights hold.
    const int i = isNode ? mesh.numbering.nodeFromFile(static_cast<int>(index))
                         : mesh.numbering.tetFromFile(static_cast<int>(index));
    if (isNode) {
      l.nodes = {i, i, i, i};
      l.weights = Eigen::Vector4d(1, 0, 0, 0);
    } else {
      l.nodes = mesh.tets[i];
      l.weights = Eigen::Vector4d(v[1], v[2], v[3], v[4]);
      if (l.weights.minCoeff() < 0.0) fail("barycentric weights must not be negative");
      if (std::abs(l.weights.sum() - 1.0) > 1e-6)
        fail("barycentric weights must sum to 1 (sum " + std::to_string(l.weights.sum()) + ")");
    }
    l.target = Eigen::Vector3d(v[expected - 3], v[expected - 2], v[expected - 1]);
    landmarks.push_back(l);
  }
  if (landmarks.empty()) throw InputError(path, 0, "no landmarks in the targets file");
  return landmarks;
}

}  // namespace tt
