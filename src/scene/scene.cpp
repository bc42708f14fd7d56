#include "scene/scene.h"

namespace ml {

Scene::Scene(SceneDesc desc) : m_desc(std::move(desc)) {
    std::vector<const TriangleMesh*> meshes;
    meshes.reserve(m_desc.meshes.size());
    for (const auto& m : m_desc.meshes) {
        meshes.push_back(m.get());
        m_moves = m_moves || m->moves();
        m_has_media = m_has_media || m->medium_interface;
    }
    m_has_media = m_has_media || m_desc.camera_medium;
    for (const auto& m : m_desc.media) m_has_emitting_media = m_has_emitting_media || m->emits();
    m_has_emitting_media = m_has_emitting_media && m_has_media;
    m_embree = std::make_unique<EmbreeScene>(meshes, m_desc.transform_start_time,
                                             m_desc.transform_end_time);
    m_bounds = m_embree->bounds();
    if (m_bounds.empty()) m_bounds.expand(Vec3(0, 0, 0));
    for (size_t i = 0; i < m_desc.lights.size(); ++i) {
        Light* l = m_desc.lights[i].get();
        l->index = int(i);
        l->preprocess(m_bounds);
        if (l->type() == LightType::Infinite) m_infinite.push_back(l);
    }
}

size_t Scene::triangle_count() const {
    size_t n = 0;
    for (const auto& m : m_desc.meshes) n += m->triangle_count();
    return n;
}

}  // namespace ml
