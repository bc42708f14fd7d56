// What the parser tracks between directives: the current transform and attributes (pbrt-v4's
// graphics state), the scopes that save and restore them, and shapes waiting to be built.
#pragma once

#include <exception>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/params.h"
#include "geometry/mesh.h"

namespace ml {

// An AreaLightSource directive; it applies to every following Shape in its attribute scope.
struct AreaLightSpec {
    std::string type;
    ParameterList params;
    FileLoc loc;
};

// Which of the two CTMs (start and end of the motion) the transform directives change
// (pbrt-v4's ActiveTransform StartTime|EndTime|All).
enum ActiveTransformBits { kStartTransform = 1, kEndTransform = 2, kAllTransforms = 3 };

struct GraphicsState {
    // Object to world at the next directive, at the start and at the end of the motion
    // (TransformTimes); equal when nothing moves.
    Transform ctm[2];
    int active_transforms = kAllTransforms;
    bool reverse_orientation = false;
    const Material* material = nullptr;  // null: the default material
    std::shared_ptr<const AreaLightSpec> area_light;
    // `MediumInterface "inside" "outside"`: the media named for the shapes (and the camera)
    // that follow; empty: vacuum.
    std::string inside_medium, outside_medium;
    FileLoc medium_loc;  // where they were set
    // `Attribute "shape"|"light"|"material"|"texture" params`: defaults for those directives.
    std::map<std::string, ParameterList> attributes;
};

// AttributeBegin saves the whole state, TransformBegin only the transform, ObjectBegin the whole
// state as AttributeBegin does; each must be closed by its own End.
enum class ScopeKind { Attribute, Transform, Object };

struct Scope {
    ScopeKind kind;
    GraphicsState saved;
    FileLoc loc;  // where it was opened, for an unclosed scope at the end of the input
};

// An object-space mesh: built while parsing (trianglemesh, sphere, disk) or read from a PLY
// file after parsing, in parallel with the others.
struct MeshSource {
    std::unique_ptr<TriangleMesh> mesh;
    std::string ply_path;      // non-empty: still to be read
    FileLoc loc;               // for errors about the file
    int uses = 0;              // shapes built from it (instancing reuses sources)
    std::exception_ptr error;  // a failed PLY read, reported in file order at the end
};

// One world-space mesh to produce from a source.
// World at time t is instance.at(t) * object.at(t) (each an AnimatedTransform between the
// transform times): pbrt-v4 interpolates an instance's and its shapes' motions separately.
struct ShapeRecord {
    size_t source;
    Transform to_world[2];  // the shape's CTM at the start and end times
    Transform instance[2];  // the ObjectInstance's CTM (identity outside instances)
    bool reverse_orientation;
    const Material* material;
    std::shared_ptr<const AreaLightSpec> area_light;  // null: does not emit
    FileLoc loc;                                      // the Shape or ObjectInstance directive
    std::shared_ptr<const AlphaMask> alpha;           // "alpha": null where opaque
    std::string inside_medium, outside_medium;        // MediumInterface at the shape
};

// ObjectBegin ... ObjectEnd: shapes relative to the CTM at each ObjectInstance.
struct ObjectDef {
    std::vector<ShapeRecord> shapes;
    FileLoc loc;
};

}  // namespace ml
