#include "tissue_trainer/core/scene/state_snapshot.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "tissue_trainer/core/error.h"

namespace tt {
namespace {

constexpr char kMagic[8] = {'T', 'T', 'S', 'N', 'A', 'P', '0', '1'};

class Fnv1a {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ull;
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;
};

template <class T>
void append(std::vector<char>& out, const T& value) {
  const char* p = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

// Reads the file's fields in order; any read past the end throws naming the field.
class Reader {
 public:
  Reader(const std::string& path, const std::vector<char>& bytes) : path_(path), bytes_(bytes) {}
  template <class T>
  T next(const char* field) {
    T value;
    take(&value, sizeof(T), field);
    return value;
  }
  void take(void* out, std::size_t bytes, const char* field) {
    if (bytes_.size() - at_ < bytes)
      throw InputError(path_, 0, std::string("truncated snapshot (ends in ") + field + ")");
    std::memcpy(out, bytes_.data() + at_, bytes);
    at_ += bytes;
  }
  std::size_t offset() const { return at_; }

 private:
  const std::string& path_;
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

}  // namespace

std::uint64_t sceneFingerprint(const std::string& sceneName, const Mesh& mesh) {
  Fnv1a h;
  h.add(sceneName.data(), sceneName.size());
  const std::uint64_t nodes = static_cast<std::uint64_t>(mesh.numNodes());
  h.add(&nodes, sizeof nodes);
  for (const Tet& t : mesh.tets) h.add(t.data(), sizeof(int) * t.size());
  h.add(mesh.rest.data(), sizeof(double) * static_cast<std::size_t>(mesh.rest.size()));
  return h.value();
}

void writeStateSnapshot(const std::string& path, const State& state, std::uint64_t fingerprint) {
  if (state.x.size() != state.v.size() || state.x.size() % 3 != 0)
    throw std::invalid_argument("writeStateSnapshot: positions and velocities differ in size");
  std::vector<char> out(kMagic, kMagic + sizeof kMagic);
  append(out, fingerprint);
  append(out, static_cast<std::uint64_t>(state.x.size() / 3));
  append(out, state.t);
  const char* x = reinterpret_cast<const char*>(state.x.data());
  const char* v = reinterpret_cast<const char*>(state.v.data());
  out.insert(out.end(), x, x + sizeof(double) * state.x.size());
  out.insert(out.end(), v, v + sizeof(double) * state.v.size());
  Fnv1a sum;
  sum.add(out.data(), out.size());
  append(out, sum.value());

  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(out.data(), static_cast<std::streamsize>(out.size()));
    f.flush();
    if (!f) throw std::runtime_error(tmp + ": cannot write the state snapshot");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error(path + ": cannot rename the snapshot into place (" +
                             std::strerror(errno) + ")");
}

State readStateSnapshot(const std::string& path, std::uint64_t fingerprint, int numNodes) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "cannot open the state snapshot");
  const std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Reader r(path, bytes);
  char magic[sizeof kMagic];
  r.take(magic, sizeof magic, "the header");
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw InputError(path, 0, "not a state snapshot (expected the header TTSNAP01)");
  const auto fileFingerprint = r.next<std::uint64_t>("the scene fingerprint");
  const auto nodes = r.next<std::uint64_t>("the node count");
  if (nodes != static_cast<std::uint64_t>(numNodes))
    throw InputError(path, 0, "snapshot of " + std::to_string(nodes) + " nodes, the scene has " +
                                  std::to_string(numNodes));
  State s;
  s.t = r.next<double>("the time");
  s.x.resize(3 * numNodes);
  s.v.resize(3 * numNodes);
  r.take(s.x.data(), sizeof(double) * s.x.size(), "the positions");
  r.take(s.v.data(), sizeof(double) * s.v.size(), "the velocities");
  Fnv1a sum;
  sum.add(bytes.data(), r.offset());
  if (r.next<std::uint64_t>("the checksum") != sum.value())
    throw InputError(path, 0, "checksum mismatch (the snapshot is corrupt)");
  if (r.offset() != bytes.size())
    throw InputError(path, 0, std::to_string(bytes.size() - r.offset()) + " bytes after the checksum");
  if (fileFingerprint != fingerprint)
    throw InputError(path, 0, "snapshot of another scene (its fingerprint differs from this scene's)");
  if (!std::isfinite(s.t) || !s.x.allFinite() || !s.v.allFinite())
    throw InputError(path, 0, "non-finite time, position or velocity");
  return s;
}

}  // namespace tt
