#pragma once
// Boundary tags per node from an index file ("Adamss: Advanced Anisotropic Mass-Spring System",
// Sec. 2.6): one line "node tags" per tagged node, the node a 0-based index and the tags
// letters: x, y, z fix that axis of the node (its position stays the rest one), X, Y, Z control
// it (it follows a prescribed motion). E.g. "12 xy" moves only along z, "40 xyZ" is driven
// along z and held in x and y. Blank lines and everything after '#' are skipped; a node on
// several lines gets all their tags.
#include <cstdint>
#include <string>
#include <vector>

namespace tt {

struct NodeTagLine {
  int node = 0;
  std::uint8_t fixed = 0;       // kFixedX | kFixedY | kFixedZ bits
  std::uint8_t controlled = 0;  // the same bits, for the controlled axes
  long line = 0;                // in the file, for messages
};

// Throws InputError "FILE:LINE: ..." for a line that is not "node tags", a node outside
// [0, numNodes - 1], an unknown letter or an axis of a node both fixed and controlled (on one
// line or on two).
std::vector<NodeTagLine> readNodeTagFile(const std::string& path, int numNodes);

}  // namespace tt
