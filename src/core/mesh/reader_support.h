#pragma once
// Bookkeeping shared by the volume-mesh readers: file node ids to indices, counts of
// ignored element types, and the common last step (orientation, surface, defaults).
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "tissue_trainer/core/mesh/mesh_io.h"
#include "text_scanner.h"

namespace tt {
namespace meshio {

// Maps the node ids of a file (any integers, possibly sparse) to 0..n-1 in reading order.
class NodeIds {
 public:
  // Fails at the scanner's line if the id was already defined.
  int add(const Scanner& s, long long id);
  // Fails at the scanner's line if the id is unknown.
  int find(const Scanner& s, long long id) const;
  int size() const { return static_cast<int>(index_.size()); }

 private:
  std::unordered_map<long long, int> index_;
};

// Counts elements that were skipped, by a numeric type code, for one note line.
class IgnoredElements {
 public:
  explicit IgnoredElements(std::string codeLabel) : codeLabel_(std::move(codeLabel)) {}
  void add(int code, const std::string& plural) {
    auto& entry = counts_[code];
    entry.first = plural;
    ++entry.second;
  }
  bool empty() const { return counts_.empty(); }
  // "ignored 860 triangles (type 2), 71 lines (type 1)": largest count first.
  std::string note() const;

 private:
  std::string codeLabel_;
  std::map<int, std::pair<std::string, long>> counts_;
};

// Gmsh element type -> number of nodes (0 if unknown) and a plural name.
int gmshNodesPerElement(int type);
std::string gmshTypeName(int type);
// VTK cell type -> plural name.
std::string vtkTypeName(int type);

// Adds VTK cell c of the given type and k nodes (already range-checked) to the mesh: tets
// (10), hexes (12) and voxels (11, reordered to hex order); other types are counted in
// `ignored`. Fails at `line` for a wrong node count or repeated nodes.
void addVtkCell(const Scanner& s, long line, std::size_t c, int type, const int* nodes, int k,
                Mesh& mesh, IgnoredElements& ignored);

// Appends rest positions; grows as it reads (never reserves from a declared count).
struct NodeBuffer {
  std::vector<double> xyz;
  void push(double x, double y, double z) {
    xyz.push_back(x);
    xyz.push_back(y);
    xyz.push_back(z);
  }
  Eigen::Matrix3Xd matrix() const;
};

// The common last step: requires at least one tet or hex, reorders inverted tets (note),
// adds the ignored-elements note, extracts the surface and fills defaults.
void finishVolumeMesh(Mesh& mesh, const std::string& path, const IgnoredElements& ignored,
                      ReadNotes* notes);

void addNote(ReadNotes* notes, const std::string& line);

}  // namespace meshio
}  // namespace tt
