#pragma once
// State snapshots: the positions, velocities and time of a running simulation written to a
// file so that a restarted process can continue where the last one stopped. A snapshot is
// written to a temporary file next to the target and renamed over it, so a reader (or a
// process killed mid-write) only ever sees a whole old or a whole new snapshot.
//
// Format (host byte order: a snapshot is read back on the machine that wrote it):
//   "TTSNAP01", u64 scene fingerprint, u64 node count, f64 time, 3n f64 positions,
//   3n f64 velocities, u64 FNV-1a checksum of everything before it.
#include <cstdint>
#include <string>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/system.h"

namespace tt {

// Identifies the scene a state belongs to: FNV-1a over the scene name, the node count, the
// tets and the rest positions (any change to the mesh or the name changes it).
std::uint64_t sceneFingerprint(const std::string& sceneName, const Mesh& mesh);

// Writes PATH.tmp and renames it over PATH. Throws std::runtime_error naming the file.
void writeStateSnapshot(const std::string& path, const State& state, std::uint64_t fingerprint);

// Reads PATH and checks it against the scene that is to continue from it: magic, checksum,
// fingerprint, node count and finite values. Throws InputError "PATH: what does not match".
State readStateSnapshot(const std::string& path, std::uint64_t fingerprint, int numNodes);

}  // namespace tt
