// TetGen .node/.ele reader. Point numbers start at 0 or 1 (taken from the first point) and
// must be consecutive; element node indices use the same numbering. Attributes and boundary
// markers are read and ignored; 10-node tets keep their 4 corner nodes.
#include "reader_support.h"

namespace tt {

namespace {

using meshio::Scanner;

std::string stripTetgenExtension(const std::string& path) {
  for (const char* ext : {".node", ".ele"}) {
    const std::string e(ext);
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0)
      return path.substr(0, path.size() - e.size());
  }
  throw InputError(path, 0, "expected a TetGen path ending in .node or .ele");
}

struct TetgenNodes {
  meshio::NodeBuffer xyz;
  long long firstIndex = 0;
  long long count = 0;
  long long attributes = 0;
};

TetgenNodes readNodeFile(const std::string& path) {
  const std::string text = meshio::loadTextFile(path);
  Scanner s(path, text, '#');
  s.requireLine("node header (point count, dimension, attribute count, marker flag)");
  s.requireTokens(4, "node header: point count, dimension, attribute count, marker flag");
  TetgenNodes nodes;
  nodes.count = s.toInt(s[0], "point count");
  s.toInt(s[1], 3, 3, "dimension");
  nodes.attributes = s.toInt(s[2], 0, 1000, "attribute count");
  const long long markers = s.toInt(s[3], 0, 1, "boundary marker flag");
  s.checkCount(nodes.count, "points");
  const std::size_t values = static_cast<std::size_t>(4 + nodes.attributes + markers);
  for (long long i = 0; i < nodes.count; ++i) {
    s.requireLine("point " + std::to_string(i + 1) + " of " + std::to_string(nodes.count));
    s.requireTokens(values, "point number, 3 coordinates" +
                                std::string(nodes.attributes ? ", attributes" : "") +
                                (markers ? ", boundary marker" : ""));
    if (i == 0) nodes.firstIndex = s.toInt(s[0], 0, 1, "first point number (0 or 1)");
    else s.toInt(s[0], nodes.firstIndex + i, nodes.firstIndex + i, "consecutive point number");
    const std::string what = "3 coordinates after point " + std::string(s[0]);
    const double x = s.toDouble(s[1], what), y = s.toDouble(s[2], what), z = s.toDouble(s[3], what);
    for (std::size_t k = 4; k < values; ++k) s.toDouble(s[k], "attribute or marker");
    nodes.xyz.push(x, y, z);
  }
  if (s.nextLine())
    s.fail("expected " + std::to_string(nodes.count) + " points, got more lines: " + meshio::quoted(s.line()));
  return nodes;
}

void readEleFile(const std::string& path, const TetgenNodes& nodes, Mesh& mesh, ReadNotes* notes) {
  const std::string text = meshio::loadTextFile(path);
  Scanner s(path, text, '#');
  s.requireLine("element header (tet count, nodes per tet, region flag)");
  s.requireTokens(3, "element header: tet count, nodes per tet, region flag");
  const long long count = s.toInt(s[0], "tet count");
  const long long perTet = s.toInt(s[1], 4, 10, "nodes per tet (4 or 10)");
  if (perTet != 4 && perTet != 10) s.fail("expected nodes per tet 4 or 10, got " + std::to_string(perTet));
  const long long region = s.toInt(s[2], 0, 1, "region attribute flag");
  s.checkCount(count, "tets");
  const long long lo = nodes.firstIndex, hi = nodes.firstIndex + nodes.count - 1;
  long long raw[10];
  for (long long i = 0; i < count; ++i) {
    s.requireLine("tet " + std::to_string(i + 1) + " of " + std::to_string(count));
    s.requireTokens(static_cast<std::size_t>(1 + perTet + region),
                    "tet number, " + std::to_string(perTet) + " node indices" + (region ? ", region" : ""));
    s.toInt(s[0], "tet number");
    for (int k = 0; k < perTet; ++k) raw[k] = s.toInt(s[1 + k], lo, hi, "node index");
    meshio::checkDistinct(s, raw, static_cast<int>(perTet));
    if (region) s.toDouble(s[1 + perTet], "region attribute");
    mesh.tets.push_back({static_cast<int>(raw[0] - lo), static_cast<int>(raw[1] - lo),
                         static_cast<int>(raw[2] - lo), static_cast<int>(raw[3] - lo)});
  }
  if (s.nextLine())
    s.fail("expected " + std::to_string(count) + " tets, got more lines: " + meshio::quoted(s.line()));
  if (perTet == 10) meshio::addNote(notes, "used the 4 corner nodes of " + std::to_string(count) + " 10-node tets");
  if (region) meshio::addNote(notes, "ignored the region attribute of " + std::to_string(count) + " tets");
}

}  // namespace

Mesh readTetgen(const std::string& path, ReadNotes* notes) {
  const std::string base = stripTetgenExtension(path);
  const TetgenNodes nodes = readNodeFile(base + ".node");
  if (nodes.attributes > 0)
    meshio::addNote(notes, "ignored " + std::to_string(nodes.attributes) + " attribute(s) per point");
  Mesh mesh;
  mesh.rest = nodes.xyz.matrix();
  readEleFile(base + ".ele", nodes, mesh, notes);
  meshio::finishVolumeMesh(mesh, base + ".ele", meshio::IgnoredElements("type"), notes);
  return mesh;
}

}  // namespace tt
