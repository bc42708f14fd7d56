// The folder graph of src/, apps/ and python/ (docs/ARCHITECTURE.md): every `#include
// "folder/file.h"` is an edge from the including file's folder to `folder`. Edges may only point
// down the layer table below, and no chain of includes, between files or between folders, may come
// back to where it started. The checks run on the sources themselves, so a new include that breaks
// the layering fails here, and on small made-up graphs, so that the checks are shown to fail when
// they should.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// THE LAYER TABLE, lowest first: a folder may include its own files and those of folders in
// lower layers. Folders in the same layer do not include each other.
const std::vector<std::vector<std::string>> kLayers = {
    {"core"},                     // math, colour, errors, assertions, parameters, threads
    {"sampling", "distributed"},  // samplers and warps; MPI's world (mpirun's ranks)
    {"geometry"},                 // meshes, shapes, Embree
    {"camera", "film"},           // rays from the lens; pixels, filters, images
    {"materials", "media"},       // BSDFs and textures; participating media
    {"lights"},                   // light sources and what they become as point lights
    {"scene"},                    // pbrt-v4 parsing and the assembled scene
    {"render", "transport"},      // the integrator interface and render loop; light transport
    {"bidir", "manylight"},       // bidirectional paths; point-light sets, trees, gathering
    {"integrators"},              // the algorithms, the registry and the render job
    {"apps", "python"},           // the command line; the Python module
};

// Libraries wrapped in one place: (include prefix, the files that may include it).
const std::vector<std::pair<std::string, std::set<std::string>>> kWrappedLibraries = {
    {"embree3/", {"src/geometry/embree_scene.cpp"}},
    {"tbb/", {"src/core/parallel.h"}},
    {"mpi.h", {"src/distributed/mpi_world.cpp"}},
    {"nanovdb/", {"src/media/nanovdb_medium.cpp"}},
};

struct Include {
    std::string from;  // file, relative to the source root
    std::string to;    // file, relative to the source root; or the <library/path>
    int line = 0;
};

struct Sources {
    std::vector<std::string> files;  // relative to the source root, e.g. "src/core/math.h"
    std::vector<Include> project;    // "..." includes, resolved
    std::vector<Include> system;     // <...> includes
    std::vector<std::string> unresolved;
};

// The folder a file belongs to: src/<folder>/..., apps or python.
std::string folder_of(const std::string& file) {
    fs::path p(file);
    auto it = p.begin();
    if (*it == "apps" || *it == "python") return it->string();
    ++it;
    return it->string();
}

Sources read_sources(const fs::path& root) {
    Sources s;
    for (const char* top : {"src", "apps", "python"})
        for (const auto& e : fs::recursive_directory_iterator(root / top)) {
            std::string ext = e.path().extension().string();
            if (e.is_regular_file() && (ext == ".h" || ext == ".cpp"))
                s.files.push_back(fs::relative(e.path(), root).generic_string());
        }
    std::sort(s.files.begin(), s.files.end());
    const std::regex include_re(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
    for (const std::string& file : s.files) {
        std::ifstream in(root / file);
        std::string text;
        for (int line = 1; std::getline(in, text); ++line) {
            std::smatch m;
            if (!std::regex_search(text, m, include_re)) continue;
            std::string name = m[2];
            if (m[1] == "<") {
                s.system.push_back({file, name, line});
                continue;
            }
            // As the compiler looks: beside the file, then in src/.
            std::string beside = (fs::path(file).parent_path() / name).generic_string();
            std::string in_src = "src/" + name;
            if (fs::exists(root / beside))
                s.project.push_back({file, beside, line});
            else if (fs::exists(root / in_src))
                s.project.push_back({file, in_src, line});
            else
                s.unresolved.push_back(file + ":" + std::to_string(line) + ": " + name);
        }
    }
    return s;
}

std::map<std::string, int> layer_ranks() {
    std::map<std::string, int> rank;
    for (size_t i = 0; i < kLayers.size(); ++i)
        for (const std::string& f : kLayers[i]) rank[f] = int(i);
    return rank;
}

// Edges between folders that do not point strictly down the table (or name a folder the table
// does not have), as "from -> to (file:line)".
std::vector<std::string> upward_edges(const std::vector<Include>& includes,
                                      const std::map<std::string, int>& rank) {
    std::vector<std::string> bad;
    for (const Include& inc : includes) {
        std::string a = folder_of(inc.from), b = folder_of(inc.to);
        if (a == b) continue;
        auto ra = rank.find(a), rb = rank.find(b);
        if (ra == rank.end() || rb == rank.end() || rb->second >= ra->second)
            bad.push_back(a + " -> " + b + " (" + inc.from + ":" + std::to_string(inc.line) +
                          " includes " + inc.to + ")");
    }
    return bad;
}

// A cycle in a directed graph, as the list of its nodes (first == last), or nullopt.
std::optional<std::vector<std::string>> find_cycle(
    const std::map<std::string, std::set<std::string>>& graph) {
    enum class Mark { New, Open, Done };
    std::map<std::string, Mark> mark;
    std::vector<std::string> stack;
    std::optional<std::vector<std::string>> cycle;
    std::function<void(const std::string&)> visit = [&](const std::string& n) {
        mark[n] = Mark::Open;
        stack.push_back(n);
        auto it = graph.find(n);
        if (it != graph.end())
            for (const std::string& m : it->second) {
                if (cycle) break;
                if (mark[m] == Mark::Open) {
                    auto start = std::find(stack.begin(), stack.end(), m);
                    cycle = std::vector<std::string>(start, stack.end());
                    cycle->push_back(m);
                } else if (mark[m] == Mark::New) {
                    visit(m);
                }
            }
        stack.pop_back();
        mark[n] = Mark::Done;
    };
    for (const auto& [n, _] : graph)
        if (!cycle && mark[n] == Mark::New) visit(n);
    return cycle;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

const Sources& sources() {
    static const Sources s = read_sources(MANYLIGHT_SOURCE_DIR);
    return s;
}

}  // namespace

TEST(Layering, TheSourcesAreFound) {
    // Guards the other tests against passing on an empty tree.
    EXPECT_GT(sources().files.size(), 100u);
    EXPECT_GT(sources().project.size(), 300u);
}

TEST(Layering, EveryProjectIncludeResolves) {
    EXPECT_TRUE(sources().unresolved.empty()) << join(sources().unresolved, "\n");
}

TEST(Layering, EveryFolderIsInTheTable) {
    std::map<std::string, int> rank = layer_ranks();
    std::set<std::string> missing;
    for (const std::string& f : sources().files)
        if (!rank.count(folder_of(f))) missing.insert(folder_of(f));
    EXPECT_TRUE(missing.empty()) << "folders missing from kLayers: "
                                 << join({missing.begin(), missing.end()}, ", ");
}

TEST(Layering, IncludesOnlyPointDown) {
    std::vector<std::string> bad = upward_edges(sources().project, layer_ranks());
    EXPECT_TRUE(bad.empty()) << bad.size() << " includes against the layer table:\n"
                             << join(bad, "\n");
}

TEST(Layering, FoldersFormNoCycle) {
    std::map<std::string, std::set<std::string>> graph;
    for (const Include& inc : sources().project)
        if (folder_of(inc.from) != folder_of(inc.to))
            graph[folder_of(inc.from)].insert(folder_of(inc.to));
    auto cycle = find_cycle(graph);
    EXPECT_FALSE(cycle) << "folder cycle: "
                        << join(cycle.value_or(std::vector<std::string>()), " -> ");
}

TEST(Layering, FilesFormNoIncludeCycle) {
    std::map<std::string, std::set<std::string>> graph;
    for (const Include& inc : sources().project) graph[inc.from].insert(inc.to);
    auto cycle = find_cycle(graph);
    EXPECT_FALSE(cycle) << "include cycle: "
                        << join(cycle.value_or(std::vector<std::string>()), " -> ");
}

TEST(Layering, WrappedLibrariesAreIncludedInOnePlace) {
    for (const auto& [prefix, allowed] : kWrappedLibraries)
        for (const Include& inc : sources().system)
            if (inc.to.rfind(prefix, 0) == 0) {
                EXPECT_TRUE(allowed.count(inc.from))
                    << inc.from << ":" << inc.line << " includes <" << inc.to << ">";
            }
}

// The checks themselves, on graphs made up to break them.
TEST(Layering, CheckFindsAnUpwardEdge) {
    std::map<std::string, int> rank = layer_ranks();
    std::vector<Include> down = {{"src/lights/a.cpp", "src/core/math.h", 1}};
    std::vector<Include> up = {{"src/lights/a.cpp", "src/manylight/b.h", 3}};
    std::vector<Include> sideways = {{"src/film/a.cpp", "src/camera/camera.h", 2}};
    std::vector<Include> unknown = {{"src/newfolder/a.cpp", "src/core/math.h", 1}};
    EXPECT_TRUE(upward_edges(down, rank).empty());
    ASSERT_EQ(upward_edges(up, rank).size(), 1u);
    EXPECT_EQ(upward_edges(up, rank)[0],
              "lights -> manylight (src/lights/a.cpp:3 includes src/manylight/b.h)");
    EXPECT_EQ(upward_edges(sideways, rank).size(), 1u);
    EXPECT_EQ(upward_edges(unknown, rank).size(), 1u);
}

TEST(Layering, CheckFindsACycle) {
    std::map<std::string, std::set<std::string>> acyclic = {{"a", {"b", "c"}}, {"b", {"c"}}};
    EXPECT_FALSE(find_cycle(acyclic));
    std::map<std::string, std::set<std::string>> cyclic = {
        {"a", {"b"}}, {"b", {"c"}}, {"c", {"d", "b"}}};
    auto cycle = find_cycle(cyclic);
    ASSERT_TRUE(cycle);
    EXPECT_EQ(join(*cycle, " -> "), "b -> c -> b");
}
