// Helpers for the PLY tests: writing small binary PLY files.
#pragma once

#include <array>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ml::test {

inline std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A binary little-endian PLY with float x y z and uint8/int faces of any size.
inline std::string binary_ply(const std::vector<std::array<float, 3>>& v,
                              const std::vector<std::vector<int>>& faces) {
    std::string s = "ply\nformat binary_little_endian 1.0\ncomment test\nelement vertex " +
                    std::to_string(v.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(faces.size()) +
                    "\nproperty list uint8 int vertex_indices\nend_header\n";
    for (const auto& p : v) s.append(reinterpret_cast<const char*>(p.data()), 12);
    for (const auto& f : faces) {
        s.push_back(char(uint8_t(f.size())));
        for (int i : f) s.append(reinterpret_cast<const char*>(&i), 4);
    }
    return s;
}

}  // namespace ml::test
