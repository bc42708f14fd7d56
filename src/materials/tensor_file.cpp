#include "materials/tensor_file.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace ml {

namespace {

size_t type_size(TensorField::Type t) {
    switch (t) {
        case TensorField::UInt8:
        case TensorField::Int8:
            return 1;
        case TensorField::UInt16:
        case TensorField::Int16:
        case TensorField::Float16:
            return 2;
        case TensorField::UInt32:
        case TensorField::Int32:
        case TensorField::Float32:
            return 4;
        case TensorField::UInt64:
        case TensorField::Int64:
        case TensorField::Float64:
            return 8;
        default:
            return 0;
    }
}

}  // namespace

size_t TensorField::count() const {
    size_t n = 1;
    for (size_t s : shape) n *= s;
    return n;
}

std::vector<float> TensorField::floats() const {
    std::vector<float> out(bytes.size() / sizeof(float));
    if (!out.empty()) std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
    return out;
}

std::map<std::string, TensorField> read_tensor_file(const std::string& path, const FileLoc& loc) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw_input_error(loc, "cannot open the tensor file \"{}\" (no such file)", path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_input_error(loc, "cannot open the tensor file \"{}\"", path);
    const std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    size_t at = 0;
    auto read = [&](void* out, size_t n, const char* what) {
        if (n > file.size() - at)
            throw_input_error(loc, "tensor file \"{}\": truncated in {}", path, what);
        std::memcpy(out, file.data() + at, n);
        at += n;
    };
    char header[12];
    uint8_t version[2];
    uint32_t n_fields = 0;
    read(header, 12, "its header");
    if (std::memcmp(header, "tensor_file", 12) != 0)
        throw_input_error(loc, "\"{}\" is not a tensor file (no \"tensor_file\" header)", path);
    read(version, 2, "its header");
    if (version[0] != 1 || version[1] != 0)
        throw_input_error(loc, "tensor file \"{}\": version {}.{}, where 1.0 is read", path,
                          version[0], version[1]);
    read(&n_fields, 4, "its header");
    std::map<std::string, TensorField> fields;
    for (uint32_t i = 0; i < n_fields; ++i) {
        uint16_t name_length = 0, ndim = 0;
        uint8_t type = 0;
        uint64_t offset = 0;
        read(&name_length, 2, "a field's name");
        std::string name(name_length, '\0');
        read(name.data(), name_length, "a field's name");
        read(&ndim, 2, "a field's header");
        read(&type, 1, "a field's header");
        read(&offset, 8, "a field's header");
        TensorField f;
        f.type = TensorField::Type(type);
        const size_t size = type_size(f.type);
        if (size == 0)
            throw_input_error(loc, "tensor file \"{}\": field \"{}\" has unknown type {}", path,
                              name, type);
        uint64_t total = size;
        for (uint16_t d = 0; d < ndim; ++d) {
            uint64_t extent = 0;
            read(&extent, 8, "a field's shape");
            if (extent != 0 && total > file.size() / extent)
                throw_input_error(loc, "tensor file \"{}\": field \"{}\" is larger than the file",
                                  path, name);
            total *= extent;
            f.shape.push_back(size_t(extent));
        }
        if (offset > file.size() || total > file.size() - offset)
            throw_input_error(loc, "tensor file \"{}\": field \"{}\" lies past the file's end",
                              path, name);
        f.bytes.assign(file.begin() + ptrdiff_t(offset), file.begin() + ptrdiff_t(offset + total));
        if (!fields.emplace(name, std::move(f)).second)
            throw_input_error(loc, "tensor file \"{}\": field \"{}\" given twice", path, name);
    }
    return fields;
}

}  // namespace ml
