// VTK XML unstructured grid (.vtu) reader for ASCII data arrays, with a small tolerant XML
// scanner: elements, attributes in single or double quotes, comments, processing
// instructions and declarations. Entities are not decoded (VTU ASCII files need none).
#include <cctype>
#include <cstring>

#include "reader_support.h"

namespace tt {

namespace {

using meshio::Scanner;

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  long line = 0;                 // line of the start tag
  std::size_t contentBegin = 0;  // text between the start and end tags
  std::size_t contentEnd = 0;
  long contentLine = 0;
  std::vector<int> children;

  const std::string* attribute(const char* key) const {
    for (const auto& [k, v] : attributes)
      if (k == key) return &v;
    return nullptr;
  }
};

class XmlScanner {
 public:
  XmlScanner(const std::string& path, const std::string& text) : path_(path), text_(text) {}

  // Parses the whole text into elements_; element 0 is the root.
  std::vector<XmlElement> parse() {
    std::vector<int> open;
    while (true) {
      const std::size_t lt = text_.find('<', pos_);
      if (lt == std::string::npos) break;
      advanceTo(lt);
      if (match("<?")) {
        skipPast("?>", "'?>' closing the processing instruction");
      } else if (match("<!--")) {
        skipPast("-->", "'-->' closing the comment");
      } else if (match("<![CDATA[")) {
        fail("expected ASCII data arrays without CDATA sections");
      } else if (match("<!")) {
        skipPast(">", "'>' closing the declaration");
      } else if (match("</")) {
        closeTag(open);
      } else {
        openTag(open);
      }
    }
    if (!open.empty())
      fail("expected </" + elements_[open.back()].name + "> before the end of the file");
    if (elements_.empty()) fail("expected an XML element such as <VTKFile>");
    return std::move(elements_);
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw InputError(path_, line_, message); }

  bool match(const char* s) const { return text_.compare(pos_, std::strlen(s), s) == 0; }

  void advanceTo(std::size_t target) {
    for (; pos_ < target && pos_ < text_.size(); ++pos_)
      if (text_[pos_] == '\n') ++line_;
  }

  void skipPast(const char* end, const std::string& what) {
    const std::size_t at = text_.find(end, pos_);
    if (at == std::string::npos) fail("expected " + what + " before the end of the file");
    advanceTo(at + std::strlen(end));
  }

  static bool isNameChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.';
  }

  void skipSpace() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) advanceTo(pos_ + 1);
  }

  std::string readName(const std::string& what) {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && isNameChar(text_[pos_])) ++pos_;
    if (pos_ == start)
      fail("expected " + what + ", got " + meshio::quoted(std::string_view(text_).substr(start, 12)));
    return text_.substr(start, pos_ - start);
  }

  void openTag(std::vector<int>& open) {
    XmlElement element;
    element.line = line_;
    advanceTo(pos_ + 1);
    element.name = readName("an element name after '<'");
    while (true) {
      skipSpace();
      if (pos_ >= text_.size()) fail("expected '>' closing <" + element.name + ">, got end of file");
      if (match("/>") || match(">")) break;
      std::string key = readName("an attribute name in <" + element.name + ">");
      skipSpace();
      if (!match("=")) fail("expected '=' after attribute " + key);
      advanceTo(pos_ + 1);
      skipSpace();
      if (pos_ >= text_.size() || (text_[pos_] != '"' && text_[pos_] != '\''))
        fail("expected a quoted value for attribute " + key);
      const char quote = text_[pos_];
      const std::size_t close = text_.find(quote, pos_ + 1);
      if (close == std::string::npos) fail("expected a closing quote for attribute " + key);
      if (element.attribute(key.c_str())) fail("expected attribute " + key + " once in <" + element.name + ">");
      element.attributes.emplace_back(key, text_.substr(pos_ + 1, close - pos_ - 1));
      advanceTo(close + 1);
    }
    const bool selfClosing = match("/>");
    advanceTo(pos_ + (selfClosing ? 2 : 1));
    element.contentBegin = element.contentEnd = pos_;
    element.contentLine = line_;
    const int index = static_cast<int>(elements_.size());
    if (!open.empty()) elements_[open.back()].children.push_back(index);
    else if (!elements_.empty()) fail("expected a single root element, got a second one <" + element.name + ">");
    elements_.push_back(std::move(element));
    if (!selfClosing) open.push_back(index);
  }

  void closeTag(std::vector<int>& open) {
    const std::size_t lt = pos_;
    advanceTo(pos_ + 2);
    const std::string name = readName("an element name after '</'");
    skipSpace();
    if (!match(">")) fail("expected '>' closing </" + name + ">");
    advanceTo(pos_ + 1);
    if (open.empty()) fail("expected no closing tag after the root element, got </" + name + ">");
    XmlElement& element = elements_[open.back()];
    if (element.name != name) fail("expected </" + element.name + ">, got </" + name + ">");
    element.contentEnd = lt;
    open.pop_back();
  }

  const std::string& path_;
  const std::string& text_;
  std::size_t pos_ = 0;
  long line_ = 1;
  std::vector<XmlElement> elements_;
};

struct VtuReader {
  const std::string& path;
  const std::string& text;
  std::vector<XmlElement> xml;

  [[noreturn]] void fail(const XmlElement& e, const std::string& message) const {
    throw InputError(path, e.line, message);
  }

  const XmlElement* child(const XmlElement& parent, const char* name, const char* arrayName = nullptr) const {
    for (int c : parent.children) {
      const XmlElement& e = xml[c];
      if (e.name != name) continue;
      if (!arrayName) return &e;
      const std::string* n = e.attribute("Name");
      if (n && *n == arrayName) return &e;
    }
    return nullptr;
  }

  const XmlElement& requireChild(const XmlElement& parent, const char* name, const char* arrayName = nullptr) const {
    const XmlElement* e = child(parent, name, arrayName);
    if (!e)
      fail(parent, std::string("expected <") + name + (arrayName ? std::string(" Name=\"") + arrayName + "\"" : "") +
                       "> inside <" + parent.name + ">");
    return *e;
  }

  long long intAttribute(const XmlElement& e, const char* key) const {
    const std::string* value = e.attribute(key);
    if (!value) fail(e, std::string("expected attribute ") + key + " in <" + e.name + ">");
    Scanner s(path, *value, 0, value->size(), e.line);
    std::string_view token;
    if (!s.nextToken(token)) fail(e, std::string("expected a value for ") + key);
    return s.toInt(token, key);
  }

  // A data array's text, checked to be ASCII and to have the given component count.
  Scanner arrayScanner(const XmlElement& e, long long components) const {
    const std::string* format = e.attribute("format");
    if (!format || *format != "ascii")
      fail(e, "expected format=\"ascii\" in <DataArray>, got " + (format ? meshio::quoted(*format) : "none") +
                  " (binary and appended data are not supported)");
    const long long declared = e.attribute("NumberOfComponents") ? intAttribute(e, "NumberOfComponents") : 1;
    if (declared != components)
      fail(e, "expected NumberOfComponents=\"" + std::to_string(components) + "\", got " + std::to_string(declared));
    return Scanner(path, text, e.contentBegin, e.contentEnd, e.contentLine);
  }

  void requireArrayEnd(Scanner& s, const XmlElement& e, long long count) const {
    std::string_view extra;
    if (s.nextToken(extra))
      s.fail("expected " + std::to_string(count) + " values in the data array, got more: " + meshio::quoted(extra));
    (void)e;
  }
};

}  // namespace

Mesh readVtu(const std::string& path, ReadNotes* notes) {
  const std::string text = meshio::loadTextFile(path);
  VtuReader r{path, text, XmlScanner(path, text).parse()};
  const XmlElement& root = r.xml[0];
  if (root.name != "VTKFile") r.fail(root, "expected <VTKFile> as the root element, got <" + root.name + ">");
  const std::string* type = root.attribute("type");
  if (!type || *type != "UnstructuredGrid")
    r.fail(root, "expected type=\"UnstructuredGrid\", got " + (type ? meshio::quoted(*type) : "none"));
  const XmlElement& grid = r.requireChild(root, "UnstructuredGrid");
  const XmlElement& piece = r.requireChild(grid, "Piece");
  int pieces = 0;
  for (int c : grid.children) pieces += r.xml[c].name == "Piece";
  if (pieces != 1) r.fail(grid, "expected one <Piece>, got " + std::to_string(pieces));
  const long long numPoints = r.intAttribute(piece, "NumberOfPoints");
  const long long numCells = r.intAttribute(piece, "NumberOfCells");

  const XmlElement& pointsArray = r.requireChild(r.requireChild(piece, "Points"), "DataArray");
  Scanner ps = r.arrayScanner(pointsArray, 3);
  ps.checkCount(numPoints, "points");
  meshio::NodeBuffer points;
  for (long long i = 0; i < numPoints; ++i) {
    double xyz[3];
    const std::string what = "3 coordinates of point " + std::to_string(i);
    for (double& v : xyz) v = ps.toDouble(ps.requireToken(what), what);
    points.push(xyz[0], xyz[1], xyz[2]);
  }
  r.requireArrayEnd(ps, pointsArray, 3 * numPoints);

  const XmlElement& cellsElement = r.requireChild(piece, "Cells");
  const XmlElement& offsetsArray = r.requireChild(cellsElement, "DataArray", "offsets");
  Scanner os = r.arrayScanner(offsetsArray, 1);
  os.checkCount(numCells, "cells");
  std::vector<long long> offsets{0};
  for (long long c = 0; c < numCells; ++c)
    offsets.push_back(os.toInt(os.requireToken("offset of cell " + std::to_string(c)), offsets.back(),
                               offsets.back() + 1000, "offset of cell " + std::to_string(c)));
  r.requireArrayEnd(os, offsetsArray, numCells);

  const XmlElement& connectivityArray = r.requireChild(cellsElement, "DataArray", "connectivity");
  Scanner cs = r.arrayScanner(connectivityArray, 1);
  cs.checkCount(offsets.back(), "connectivity values");
  std::vector<int> connectivity;
  std::vector<long> lines;
  for (long long c = 0; c < numCells; ++c) {
    const std::string what = "node index of cell " + std::to_string(c);
    for (long long i = offsets[c]; i < offsets[c + 1]; ++i) {
      connectivity.push_back(static_cast<int>(cs.toInt(cs.requireToken(what), 0, numPoints - 1, what)));
      if (i == offsets[c]) lines.push_back(cs.lineNo());
    }
    if (offsets[c] == offsets[c + 1]) lines.push_back(cs.lineNo());
  }
  r.requireArrayEnd(cs, connectivityArray, offsets.back());

  const XmlElement& typesArray = r.requireChild(cellsElement, "DataArray", "types");
  Scanner ts = r.arrayScanner(typesArray, 1);
  Mesh mesh;
  meshio::IgnoredElements ignored("VTK type");
  for (long long c = 0; c < numCells; ++c) {
    const std::string what = "type of cell " + std::to_string(c);
    const int cellType = static_cast<int>(ts.toInt(ts.requireToken(what), 1, 100, what));
    meshio::addVtkCell(ts, lines[c], static_cast<std::size_t>(c), cellType,
                       connectivity.data() + offsets[c], static_cast<int>(offsets[c + 1] - offsets[c]),
                       mesh, ignored);
  }
  r.requireArrayEnd(ts, typesArray, numCells);

  mesh.rest = points.matrix();
  meshio::finishVolumeMesh(mesh, path, ignored, notes);
  return mesh;
}

}  // namespace tt
