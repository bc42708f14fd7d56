#include "geometry/ply.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>

#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <mutex>
#include <streambuf>
#include <vector>

#include "geometry/ply_importer.h"

namespace ml {

namespace {

// ---- Step 1: the header, parsed only far enough to know the size of everything. ----

struct PlyProp {
    std::string name;
    int size = 0;        // scalar size, or the list's item size
    int count_size = 0;  // list count size; 0 for a scalar
    bool item_signed = false;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProp> props;
};

enum class PlyFormat { Ascii, BinaryLE, BinaryBE };

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t data_offset = 0;
};

int type_size(std::string_view t, bool* is_signed) {
    *is_signed =
        t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
    if (t == "char" || t == "int8" || t == "uchar" || t == "uint8") return 1;
    if (t == "short" || t == "int16" || t == "ushort" || t == "uint16") return 2;
    if (t == "int" || t == "int32" || t == "uint" || t == "uint32" || t == "float" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

class Fail {
public:
    Fail(const std::string& path, const FileLoc& loc) : m_path(path), m_loc(loc) {}
    template <typename... Args>
    [[noreturn]] void operator()(fmt::format_string<Args...> f, Args&&... args) const {
        throw InputError(m_loc, m_path + ": " + fmt::format(f, std::forward<Args>(args)...));
    }

private:
    const std::string& m_path;
    const FileLoc& m_loc;
};

PlyHeader parse_header(std::string_view data, const Fail& fail) {
    PlyHeader h;
    size_t pos = 0;
    int line_no = 0;
    bool have_format = false;
    for (;;) {
        size_t eol = data.find('\n', pos);
        if (eol == std::string_view::npos) fail("malformed PLY header: no end_header");
        std::string_view line = data.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_no;
        if (line_no == 1) {
            if (split_words(line) != std::vector<std::string_view>{"ply"})
                fail("not a PLY file (no \"ply\" magic)");
            continue;
        }
        // The header is ASCII text: OpenMesh's reader splits it on every space character
        // (vertical tab and form feed too) and loops forever on what it cannot read, so a
        // control character would make the two readers see different headers.
        bool comment = line.substr(0, 8) == "comment " || line.substr(0, 9) == "obj_info ";
        for (char ch : line) {
            auto c = static_cast<unsigned char>(ch);
            if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f || (c >= 0x80 && !comment))
                fail("PLY header line {}: byte {} is not ASCII text", line_no, int(c));
        }
        auto w = split_words(line);
        if (!w.empty() && w[0] == "obj_info") {
            // OpenMesh's reader takes an obj_info line's words as the header's own (only
            // comments are skipped whole), and loops forever on an `element` it cannot read.
            for (size_t k = 1; k < w.size(); ++k)
                if (w[k] == "ply" || w[k] == "format" || w[k] == "element" || w[k] == "property" ||
                    w[k] == "comment" || w[k] == "obj_info" || w[k] == "end_header")
                    fail("PLY header line {}: the header keyword \"{}\" inside obj_info", line_no,
                         w[k]);
            continue;
        }
        if (w.empty() || w[0] == "comment") continue;
        if (w[0] == "end_header") break;
        if (w[0] == "format") {
            if (have_format) fail("PLY header line {}: a second format line", line_no);
            // PLY has one version, 1.0; OpenMesh's reader loops forever on a version that is
            // not a number.
            double version = 0;
            if (w.size() != 3 ||
                std::from_chars(w[2].data(), w[2].data() + w[2].size(), version).ptr !=
                    w[2].data() + w[2].size() ||
                version != 1.0)
                fail(
                    "malformed PLY header line {}: the format must be ascii, "
                    "binary_little_endian or binary_big_endian, version 1.0",
                    line_no);
            if (w[1] == "ascii")
                h.format = PlyFormat::Ascii;
            else if (w[1] == "binary_little_endian")
                h.format = PlyFormat::BinaryLE;
            else if (w[1] == "binary_big_endian")
                h.format = PlyFormat::BinaryBE;
            else
                fail("unknown PLY format \"{}\"", w[1]);
            have_format = true;
        } else if (w[0] == "element") {
            // OpenMesh reads the count into an unsigned int: a larger one fails its stream, and
            // its header loop never ends (an element of no properties passes the body's check).
            uint32_t count = 0;
            if (w.size() != 3) fail("malformed PLY header line {}", line_no);
            auto [end, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
            if (ec != std::errc() || end != w[2].data() + w[2].size())
                fail(
                    "malformed PLY header line {}: the count \"{}\" is not a number from 0 to "
                    "4294967295",
                    line_no, w[2]);
            h.elements.push_back(PlyElement{std::string(w[1]), count, {}});
        } else if (w[0] == "property") {
            if (h.elements.empty())
                fail("PLY header line {}: property before any element", line_no);
            PlyProp p;
            bool sgn = false;
            if (w.size() == 5 && w[1] == "list") {
                p.count_size = type_size(w[2], &sgn);
                p.size = type_size(w[3], &p.item_signed);
                p.name = std::string(w[4]);
                if (!p.count_size || !p.size)
                    fail("PLY header line {}: unknown property type", line_no);
            } else if (w.size() == 3) {
                p.size = type_size(w[1], &p.item_signed);
                p.name = std::string(w[2]);
                if (!p.size)
                    fail("PLY header line {}: unknown property type \"{}\"", line_no, w[1]);
            } else {
                fail("malformed PLY header line {}", line_no);
            }
            h.elements.back().props.push_back(std::move(p));
        } else {
            fail("malformed PLY header line {}: \"{}\"", line_no, std::string(line));
        }
    }
    if (!have_format) fail("malformed PLY header: no format line");
    h.data_offset = pos;
    return h;
}

// ---- Step 2: walk the body to check it holds what the header promises. ----

uint64_t read_uint(const char* p, int size, bool big_endian, bool is_signed, bool* negative) {
    unsigned char b[8];
    std::memcpy(b, p, size);
    if (big_endian) std::reverse(b, b + size);
    uint64_t v = 0;
    for (int i = size - 1; i >= 0; --i) v = (v << 8) | b[i];
    *negative = is_signed && (b[size - 1] & 0x80);
    return v;
}

const PlyElement* find_element(const PlyHeader& h, const char* name) {
    for (const PlyElement& e : h.elements)
        if (e.name == name) return &e;
    return nullptr;
}

bool is_face_list(const PlyElement& e, const PlyProp& p) {
    return e.name == "face" && p.count_size &&
           (p.name == "vertex_indices" || p.name == "vertex_index");
}

PlyCounts walk_binary(std::string_view data, const PlyHeader& h, const Fail& fail) {
    PlyCounts c;
    c.binary = true;
    bool be = h.format == PlyFormat::BinaryBE;
    size_t pos = h.data_offset, size = data.size();
    for (const PlyElement& e : h.elements) {
        if (e.name == "vertex") c.vertices = e.count;
        bool fixed = true;
        uint64_t record = 0;
        for (const PlyProp& p : e.props) {
            fixed = fixed && !p.count_size;
            record += p.size;
        }
        if (fixed) {
            if (record != 0 && e.count > (size - pos) / record)
                fail("truncated: {} {} records of {} bytes do not fit in the file", e.count, e.name,
                     record);
            pos += e.count * record;
            continue;
        }
        for (uint64_t i = 0; i < e.count; ++i) {
            for (const PlyProp& p : e.props) {
                if (!p.count_size) {
                    if (size - pos < size_t(p.size)) fail("truncated in {} {}", e.name, i);
                    pos += p.size;
                    continue;
                }
                if (size - pos < size_t(p.count_size)) fail("truncated in {} {}", e.name, i);
                bool neg = false;
                uint64_t n = read_uint(data.data() + pos, p.count_size, be, false, &neg);
                pos += p.count_size;
                if (n > (size - pos) / p.size) fail("truncated in {} {}", e.name, i);
                if (is_face_list(e, p)) {
                    if (n >= 3) c.triangles += n - 2;
                    for (uint64_t k = 0; k < n; ++k) {
                        uint64_t idx = read_uint(data.data() + pos + k * p.size, p.size, be,
                                                 p.item_signed, &neg);
                        if (neg || idx >= c.vertices)
                            fail(
                                "face {} has vertex index {} out of range (the mesh has {} "
                                "vertices)",
                                i, neg ? -1 : int64_t(idx), c.vertices);
                    }
                }
                pos += n * p.size;
            }
        }
    }
    return c;
}

PlyCounts walk_ascii(std::string_view data, const PlyHeader& h, const Fail& fail) {
    PlyCounts c;
    size_t pos = h.data_offset;
    auto next_number = [&](const char* what, uint64_t i, double* v) {
        while (pos < data.size() && std::isspace((unsigned char)data[pos])) ++pos;
        size_t start = pos;
        while (pos < data.size() && !std::isspace((unsigned char)data[pos])) ++pos;
        if (start == pos) fail("truncated in {} {}", what, i);
        auto [ptr, ec] = std::from_chars(data.data() + start, data.data() + pos, *v);
        if (ec != std::errc() || ptr != data.data() + pos)
            fail("bad number \"{}\" in {} {}", std::string(data.substr(start, pos - start)), what,
                 i);
    };
    for (const PlyElement& e : h.elements) {
        if (e.name == "vertex") c.vertices = e.count;
        for (uint64_t i = 0; i < e.count; ++i) {
            for (const PlyProp& p : e.props) {
                double v = 0;
                next_number(e.name.c_str(), i, &v);
                if (!p.count_size) continue;
                if (v < 0 || v != std::floor(v) || v > 1e6)
                    fail("bad list length in {} {}", e.name, i);
                uint64_t n = uint64_t(v);
                if (is_face_list(e, p) && n >= 3) c.triangles += n - 2;
                for (uint64_t k = 0; k < n; ++k) {
                    next_number(e.name.c_str(), i, &v);
                    if (is_face_list(e, p) &&
                        (v < 0 || v >= double(c.vertices) || v != std::floor(v)))
                        fail("face {} has vertex index {} out of range (the mesh has {} vertices)",
                             i, v, c.vertices);
                }
            }
        }
    }
    return c;
}

PlyCounts validate(std::string_view data, const Fail& fail) {
    PlyHeader h = parse_header(data, fail);
    const PlyElement* vertex = find_element(h, "vertex");
    const PlyElement* face = find_element(h, "face");
    if (!vertex) fail("no vertex element");
    if (!face) fail("no face element");
    bool has[3] = {false, false, false};
    for (const PlyProp& p : vertex->props)
        for (int k = 0; k < 3; ++k)
            if (!p.count_size && p.name == std::string(1, char('x' + k))) has[k] = true;
    if (!has[0] || !has[1] || !has[2]) fail("vertices lack x, y or z");
    bool list = false;
    for (const PlyProp& p : face->props) list = list || is_face_list(*face, p);
    if (!list) fail("faces lack a vertex_indices list");
    if (vertex->count > (uint64_t(1) << 31) || face->count > (uint64_t(1) << 31))
        fail("too many vertices or faces");
    PlyCounts c =
        h.format == PlyFormat::Ascii ? walk_ascii(data, h, fail) : walk_binary(data, h, fail);
    c.vertices = vertex->count;
    c.faces = face->count;
    return c;
}

std::string read_file(const std::string& path, const Fail& fail) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail("no such file");
    if (std::filesystem::is_directory(path, ec)) fail("is a directory, not a PLY file");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open");
    in.seekg(0, std::ios::end);
    std::streamoff size = in.tellg();
    if (size < 0) fail("cannot read");
    std::string data(size_t(size), '\0');
    in.seekg(0);
    in.read(data.data(), size);
    if (!in) fail("cannot read");
    return data;
}

// ---- Step 3: OpenMesh's reader on the validated bytes. ----

// An istream over memory we already hold, so the file is read from disk once.
class MemoryBuf : public std::streambuf {
public:
    MemoryBuf(char* data, size_t size) { setg(data, data, data + size); }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        char* target = dir == std::ios_base::beg   ? eback() + off
                       : dir == std::ios_base::cur ? gptr() + off
                                                   : egptr() + off;
        if (target < eback() || target > egptr()) return pos_type(off_type(-1));
        setg(eback(), target, egptr());
        return pos_type(target - eback());
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }
};

// OpenMesh's PLY reader keeps per-file state in mutable members, so one instance cannot serve
// two threads. Each thread borrows its own from this pool. Readers register themselves with
// OpenMesh's IOManager on construction and are never unregistered, so they live forever.
class ReaderPool {
public:
    OpenMesh::IO::_PLYReader_* acquire() {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_free.empty()) return new OpenMesh::IO::_PLYReader_();
        auto* r = m_free.back();
        m_free.pop_back();
        return r;
    }
    void release(OpenMesh::IO::_PLYReader_* r) {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_free.push_back(r);
    }

private:
    std::mutex m_mutex;
    std::vector<OpenMesh::IO::_PLYReader_*> m_free;
};

ReaderPool& reader_pool() {
    static ReaderPool* pool = [] {
        // OpenMesh reports to the console; our errors carry the file instead.
        omerr().disable();
        omout().disable();
        omlog().disable();
        return new ReaderPool();
    }();
    return *pool;
}

}  // namespace

PlyCounts scan_ply(const std::string& path, const FileLoc& loc) {
    Fail fail(path, loc);
    std::string data = read_file(path, fail);
    return validate(data, fail);
}

std::unique_ptr<TriangleMesh> load_ply(const std::string& path, const FileLoc& loc) {
    std::string data = read_file(path, Fail(path, loc));
    return load_ply_data(std::move(data), path, loc);
}

std::unique_ptr<TriangleMesh> load_ply_data(std::string data, const std::string& path,
                                            const FileLoc& loc) {
    Fail fail(path, loc);
    PlyCounts counts = validate(data, fail);

    auto mesh = std::make_unique<TriangleMesh>();
    PlyImporter importer(*mesh, counts.vertices, counts.triangles);
    MemoryBuf buf(data.data(), data.size());
    std::istream in(&buf);
    OpenMesh::IO::Options opt =
        OpenMesh::IO::Options::VertexNormal | OpenMesh::IO::Options::VertexTexCoord;
    ReaderPool& pool = reader_pool();
    OpenMesh::IO::_PLYReader_* reader = pool.acquire();
    bool ok = false;
    try {
        ok = reader->read(in, importer, opt);
    } catch (...) {
        pool.release(reader);
        fail("OpenMesh could not read it");
    }
    pool.release(reader);
    if (!ok) fail("OpenMesh could not read it");
    if (!importer.error().empty()) fail("{}", importer.error());
    if (!mesh->n.empty()) mesh->n.resize(mesh->p.size());
    if (!mesh->uv.empty()) mesh->uv.resize(mesh->p.size());
    // Counts OpenMesh returned against the header: a mismatch means a misread.
    if (mesh->p.size() != counts.vertices)
        fail("read {} vertices, the header says {}", mesh->p.size(), counts.vertices);
    if (importer.faces() != counts.faces)
        fail("read {} faces, the header says {}", importer.faces(), counts.faces);
    if (mesh->triangle_count() != counts.triangles)
        fail("read {} triangles, the faces hold {}", mesh->triangle_count(), counts.triangles);
    if (mesh->indices.empty()) fail("the mesh has no faces");
    for (size_t i = 0; i < mesh->p.size(); ++i)
        if (!is_finite(mesh->p[i])) fail("vertex {} has a non-finite coordinate", i);
    for (size_t i = 0; i < mesh->n.size(); ++i)
        if (!is_finite(mesh->n[i])) fail("vertex {} has a non-finite normal", i);
    for (size_t i = 0; i < mesh->uv.size(); ++i)
        if (!std::isfinite(mesh->uv[i].x) || !std::isfinite(mesh->uv[i].y))
            fail("vertex {} has a non-finite texture coordinate", i);
    return mesh;
}

}  // namespace ml
