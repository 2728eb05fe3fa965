#include "tissue_trainer/core/mesh/node_tags.h"

#include "text_scanner.h"
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

std::vector<NodeTagLine> readNodeTagFile(const std::string& path, int numNodes) {
  const std::string text = meshio::loadTextFile(path);
  meshio::Scanner scan(path, text, '#');
  std::vector<NodeTagLine> lines;
  // A node on several lines gets all their tags, so an axis fixed on one line and controlled on
  // another is the same contradiction as "xX" on one line.
  std::vector<std::uint8_t> fixedSoFar(numNodes, 0), controlledSoFar(numNodes, 0);
  while (scan.nextLine()) {
    scan.requireTokens(2, "'node tags' such as '12 xy' or '40 xyZ'");
    NodeTagLine tag;
    tag.line = scan.lineNo();
    tag.node = static_cast<int>(scan.toInt(scan[0], 0, numNodes - 1, "a node index"));
    for (char c : scan[1]) {
      const bool control = c >= 'X' && c <= 'Z';
      const char axis = control ? static_cast<char>(c - 'X' + 'x') : c;
      if (axis < 'x' || axis > 'z')
        scan.fail("unknown tag '" + std::string(1, c) +
                  "' (expected x, y, z to fix an axis and X, Y, Z to control it)");
      (control ? tag.controlled : tag.fixed) |= static_cast<std::uint8_t>(1u << (axis - 'x'));
    }
    if (tag.fixed & tag.controlled)
      scan.fail("an axis both fixed and controlled in '" + std::string(scan[1]) + "'");
    std::uint8_t& fixed = fixedSoFar[tag.node];
    std::uint8_t& controlled = controlledSoFar[tag.node];
    if ((fixed & tag.controlled) || (controlled & tag.fixed))
      scan.fail("node " + std::to_string(tag.node) + " has an axis fixed on one line and " +
                "controlled on another");
    fixed |= tag.fixed;
    controlled |= tag.controlled;
    lines.push_back(tag);
  }
  return lines;
}

}  // namespace tt
