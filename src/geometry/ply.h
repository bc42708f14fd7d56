// PLY meshes: a small header scan that validates the file against what its header promises
// (counts, sizes, face indices), then OpenMesh's PLY reader feeding our own importer, so polygons
// become triangle fans straight into a TriangleMesh without OpenMesh's half-edge structure.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "core/error.h"
#include "geometry/mesh.h"

namespace ml {

struct PlyCounts {
    uint64_t vertices = 0;
    uint64_t faces = 0;
    uint64_t triangles = 0;  // sum over faces of (n - 2), faces of fewer than 3 vertices skipped
    bool binary = false;
};

// Validates a PLY file without building a mesh: header, sizes and face indices. Throws
// InputError at `loc` with the message "PATH: problem".
PlyCounts scan_ply(const std::string& path, const FileLoc& loc);

// Reads a PLY file into an object-space mesh (positions, and normals and uvs when the file has
// them). Throws InputError at `loc` with the message "PATH: problem". Thread-safe.
std::unique_ptr<TriangleMesh> load_ply(const std::string& path, const FileLoc& loc);
// The same on a file's bytes already in memory (the fuzzer's entry point); `path` names them in
// messages.
std::unique_ptr<TriangleMesh> load_ply_data(std::string data, const std::string& path,
                                            const FileLoc& loc);

}  // namespace ml
