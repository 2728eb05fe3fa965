// Bad mesh files: every reader must throw tt::InputError naming the file, the line and what
// was expected, and random mutations of good files must either read as a valid mesh or throw
// InputError. Built under AddressSanitizer + UBSan by scripts/test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "tissue_trainer/core/mesh/mesh_io.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

std::string tempDir() {
  const fs::path dir = fs::temp_directory_path() / "tt_malformed_input";
  fs::create_directories(dir);
  return dir.string();
}

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = tempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct BadInput {
  std::string file;    // written under the temp dir unless `missing`
  std::string text;
  long line;           // expected line (0: none)
  std::string phrase;  // expected in the message
  bool missing = false;
};

using Reader = std::function<void(const std::string&)>;

void expectInputError(const Reader& read, const BadInput& bad, const std::string& errorFile = "") {
  const std::string path = bad.missing ? tempDir() + "/" + bad.file : writeFile(bad.file, bad.text);
  if (bad.missing) fs::remove(path);
  const std::string expectedFile = errorFile.empty() ? path : tempDir() + "/" + errorFile;
  try {
    read(path);
    ADD_FAILURE() << bad.file << ": no error for\n" << bad.text;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), expectedFile) << what;
    EXPECT_EQ(e.line(), bad.line) << what;
    EXPECT_NE(what.find(bad.phrase), std::string::npos) << "'" << bad.phrase << "' not in: " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    const std::string prefix = bad.line > 0 ? expectedFile + ":" + std::to_string(bad.line) + ": " : expectedFile + ": ";
    EXPECT_EQ(what.rfind(prefix, 0), 0u) << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << bad.file << ": wrong exception type: " << e.what();
  }
}

const Reader kReadMesh = [](const std::string& p) { readMesh(p); };
const Reader kReadObj = [](const std::string& p) { readObj(p); };

const std::string kV2Head = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
const std::string kV2Nodes = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";  // lines 4-10

TEST(MalformedInput, Gmsh) {
  const std::vector<BadInput> table = {
      {"missing.msh", "", 0, "cannot open", true},
      {"empty.msh", "", 0, "file is empty"},
      {"blank.msh", "  \n\n\t\n", 0, "file is empty"},
      {"garbage.msh", "hello world\n", 1, "expected a section header"},
      {"binary.msh", "$NOD\n2\n1 0 0\x01\x02 0\n", 3, "binary byte 0x01"},
      {"truncated.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n", 4, "expected node 3 of 3, got end of file"},
      {"fewnodes.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n$ENDNOD\n", 5, "expected 3 nodes, section ended after 2"},
      {"manynodes.msh", "$NOD\n1\n1 0 0 0\n2 1 0 0\n$ENDNOD\n", 4, "expected $ENDNOD after 1 nodes"},
      {"nonnumeric.msh", "$NOD\n2\n1 0 0 0\n7 abc 0 0\n", 4, "expected 3 coordinates after node id 7, got 'abc'"},
      {"nan.msh", "$NOD\n2\n1 0 0 0\n7 0 nan 0\n", 4, "non-finite value 'nan'"},
      {"inf.msh", "$NOD\n2\n1 0 0 0\n7 0 0 -inf\n", 4, "non-finite value '-inf'"},
      {"overflow.msh", "$NOD\n2\n1 0 0 0\n7 0 1e999 0\n", 4, "non-finite value '1e999'"},
      {"shortnode.msh", "$NOD\n2\n1 0 0\n", 3, "expected node id and 3 coordinates, got 3 values"},
      {"hugeid.msh", "$NOD\n1\n99999999999999999999 0 0 0\n", 3, "out-of-range integer"},
      {"twiceid.msh", "$NOD\n2\n5 0 0 0\n5 1 0 0\n", 4, "node 5 is defined twice"},
      {"hugecount.msh", "$NOD\n999999999999\n1 0 0 0\n", 2, "declared 999999999999 nodes but only 8 bytes follow"},
      {"negcount.msh", "$NOD\n-3\n", 2, "expected a non-negative number of nodes, got -3"},
      {"unknownnode.msh", "$NOD\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$ENDNOD\n$ELM\n1\n1 4 1 1 4 1 2 3 99\n$ENDELM\n",
       10, "unknown node 99"},
      {"repeated.msh", "$NOD\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$ENDNOD\n$ELM\n1\n1 4 1 1 4 1 2 2 3\n$ENDELM\n",
       10, "node 2 is repeated"},
      {"v1tetcount.msh", "$NOD\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$ENDNOD\n$ELM\n1\n1 4 1 1 3 1 2 3\n$ENDELM\n",
       10, "expected 4 nodes for a tetrahedron, got 3"},
      {"v1shortelm.msh", "$NOD\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$ENDNOD\n$ELM\n1\n1 4 1 1 4 1 2 3\n$ENDELM\n",
       10, "expected element with 4 nodes (9 values), got 8 values"},
      {"noelements.msh", "$NOD\n1\n1 0 0 0\n$ENDNOD\n", 4, "expected an element section"},
      {"notets.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$ENDNOD\n$ELM\n1\n1 2 1 1 3 1 2 3\n$ENDELM\n", 0,
       "expected at least one tetrahedron or hexahedron, found none (ignored 1 triangles (type 2))"},
      {"binaryfmt.msh", "$MeshFormat\n2.2 1 8\n$EndMeshFormat\n", 2, "expected file type 0 (ASCII)"},
      {"v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", 2, "expected format version 2.x or 4.x"},
      {"noformatend.msh", "$MeshFormat\n2.2 0 8\n$Nodes\n", 3, "expected $EndMeshFormat after the format line"},
      {"v2type.msh", kV2Head + kV2Nodes + "$Elements\n1\n1 99 2 0 0 1 2 3 4\n$EndElements\n", 13,
       "expected a known element type, got 99"},
      {"v2tags.msh", kV2Head + kV2Nodes + "$Elements\n1\n1 4 2 0 1 2 3 4\n$EndElements\n", 13,
       "expected element of type 4 with 2 tags and 4 nodes (9 values), got 8 values"},
      {"v2unknown.msh", kV2Head + kV2Nodes + "$Elements\n1\n1 4 2 0 0 1 2 3 5\n$EndElements\n", 13,
       "unknown node 5"},
      {"v2elemsfirst.msh", kV2Head + "$Elements\n0\n$EndElements\n", 4, "expected the node section before $Elements"},
      {"v2unterminated.msh", kV2Head + "$PhysicalNames\n1\n3 1 \"a\"\n", 6, "expected $EndPhysicalNames before the end"},
      {"v4blocks.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 5\n3 1 0 4\n1\n2\n3\n4\n"
                       "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n", 5, "expected 5 nodes in the blocks, got 4"},
      {"v4param.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n2 1 1 1\n1\n0 0 0\n$EndNodes\n", 8,
       "expected 5 coordinates of node 1 (5 values), got 3 values"},
      {"v4elemtag.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n"
                        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 7\n$EndElements\n",
       19, "unknown node 7"},
      {"v4blockcount.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 2\n1\n2\n0 0 0\n1 0 0\n$EndNodes\n",
       6, "expected at most 1 more nodes, block declares 2"},
      {"v4hugeblock.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 2000000000\n1\n", 6,
       "declared 2000000000 nodes in the block but only 2 bytes follow"},
      {"truncelm.msh", "$NOD\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$ENDNOD\n$ELM\n2\n1 4 1 1 4 1 2 3 4\n", 10,
       "expected element 2 of 2, got end of file"},
  };
  for (const BadInput& bad : table) expectInputError(kReadMesh, bad);
}

TEST(MalformedInput, Tetgen) {
  const std::string goodNode = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  const std::string goodEle = "1 4 0\n1 1 2 3 4\n";
  auto withNode = [&](const std::string& base, const std::string& node, long line, const std::string& phrase) {
    writeFile(base + ".ele", goodEle);
    BadInput bad{base + ".node", node, line, phrase};
    expectInputError(kReadMesh, bad);
  };
  auto withEle = [&](const std::string& base, const std::string& ele, long line, const std::string& phrase) {
    writeFile(base + ".node", goodNode);
    BadInput bad{base + ".ele", ele, line, phrase};
    expectInputError([](const std::string& p) { readTetgen(p.substr(0, p.size() - 4) + ".node"); }, bad);
  };
  withNode("tg_header", "4 3 0\n", 1, "node header: point count, dimension, attribute count, marker flag");
  withNode("tg_dim", "4 2 0 0\n", 1, "expected dimension in [3, 3], got 2");
  withNode("tg_first", "# c\n4 3 0 0\n5 0 0 0\n", 3, "expected first point number (0 or 1) in [0, 1], got 5");
  withNode("tg_consecutive", "4 3 0 0\n1 0 0 0\n3 1 0 0\n", 3, "expected consecutive point number in [2, 2], got 3");
  withNode("tg_nan", "4 3 0 0\n1 0 0 0\n2 NaN 0 0\n", 3, "non-finite value 'NaN'");
  withNode("tg_attr", "2 3 1 0\n1 0 0 0\n", 2, "expected point number, 3 coordinates, attributes (5 values), got 4");
  withNode("tg_truncated", "4 3 0 0\n1 0 0 0\n2 1 0 0\n", 3, "expected point 3 of 4, got end of file");
  withNode("tg_extra", "1 3 0 0\n1 0 0 0\n2 1 0 0\n", 3, "expected 1 points, got more lines");
  withNode("tg_huge", "400000000 3 0 0\n1 0 0 0\n", 1, "declared 400000000 points");
  withEle("tg_range", "1 4 0\n1 1 2 3 9\n", 2, "expected node index in [1, 4], got 9");
  withEle("tg_zero", "1 4 0\n1 0 1 2 3\n", 2, "expected node index in [1, 4], got 0");
  withEle("tg_repeat", "1 4 0\n1 1 2 3 3\n", 2, "node 3 is repeated");
  withEle("tg_per", "1 5 0\n", 1, "expected nodes per tet 4 or 10, got 5");
  withEle("tg_eletrunc", "2 4 0\n1 1 2 3 4\n", 2, "expected tet 2 of 2, got end of file");
  withEle("tg_eleword", "1 4 0\n1 1 2 three 4\n", 2, "expected node index (an integer), got 'three'");
  withEle("tg_elehuge", "99999999999 4 0\n", 1, "declared 99999999999 tets");
  // .ele missing: the error names the .ele file.
  writeFile("tg_noele.node", goodNode);
  fs::remove(tempDir() + "/tg_noele.ele");
  expectInputError([](const std::string&) { readTetgen(tempDir() + "/tg_noele.node"); },
                   BadInput{"tg_noele.ele", "", 0, "cannot open", true});
  expectInputError(kReadMesh, BadInput{"tg_nonode.node", "", 0, "cannot open", true});
}

const std::string kVtkHead = "# vtk DataFile Version 3.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n";
const std::string kVtkPoints = "POINTS 4 float\n0 0 0 1 0 0\n0 1 0 0 0 1\n";  // lines 5-7

TEST(MalformedInput, VtkLegacy) {
  const std::vector<BadInput> table = {
      {"missing.vtk", "", 0, "cannot open", true},
      {"empty.vtk", "\n", 0, "file is empty"},
      {"header.vtk", "# something else\n", 1, "expected '# vtk DataFile Version x.x'"},
      {"binary.vtk", "# vtk DataFile Version 3.0\ntitle\nBINARY\n", 3, "expected ASCII"},
      {"poly.vtk", "# vtk DataFile Version 3.0\ntitle\nASCII\nDATASET POLYDATA\n", 4, "expected dataset type UNSTRUCTURED_GRID"},
      {"truncpoints.vtk", kVtkHead + "POINTS 4 float\n0 0 0 1 0 0\n0 1 0\n", 7, "expected coordinates of point 3, got end of file"},
      {"nanpoints.vtk", kVtkHead + "POINTS 2 float\n0 0 0\n1 nan 0\n", 7, "non-finite value 'nan'"},
      {"hugepoints.vtk", kVtkHead + "POINTS 123456789012 float\n0 0 0\n", 5, "declared 123456789012 points"},
      {"cellsfirst.vtk", kVtkHead + "CELLS 1 5\n4 0 1 2 3\n", 5, "expected POINTS before CELLS"},
      {"range.vtk", kVtkHead + kVtkPoints + "CELLS 1 5\n4 0 1 2 4\n", 9, "expected node index of cell 0 in [0, 3], got 4"},
      {"negindex.vtk", kVtkHead + kVtkPoints + "CELLS 1 5\n4 0 -1 2 3\n", 9, "got -1"},
      {"cellsize.vtk", kVtkHead + kVtkPoints + "CELLS 2 10\n4 0 1 2 3\n3 0 1 2\n", 10, "expected 10 values in CELLS as declared, got 9"},
      {"cellcount.vtk", kVtkHead + kVtkPoints + "CELLS 1 5\n9 0 1 2 3\n", 9, "expected node count of cell 0 in [1, 4], got 9"},
      {"typecount.vtk", kVtkHead + kVtkPoints + "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10 10\n", 10,
       "expected CELL_TYPES count equal to the 1 cells, got 2"},
      {"tetnodes.vtk", kVtkHead + kVtkPoints + "CELLS 2 9\n4 0 1 2 3\n3 0 1 2\nCELL_TYPES 2\n10\n10\n", 10,
       "expected 4 nodes for cell 1 of type 10, got 3"},
      {"repeat.vtk", kVtkHead + kVtkPoints + "CELLS 1 5\n4 0 1 1 3\nCELL_TYPES 1\n10\n", 9, "node 1 is repeated"},
      {"notypes.vtk", kVtkHead + kVtkPoints + "CELLS 1 5\n4 0 1 2 3\n", 9, "expected CELL_TYPES before the end"},
      {"keyword.vtk", kVtkHead + kVtkPoints + "VERTICES 1 2\n", 8, "expected POINTS, CELLS, CELL_TYPES or a data section, got 'VERTICES'"},
      {"offsets.vtk", kVtkHead + kVtkPoints + "CELLS 2 4\nOFFSETS vtktypeint64\n0 5\n", 10, "expected non-decreasing offset in [0, 4], got 5"},
      {"offsetsend.vtk", kVtkHead + kVtkPoints + "CELLS 2 4\nOFFSETS vtktypeint64\n0 3\n", 10,
       "expected the last offset to equal the connectivity size 4"},
  };
  for (const BadInput& bad : table) expectInputError(kReadMesh, bad);
}

std::string vtu(const std::string& pieceAttrs, const std::string& points, const std::string& conn,
                const std::string& offsets, const std::string& types, const std::string& pointsFormat = "ascii") {
  return "<?xml version=\"1.0\"?>\n"                                                       // 1
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n"                           // 2
         "<UnstructuredGrid>\n"                                                            // 3
         "<Piece " + pieceAttrs + ">\n"                                                    // 4
         "<Points>\n"                                                                      // 5
         "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"" + pointsFormat + "\">\n"  // 6
         + points + "\n"                                                                   // 7
         "</DataArray>\n"                                                                  // 8
         "</Points>\n"                                                                     // 9
         "<Cells>\n"                                                                       // 10
         "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n"             // 11
         + conn + "\n"                                                                     // 12
         "</DataArray>\n"                                                                  // 13
         "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n"                  // 14
         + offsets + "\n"                                                                  // 15
         "</DataArray>\n"                                                                  // 16
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n"                    // 17
         + types + "\n"                                                                    // 18
         "</DataArray>\n"                                                                  // 19
         "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

TEST(MalformedInput, Vtu) {
  const std::string piece = "NumberOfPoints=\"4\" NumberOfCells=\"1\"";
  const std::string pts = "0 0 0 1 0 0 0 1 0 0 0 1";
  // Sanity: the template itself reads.
  EXPECT_EQ(readVtu(writeFile("good.vtu", vtu(piece, pts, "0 1 2 3", "4", "10"))).numTets(), 1);
  const std::vector<BadInput> table = {
      {"missing.vtu", "", 0, "cannot open", true},
      {"notxml.vtu", "just text\n", 1, "expected an XML element"},
      {"root.vtu", "<?xml version=\"1.0\"?>\n<Foo>\n</Foo>\n", 2, "expected <VTKFile> as the root element"},
      {"unclosed.vtu", "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n", 2, "expected </UnstructuredGrid> before the end"},
      {"mismatch.vtu", "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n</Piece>\n", 3,
       "expected </UnstructuredGrid>, got </Piece>"},
      {"quote.vtu", "<VTKFile type=UnstructuredGrid>\n</VTKFile>\n", 1, "expected a quoted value for attribute type"},
      {"nopiece.vtu", "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n</UnstructuredGrid>\n</VTKFile>\n", 2,
       "expected <Piece> inside <UnstructuredGrid>"},
      {"count.vtu", vtu("NumberOfPoints=\"four\" NumberOfCells=\"1\"", pts, "0 1 2 3", "4", "10"), 4,
       "expected NumberOfPoints (an integer), got 'four'"},
      {"hugecount.vtu", vtu("NumberOfPoints=\"5000000000\" NumberOfCells=\"1\"", pts, "0 1 2 3", "4", "10"), 6,
       "declared 5000000000 points but only"},
      {"twiceattr.vtu", "<VTKFile type=\"UnstructuredGrid\" type=\"x\">\n</VTKFile>\n", 1, "expected attribute type once in <VTKFile>"},
      {"format.vtu", vtu(piece, pts, "0 1 2 3", "4", "10", "binary"), 6, "expected format=\"ascii\""},
      {"fewpoints.vtu", vtu(piece, "0 0 0 1 0 0 0 1 0 0 0", "0 1 2 3", "4", "10"), 7,
       "expected 3 coordinates of point 3, got end of file"},
      {"manypoints.vtu", vtu(piece, pts + "\n5", "0 1 2 3", "4", "10"), 8, "got more: '5'"},
      {"infpoint.vtu", vtu(piece, "0 0 0 1 0 0 0 1 0 0 0 inf", "0 1 2 3", "4", "10"), 7, "non-finite value 'inf'"},
      {"range.vtu", vtu(piece, pts, "0 1 2 4", "4", "10"), 12, "expected node index of cell 0 in [0, 3], got 4"},
      {"repeat.vtu", vtu(piece, pts, "0 1 2 2", "4", "10"), 12, "node 2 is repeated"},
      {"offsets.vtu", vtu("NumberOfPoints=\"4\" NumberOfCells=\"2\"", pts, "0 1 2 3", "4 2", "10 10"), 15,
       "expected offset of cell 1 in [4, 1004], got 2"},
      {"shortconn.vtu", vtu(piece, pts, "0 1 2", "4", "10"), 12, "expected node index of cell 0, got end of file"},
      {"tetnodes.vtu", vtu(piece, pts, "0 1 2", "3", "10"), 12, "expected 4 nodes for cell 0 of type 10, got 3"},
      {"types.vtu", vtu(piece, pts, "0 1 2 3", "4", "ten"), 18, "expected type of cell 0 (an integer), got 'ten'"},
      {"notets.vtu", vtu(piece, pts, "0 1 2", "3", "5"), 0, "found none (ignored 1 triangles (VTK type 5))"},
  };
  for (const BadInput& bad : table) expectInputError(kReadMesh, bad);
}

TEST(MalformedInput, Obj) {
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";  // lines 1-3
  const std::vector<BadInput> table = {
      {"missing.obj", "", 0, "cannot open", true},
      {"empty.obj", "", 0, "file is empty"},
      {"noface.obj", v, 3, "expected at least one face"},
      {"zero.obj", v + "f 0 1 2\n", 4, "expected a vertex index in [1, 3] or [-3, -1], got 0"},
      {"range.obj", v + "f 1 2 4\n", 4, "got 4"},
      {"negrange.obj", v + "f -1 -2 -4\n", 4, "got -4"},
      {"forward.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n", 2, "expected a vertex index in [1, 1]"},
      {"twoverts.obj", v + "f 1 2\n", 4, "expected a face with at least 3 vertices, got 2"},
      {"repeat.obj", v + "f 1 2 1\n", 4, "vertex 1 is repeated"},
      {"shortv.obj", "v 0 0\n", 1, "expected 'v x y z'"},
      {"nanv.obj", "v 0 nan 0\n", 1, "non-finite value 'nan'"},
      {"wordv.obj", "v 0 zero 0\n", 1, "expected 3 coordinates of vertex 1, got 'zero'"},
      {"badref.obj", v + "f 1/2/3 x/1 2\n", 4, "got 'x'"},
      {"binary.obj", v + "f 1 2 3\n\x7f\x01\x02\n", 5, "binary byte 0x01"},
  };
  for (const BadInput& bad : table) expectInputError(kReadObj, bad);
}

TEST(MalformedInput, UnknownExtension) {
  expectInputError(kReadMesh, BadInput{"mesh.stl", "solid x\n", 0, "expected a mesh file ending in .msh"});
}

// ---- Fuzzing: seeded random mutations of good files. ----

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start + 1));
    start = end + 1;
  }
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l;
  return text;
}

std::string mutate(const std::string& original, std::mt19937& rng) {
  static const char* kReplacements[] = {"1e308", "-1", "nan", "inf", "0", "99999999999", "-2147483649",
                                        "2147483647", "1e-320", "abc", "4000000000", "-0", "1.5", "",
                                        "3 3", "+7", "0x10", "-9223372036854775808"};
  std::string text = original;
  const int operations = 1 + static_cast<int>(rng() % 3);
  for (int op = 0; op < operations && !text.empty(); ++op) {
    std::vector<std::string> lines = splitLines(text);
    const std::size_t li = rng() % lines.size();
    switch (rng() % 7) {
      case 0: {  // flip a byte
        const std::size_t at = rng() % text.size();
        text[at] = static_cast<char>(rng() % 256);
        break;
      }
      case 1:
        lines.erase(lines.begin() + li);
        text = joinLines(lines);
        break;
      case 2:
        lines.insert(lines.begin() + li, lines[li]);
        text = joinLines(lines);
        break;
      case 3:
        text.resize(rng() % text.size());
        break;
      case 4: {  // swap two lines
        std::swap(lines[li], lines[rng() % lines.size()]);
        text = joinLines(lines);
        break;
      }
      default: {  // replace a number token
        std::string& line = lines[li];
        std::vector<std::pair<std::size_t, std::size_t>> numbers;
        for (std::size_t i = 0; i < line.size();) {
          if (std::isdigit(static_cast<unsigned char>(line[i])) || line[i] == '-') {
            std::size_t j = i;
            while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j])) && line[j] != '<' && line[j] != '"') ++j;
            numbers.emplace_back(i, j - i);
            i = j;
          } else {
            ++i;
          }
        }
        if (numbers.empty()) break;
        const auto [at, len] = numbers[rng() % numbers.size()];
        line.replace(at, len, kReplacements[rng() % (sizeof kReplacements / sizeof kReplacements[0])]);
        text = joinLines(lines);
        break;
      }
    }
  }
  return text;
}

// Returns true when the read succeeded, false when it threw InputError.
bool expectValidOrInputError(const std::function<void()>& read, const std::function<void(const std::string&)>& fail) {
  try {
    read();
    return true;
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find('\n') != std::string::npos || what.rfind(e.file(), 0) != 0) fail("bad message: " + what);
  } catch (const std::exception& e) {
    fail(std::string("wrong exception: ") + e.what());
  }
  return false;
}

void checkVolumeMesh(const Mesh& m, const std::function<void(const std::string&)>& fail) {
  const int n = m.numNodes();
  if (!m.rest.allFinite()) fail("non-finite rest position");
  for (const Tet& t : m.tets)
    for (int i = 0; i < 4; ++i) {
      if (t[i] < 0 || t[i] >= n) return fail("tet index out of range");
      for (int j = 0; j < i; ++j)
        if (t[i] == t[j]) return fail("repeated node in a tet");
    }
  for (const Hex& h : m.hexes)
    for (int v : h)
      if (v < 0 || v >= n) return fail("hex index out of range");
  for (const Triangle& tri : m.surface)
    for (int v : tri)
      if (v < 0 || v >= n) return fail("surface index out of range");
  if (m.tets.empty() && m.hexes.empty()) fail("no elements");
  if (m.fibreFrame.size() != m.tets.size() || m.material.size() != m.tets.size() ||
      m.nodeTags.size() != static_cast<std::size_t>(n))
    fail("defaults not filled");
}

// A small mesh: one unit cube as 6 tets plus one hex beside it.
Mesh smallMesh() {
  Mesh m;
  m.rest.resize(3, 12);
  m.rest << 0, 1, 1, 0, 0, 1, 1, 0, 2, 2, 2, 2,
            0, 0, 1, 1, 0, 0, 1, 1, 0, 1, 0, 1,
            0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 1, 1;
  m.tets = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (Tet& t : m.tets)
    if (tetVolume(m.rest, t) < 0) std::swap(t[1], t[2]);
  m.hexes = {{1, 8, 9, 2, 5, 10, 11, 6}};
  m.surface = extractSurface(m);
  m.fillDefaults();
  return m;
}

void fuzzFile(const std::string& name, const std::string& original, int mutations, unsigned seed,
              const std::function<void(const std::string&)>& read) {
  std::mt19937 rng(seed);
  const std::string path = tempDir() + "/fuzz_" + name;
  int succeeded = 0;
  for (int i = 0; i < mutations; ++i) {
    const std::string text = mutate(original, rng);
    std::ofstream(path, std::ios::binary) << text;
    auto fail = [&](const std::string& why) {
      ADD_FAILURE() << name << " mutation " << i << " (seed " << seed << "): " << why;
    };
    // TT_FUZZ_KEEP=i keeps mutation i as PATH.kept, to reproduce a failure by hand.
    if (std::getenv("TT_FUZZ_KEEP") && std::atoi(std::getenv("TT_FUZZ_KEEP")) == i)
      std::ofstream(path + ".kept", std::ios::binary) << text;
    const bool ok = expectValidOrInputError([&] { read(path); }, fail);
    succeeded += ok;
  }
  std::printf("%s: %d of %d mutations read as valid meshes, %d rejected\n", name.c_str(), succeeded, mutations,
              mutations - succeeded);
  // Both outcomes must occur, or the mutations test only one path.
  EXPECT_GT(succeeded, 0) << name;
  EXPECT_LT(succeeded, mutations) << name;
}

std::function<void(const std::string&)> volumeReader() {
  return [](const std::string& path) {
    const Mesh m = readMesh(path);
    checkVolumeMesh(m, [&](const std::string& why) { ADD_FAILURE() << path << ": " << why; });
  };
}

TEST(MalformedInput, FuzzGmshLiver) {
  const std::string liver = readFile(std::string(TT_SOURCE_DIR) + "/config/meshes/liver.msh");
  ASSERT_FALSE(liver.empty());
  fuzzFile("liver.msh", liver, 300, 1, volumeReader());
}

TEST(MalformedInput, FuzzWrittenFormats) {
  const Mesh m = smallMesh();
  const std::string dir = tempDir();
  writeGmsh2(dir + "/small_v2.msh", m);
  writeGmsh4(dir + "/small_v4.msh", m);
  writeVtkLegacy(dir + "/small.vtk", m);
  writeVtu(dir + "/small.vtu", m);
  Mesh tetsOnly = m;
  tetsOnly.hexes.clear();
  writeTetgen(dir + "/small_tg", tetsOnly);
  writeObj(dir + "/small.obj", SurfaceMesh{m.rest, m.surface});
  unsigned seed = 100;
  for (const std::string name : {"small_v2.msh", "small_v4.msh", "small.vtk", "small.vtu"})
    fuzzFile(name, readFile(dir + "/" + name), 300, ++seed, volumeReader());

  // TetGen: mutate one file of the pair while the other stays good.
  const std::string node = readFile(dir + "/small_tg.node"), ele = readFile(dir + "/small_tg.ele");
  std::ofstream(dir + "/fuzz_tg.ele", std::ios::binary) << ele;
  fuzzFile("tg.node", node, 300, ++seed, volumeReader());
  std::ofstream(dir + "/fuzz_tg.node", std::ios::binary) << node;
  fuzzFile("tg.ele", ele, 300, ++seed, volumeReader());

  fuzzFile("small.obj", readFile(dir + "/small.obj"), 300, ++seed, [](const std::string& path) {
    const SurfaceMesh s = readObj(path);
    for (const Triangle& t : s.triangles)
      for (int v : t)
        if (v < 0 || v >= s.vertices.cols()) ADD_FAILURE() << path << ": OBJ index out of range";
    if (!s.vertices.allFinite()) ADD_FAILURE() << path << ": non-finite OBJ vertex";
  });
}

}  // namespace
}  // namespace tt
