// Legacy VTK reader: ASCII UNSTRUCTURED_GRID with POINTS, CELLS (classic count-prefixed
// layout or the 5.x OFFSETS/CONNECTIVITY layout) and CELL_TYPES. Point and cell data after
// the cells are ignored.
#include <strings.h>

#include "reader_support.h"

namespace tt {

namespace {

using meshio::Scanner;

bool keywordIs(std::string_view token, const char* keyword) {
  const std::size_t n = std::char_traits<char>::length(keyword);
  return token.size() == n && strncasecmp(token.data(), keyword, n) == 0;
}

struct VtkCells {
  std::vector<long long> offsets{0};  // cell c uses connectivity[offsets[c] .. offsets[c+1])
  std::vector<int> connectivity;
  std::vector<long> lines;            // line where cell c starts, for messages
  std::size_t count() const { return offsets.size() - 1; }
};

void readHeader(Scanner& s) {
  s.requireLine("'# vtk DataFile Version' header");
  if (s.size() < 3 || s[0] != "#" || !keywordIs(s[1], "vtk") || !keywordIs(s[2], "DataFile"))
    s.fail("expected '# vtk DataFile Version x.x', got " + meshio::quoted(s.line()));
  s.requireLine("title line");
  // The title may be blank, in which case the line just read is already the format line.
  if (!(s.size() == 1 && (keywordIs(s[0], "ASCII") || keywordIs(s[0], "BINARY"))))
    s.requireLine("ASCII");
  if (s.size() != 1 || !keywordIs(s[0], "ASCII"))
    s.fail("expected ASCII (binary legacy VTK is not supported), got " + meshio::quoted(s.line()));
  s.finishLine();
  const std::string_view dataset = s.requireToken("DATASET");
  if (!keywordIs(dataset, "DATASET")) s.fail("expected DATASET, got " + meshio::quoted(dataset));
  const std::string_view kind = s.requireToken("dataset type");
  if (!keywordIs(kind, "UNSTRUCTURED_GRID"))
    s.fail("expected dataset type UNSTRUCTURED_GRID, got " + meshio::quoted(kind));
}

void readPoints(Scanner& s, meshio::NodeBuffer& points) {
  const long long n = s.toInt(s.requireToken("point count"), "point count");
  s.checkCount(n, "points");
  s.requireToken("point data type");
  for (long long i = 0; i < n; ++i) {
    double xyz[3];
    for (double& v : xyz)
      v = s.toDouble(s.requireToken("coordinates of point " + std::to_string(i)),
                     "3 coordinates of point " + std::to_string(i));
    points.push(xyz[0], xyz[1], xyz[2]);
  }
}

int readNodeIndex(Scanner& s, int numPoints, long long cell) {
  const std::string what = "node index of cell " + std::to_string(cell);
  return static_cast<int>(s.toInt(s.requireToken(what), 0, numPoints - 1LL, what));
}

void readCellsClassic(Scanner& s, long long n, long long size, int numPoints, VtkCells& cells) {
  s.checkCount(size, "cell list values");
  s.checkCount(n, "cells");
  for (long long c = 0; c < n; ++c) {
    const std::string_view first = s.requireToken("node count of cell " + std::to_string(c));
    cells.lines.push_back(s.lineNo());
    const long long used = static_cast<long long>(cells.connectivity.size() + cells.count());
    const long long k = s.toInt(first, 1, size - used - 1, "node count of cell " + std::to_string(c));
    for (long long j = 0; j < k; ++j) cells.connectivity.push_back(readNodeIndex(s, numPoints, c));
    cells.offsets.push_back(static_cast<long long>(cells.connectivity.size()));
  }
  const long long used = static_cast<long long>(cells.connectivity.size() + cells.count());
  if (used != size)
    s.fail("expected " + std::to_string(size) + " values in CELLS as declared, got " + std::to_string(used));
}

void readCellsOffsets(Scanner& s, long long numOffsets, long long numConnectivity, int numPoints,
                      VtkCells& cells) {
  s.checkCount(numOffsets, "offsets");
  s.checkCount(numConnectivity, "connectivity values");
  s.requireToken("OFFSETS data type");
  std::vector<long long> offsets;
  for (long long i = 0; i < numOffsets; ++i) {
    const long long lo = offsets.empty() ? 0 : offsets.back();
    const long long hi = offsets.empty() ? 0 : numConnectivity;
    offsets.push_back(s.toInt(s.requireToken("offset"), lo, hi, "non-decreasing offset"));
    if (i > 0) cells.lines.push_back(s.lineNo());
  }
  if (numOffsets < 1 || offsets.back() != numConnectivity)
    s.fail("expected the last offset to equal the connectivity size " + std::to_string(numConnectivity));
  const std::string_view keyword = s.requireToken("CONNECTIVITY");
  if (!keywordIs(keyword, "CONNECTIVITY")) s.fail("expected CONNECTIVITY, got " + meshio::quoted(keyword));
  s.requireToken("CONNECTIVITY data type");
  std::size_t cell = 0;
  for (long long i = 0; i < numConnectivity; ++i) {
    while (offsets[cell + 1] <= i) ++cell;
    cells.connectivity.push_back(readNodeIndex(s, numPoints, static_cast<long long>(cell)));
    if (i == offsets[cell]) cells.lines[cell] = s.lineNo();
  }
  cells.offsets = std::move(offsets);
}

void readCellTypes(Scanner& s, const VtkCells& cells, Mesh& mesh, meshio::IgnoredElements& ignored) {
  const long long n = s.toInt(s.requireToken("cell type count"), "cell type count");
  if (n != static_cast<long long>(cells.count()))
    s.fail("expected CELL_TYPES count equal to the " + std::to_string(cells.count()) + " cells, got " + std::to_string(n));
  for (std::size_t c = 0; c < cells.count(); ++c) {
    const int type = static_cast<int>(s.toInt(s.requireToken("cell type"), 1, 100, "cell type"));
    const int k = static_cast<int>(cells.offsets[c + 1] - cells.offsets[c]);
    meshio::addVtkCell(s, cells.lines[c], c, type, cells.connectivity.data() + cells.offsets[c], k,
                       mesh, ignored);
  }
}

}  // namespace

Mesh readVtkLegacy(const std::string& path, ReadNotes* notes) {
  const std::string text = meshio::loadTextFile(path);
  Scanner s(path, text);
  readHeader(s);
  meshio::NodeBuffer points;
  VtkCells cells;
  Mesh mesh;
  meshio::IgnoredElements ignored("VTK type");
  bool havePoints = false, haveCells = false, haveTypes = false;
  std::string_view keyword;
  while (s.nextToken(keyword)) {
    if (keywordIs(keyword, "POINTS")) {
      if (havePoints) s.fail("expected one POINTS section, got a second one");
      readPoints(s, points);
      havePoints = true;
    } else if (keywordIs(keyword, "CELLS")) {
      if (!havePoints) s.fail("expected POINTS before CELLS");
      if (haveCells) s.fail("expected one CELLS section, got a second one");
      const long long a = s.toInt(s.requireToken("cell count"), "cell count");
      const long long b = s.toInt(s.requireToken("cell list size"), "cell list size");
      std::string_view next;
      const int numPoints = static_cast<int>(points.xyz.size() / 3);
      // Peek: the 5.x layout continues with the OFFSETS keyword.
      Scanner peek = s;
      if (peek.nextToken(next) && keywordIs(next, "OFFSETS")) {
        s.requireToken("OFFSETS");
        readCellsOffsets(s, a, b, numPoints, cells);
      } else {
        readCellsClassic(s, a, b, numPoints, cells);
      }
      haveCells = true;
    } else if (keywordIs(keyword, "CELL_TYPES")) {
      if (!haveCells) s.fail("expected CELLS before CELL_TYPES");
      if (haveTypes) s.fail("expected one CELL_TYPES section, got a second one");
      readCellTypes(s, cells, mesh, ignored);
      haveTypes = true;
    } else if (keywordIs(keyword, "POINT_DATA") || keywordIs(keyword, "CELL_DATA") ||
               keywordIs(keyword, "FIELD") || keywordIs(keyword, "METADATA")) {
      break;
    } else {
      s.fail("expected POINTS, CELLS, CELL_TYPES or a data section, got " + meshio::quoted(keyword));
    }
  }
  if (!havePoints || !haveCells || !haveTypes)
    s.fail(std::string("expected ") + (!havePoints ? "POINTS" : !haveCells ? "CELLS" : "CELL_TYPES") +
           " before the end of the file");
  mesh.rest = points.matrix();
  meshio::finishVolumeMesh(mesh, path, ignored, notes);
  return mesh;
}

}  // namespace tt
