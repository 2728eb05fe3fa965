// Gmsh .msh reader: v1 ($NOD/$ELM), v2 ASCII and v4 ASCII (4.0 and 4.1 layouts), the
// version taken from the content. Sections other than nodes and elements are skipped.
#include <cmath>
#include <strings.h>

#include "reader_support.h"

namespace tt {

namespace {

using meshio::Scanner;

constexpr long long kMaxTags = 1000;

bool isSectionLine(const Scanner& s) { return s[0].size() > 0 && s[0][0] == '$'; }

struct GmshState {
  GmshState(const std::string& path, std::string content)
      : text(std::move(content)), scanner(path, text) {}
  std::string text;
  Scanner scanner;
  int major = 0;         // 1, 2 or 4; 0 until a format is known
  bool layout41 = false;  // v4.1 node and element blocks (else 4.0)
  bool haveNodes = false, haveElements = false;
  meshio::NodeIds ids;
  meshio::NodeBuffer nodes;
  meshio::IgnoredElements ignored{"type"};
  Mesh mesh;
};

// Reads the next data line of a section that must hold `count` items, failing with a clear
// message when the section ends early.
void requireDataLine(Scanner& s, const std::string& item, long long index, long long count) {
  s.requireLine(item + " " + std::to_string(index + 1) + " of " + std::to_string(count));
  if (isSectionLine(s))
    s.fail("expected " + std::to_string(count) + " " + item + "s, section ended after " +
           std::to_string(index) + " at " + meshio::quoted(s[0]));
}

void requireEnd(Scanner& s, const std::string& endTag, const std::string& after) {
  s.requireLine(endTag);
  if (s[0] != endTag || s.size() != 1)
    s.fail("expected " + endTag + " after " + after + ", got " + meshio::quoted(s.line()));
}

long long readCountLine(Scanner& s, const std::string& what, const std::string& items) {
  s.requireLine(what);
  s.requireTokens(1, what);
  const long long n = s.toInt(s[0], what);
  s.checkCount(n, items);
  return n;
}

void readNode(GmshState& g, std::string_view idToken, const std::string_view* xyz) {
  Scanner& s = g.scanner;
  const long long id = s.toInt(idToken, "node id");
  const std::string what = "3 coordinates after node id " + std::to_string(id);
  const double x = s.toDouble(xyz[0], what), y = s.toDouble(xyz[1], what),
               z = s.toDouble(xyz[2], what);
  g.ids.add(s, id);
  g.nodes.push(x, y, z);
}

// One element of Gmsh type `type` whose node ids are the tokens nodeTokens[0..n).
void addElement(GmshState& g, int type, const std::string_view* nodeTokens, int n) {
  Scanner& s = g.scanner;
  const bool tet = type == 4, hex = type == 5;
  if (!tet && !hex) {
    g.ignored.add(type, meshio::gmshTypeName(type));
    return;
  }
  const int expected = tet ? 4 : 8;
  if (n != expected)
    s.fail("expected " + std::to_string(expected) + " nodes for a " +
           (tet ? "tetrahedron" : "hexahedron") + ", got " + std::to_string(n));
  long long raw[8];
  for (int i = 0; i < n; ++i) raw[i] = s.toInt(nodeTokens[i], "node id of an element");
  meshio::checkDistinct(s, raw, n);
  int index[8];
  for (int i = 0; i < n; ++i) index[i] = g.ids.find(s, raw[i]);
  if (tet) g.mesh.tets.push_back({index[0], index[1], index[2], index[3]});
  else g.mesh.hexes.push_back({index[0], index[1], index[2], index[3], index[4], index[5], index[6], index[7]});
}

void readFormat(GmshState& g) {
  Scanner& s = g.scanner;
  s.requireLine("version, file type and data size");
  s.requireTokens(3, "version, file type and data size");
  const double version = s.toDouble(s[0], "a format version");
  const long long fileType = s.toInt(s[1], "file type");
  if (fileType != 0) s.fail("expected file type 0 (ASCII), got " + std::to_string(fileType) + " (binary is not supported)");
  if (version >= 2.0 && version < 3.0) {
    g.major = 2;
  } else if (version >= 4.0 && version < 5.0) {
    g.major = 4;
    g.layout41 = version >= 4.05;
  } else {
    s.fail("expected format version 2.x or 4.x, got " + meshio::quoted(s[0]));
  }
  requireEnd(s, "$EndMeshFormat", "the format line");
}

void readNodesV1V2(GmshState& g, const std::string& endTag) {
  Scanner& s = g.scanner;
  const long long n = readCountLine(s, "node count", "nodes");
  for (long long i = 0; i < n; ++i) {
    requireDataLine(s, "node", i, n);
    if (s.size() != 4) {
      s.fail("expected node id and 3 coordinates, got " + std::to_string(s.size()) + " values");
    }
    const std::string_view xyz[3] = {s[1], s[2], s[3]};
    readNode(g, s[0], xyz);
  }
  requireEnd(s, endTag, std::to_string(n) + " nodes");
}

void readElementsV1V2(GmshState& g, const std::string& endTag) {
  Scanner& s = g.scanner;
  const long long n = readCountLine(s, "element count", "elements");
  std::vector<std::string_view> tokens;
  for (long long i = 0; i < n; ++i) {
    requireDataLine(s, "element", i, n);
    if (g.major == 1) {
      // number type physical elementary node-count nodes...
      s.requireAtLeast(5, "element number, type, 2 region tags and node count");
      s.toInt(s[0], "element number");
      const int type = static_cast<int>(s.toInt(s[1], 1, 1000, "element type"));
      s.toInt(s[2], "physical region");
      s.toInt(s[3], "elementary region");
      const int count = static_cast<int>(s.toInt(s[4], 1, 1000, "node count"));
      s.requireTokens(5 + count, "element with " + std::to_string(count) + " nodes");
      tokens.assign(s.tokens() + 5, s.tokens() + 5 + count);
      addElement(g, type, tokens.data(), count);
    } else {
      // number type tag-count tags... nodes...
      s.requireAtLeast(3, "element number, type and tag count");
      s.toInt(s[0], "element number");
      const int type = static_cast<int>(s.toInt(s[1], 1, 1000, "element type"));
      const int count = meshio::gmshNodesPerElement(type);
      if (count == 0) s.fail("expected a known element type, got " + std::to_string(type));
      const int tags = static_cast<int>(s.toInt(s[2], 0, kMaxTags, "tag count"));
      s.requireTokens(3 + tags + count, "element of type " + std::to_string(type) + " with " +
                                            std::to_string(tags) + " tags and " +
                                            std::to_string(count) + " nodes");
      for (int k = 0; k < tags; ++k) s.toInt(s[3 + k], "element tag");
      tokens.assign(s.tokens() + 3 + tags, s.tokens() + 3 + tags + count);
      addElement(g, type, tokens.data(), count);
    }
  }
  requireEnd(s, endTag, std::to_string(n) + " elements");
}

void readNodesV4(GmshState& g) {
  Scanner& s = g.scanner;
  s.requireLine("node block header");
  s.requireTokens(g.layout41 ? 4 : 2, "entity block count and node count");
  const long headerLine = s.lineNo();
  const long long blocks = s.toInt(s[0], "entity block count");
  const long long total = s.toInt(s[1], "node count");
  s.checkCount(blocks, "node blocks");
  s.checkCount(total, "nodes");
  long long read = 0;
  for (long long b = 0; b < blocks; ++b) {
    requireDataLine(s, "node block", b, blocks);
    s.requireTokens(4, "node block header (entity dimension, entity tag, parametric, count)");
    const int dim = static_cast<int>(s.toInt(s[g.layout41 ? 0 : 1], 0, 3, "entity dimension"));
    const bool parametric = s.toInt(s[2], 0, 1, "parametric flag") == 1;
    const long long count = s.toInt(s[3], "node count of the block");
    s.checkCount(count, "nodes in the block");
    if (count > total - read) s.fail("expected at most " + std::to_string(total - read) + " more nodes, block declares " + std::to_string(count));
    const std::size_t values = 3 + (parametric ? dim : 0);
    if (g.layout41) {
      std::vector<long long> tags;  // grows as read: count was checked against the file size
      for (long long i = 0; i < count; ++i) {
        requireDataLine(s, "node tag", i, count);
        s.requireTokens(1, "one node tag");
        tags.push_back(s.toInt(s[0], "node tag"));
      }
      for (long long i = 0; i < count; ++i) {
        requireDataLine(s, "node coordinate line", i, count);
        s.requireTokens(values, std::to_string(values) + " coordinates of node " + std::to_string(tags[i]));
        const std::string what = "3 coordinates of node id " + std::to_string(tags[i]);
        const double x = s.toDouble(s[0], what), y = s.toDouble(s[1], what), z = s.toDouble(s[2], what);
        g.ids.add(s, tags[i]);
        g.nodes.push(x, y, z);
      }
    } else {
      for (long long i = 0; i < count; ++i) {
        requireDataLine(s, "node", i, count);
        s.requireTokens(1 + values, "node tag and " + std::to_string(values) + " coordinates");
        const std::string_view xyz[3] = {s[1], s[2], s[3]};
        readNode(g, s[0], xyz);
      }
    }
    read += count;
  }
  if (read != total) s.failAt(headerLine, "expected " + std::to_string(total) + " nodes in the blocks, got " + std::to_string(read));
  requireEnd(s, "$EndNodes", std::to_string(total) + " nodes");
}

void readElementsV4(GmshState& g) {
  Scanner& s = g.scanner;
  s.requireLine("element block header");
  s.requireTokens(g.layout41 ? 4 : 2, "entity block count and element count");
  const long headerLine = s.lineNo();
  const long long blocks = s.toInt(s[0], "entity block count");
  const long long total = s.toInt(s[1], "element count");
  s.checkCount(blocks, "element blocks");
  s.checkCount(total, "elements");
  long long read = 0;
  std::vector<std::string_view> tokens;
  for (long long b = 0; b < blocks; ++b) {
    requireDataLine(s, "element block", b, blocks);
    s.requireTokens(4, "element block header (entity dimension, entity tag, type, count)");
    const int type = static_cast<int>(s.toInt(s[2], 1, 1000, "element type"));
    const int nodes = meshio::gmshNodesPerElement(type);
    if (nodes == 0) s.fail("expected a known element type, got " + std::to_string(type));
    const long long count = s.toInt(s[3], "element count of the block");
    s.checkCount(count, "elements in the block");
    if (count > total - read) s.fail("expected at most " + std::to_string(total - read) + " more elements, block declares " + std::to_string(count));
    for (long long i = 0; i < count; ++i) {
      requireDataLine(s, "element", i, count);
      s.requireTokens(1 + nodes, "element tag and " + std::to_string(nodes) + " node tags");
      s.toInt(s[0], "element tag");
      tokens.assign(s.tokens() + 1, s.tokens() + 1 + nodes);
      addElement(g, type, tokens.data(), nodes);
    }
    read += count;
  }
  if (read != total) s.failAt(headerLine, "expected " + std::to_string(total) + " elements in the blocks, got " + std::to_string(read));
  requireEnd(s, "$EndElements", std::to_string(total) + " elements");
}

void skipSection(Scanner& s, std::string_view tag) {
  const std::string name(tag.substr(1));
  const std::string endTag = "$End" + name;
  while (s.nextLine())
    if (s[0].size() == endTag.size() && strncasecmp(s[0].data(), endTag.data(), endTag.size()) == 0) return;
  s.fail("expected " + endTag + " before the end of the file");
}

}  // namespace

Mesh readGmsh(const std::string& path, ReadNotes* notes) {
  GmshState g(path, meshio::loadTextFile(path));
  Scanner& s = g.scanner;
  while (s.nextLine()) {
    const std::string_view tag = s[0];
    if (!isSectionLine(s) || s.size() != 1)
      s.fail("expected a section header such as $MeshFormat, $Nodes or $NOD, got " + meshio::quoted(s.line()));
    const bool nodesTag = tag == "$Nodes" || tag == "$NOD";
    const bool elementsTag = tag == "$Elements" || tag == "$ELM";
    if (tag == "$MeshFormat") {
      if (g.major != 0) s.fail("expected one $MeshFormat section before the nodes, got another");
      readFormat(g);
    } else if (nodesTag) {
      if (g.haveNodes) s.fail("expected one node section, got a second one");
      if (tag == "$NOD") {
        if (g.major == 0) g.major = 1;
        if (g.major != 1) s.fail("expected $Nodes in a version " + std::to_string(g.major) + " file, got $NOD");
      } else if (g.major == 0) {
        s.fail("expected $MeshFormat before $Nodes");
      }
      if (g.major == 4) readNodesV4(g);
      else readNodesV1V2(g, g.major == 1 ? "$ENDNOD" : "$EndNodes");
      g.haveNodes = true;
    } else if (elementsTag) {
      if (!g.haveNodes) s.fail("expected the node section before " + std::string(tag));
      if (g.haveElements) s.fail("expected one element section, got a second one");
      if ((tag == "$ELM") != (g.major == 1)) s.fail("expected " + std::string(g.major == 1 ? "$ELM" : "$Elements") + ", got " + std::string(tag));
      if (g.major == 4) readElementsV4(g);
      else readElementsV1V2(g, g.major == 1 ? "$ENDELM" : "$EndElements");
      g.haveElements = true;
    } else {
      skipSection(s, tag);
    }
  }
  if (!g.haveNodes || !g.haveElements)
    s.fail(std::string("expected ") + (g.haveNodes ? "an element" : "a node") + " section before the end of the file");
  g.mesh.rest = g.nodes.matrix();
  meshio::finishVolumeMesh(g.mesh, path, g.ignored, notes);
  return std::move(g.mesh);
}

}  // namespace tt
