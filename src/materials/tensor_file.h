// pbrt-v4's and Mitsuba's "tensor file" (.bsdf): named, typed, n-dimensional arrays, the format
// of the RGL measured-material database (Dupuy and Jakob 2018). Read whole; every offset, size
// and shape is checked against the file, so a damaged file is an error at `loc`, never a crash.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"

namespace ml {

struct TensorField {
    enum Type : uint8_t {
        Invalid,
        UInt8,
        Int8,
        UInt16,
        Int16,
        UInt32,
        Int32,
        UInt64,
        Int64,
        Float16,
        Float32,
        Float64
    };
    Type type = Invalid;
    std::vector<size_t> shape;
    std::vector<uint8_t> bytes;
    size_t count() const;
    // The values of a Float32 field.
    std::vector<float> floats() const;
};

std::map<std::string, TensorField> read_tensor_file(const std::string& path, const FileLoc& loc);

}  // namespace ml
