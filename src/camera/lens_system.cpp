#include "camera/lens_system.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/parallel.h"
#include "sampling/warps.h"

namespace ml {

namespace {

// Where the ray meets the sphere of `radius` centred at z = z_centre on the axis: the hit the
// element's side of the sphere holds (the nearer one when the ray travels towards the sphere's
// centre's side, as pbrt-v4 picks it), and the normal there facing the ray.
bool intersect_element(float radius, float z_centre, const Ray& r, float* t, Vec3* n) {
    Vec3 o = r.o - Vec3(0, 0, z_centre);
    float a = dot(r.d, r.d), b = 2 * dot(r.d, o), c = dot(o, o) - radius * radius;
    double disc = double(b) * b - 4 * double(a) * c;
    if (disc < 0) return false;
    double root = std::sqrt(disc);
    double q = b < 0 ? -0.5 * (b - root) : -0.5 * (b + root);
    float t0 = float(q / a), t1 = float(c / q);
    if (t0 > t1) std::swap(t0, t1);
    bool closer = (r.d.z > 0) != (radius < 0);
    *t = closer ? t0 : t1;
    if (!(*t >= 0)) return false;
    Vec3 normal = normalize(o + r.d * *t);
    *n = dot(normal, r.d) > 0 ? -normal : normal;  // facing against the ray
    return true;
}

// Snell's law for unit `wi` (pointing away from the surface) and `n` on its side; eta = eta_t /
// eta_i. False on total internal reflection.
bool refract_dir(const Vec3& wi, const Vec3& n, float eta, Vec3* wt) {
    float cos_i = dot(n, wi);
    Vec3 nn = n;
    if (cos_i < 0) {
        eta = 1 / eta;
        cos_i = -cos_i;
        nn = -n;
    }
    float sin2_t = std::max(0.f, 1 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1) return false;
    float cos_t = std::sqrt(1 - sin2_t);
    *wt = -wi / eta + nn * (cos_i / eta - cos_t);
    return true;
}

// Lens space flips z: the film at 0, the lens towards -z.
Ray flip_z(const Ray& r) {
    return Ray{Vec3(r.o.x, r.o.y, -r.o.z), Vec3(r.d.x, r.d.y, -r.d.z), r.tmax, r.time};
}

float radical_inverse(int base, uint32_t i) {
    float inv = 1.f / float(base), f = inv, v = 0;
    while (i) {
        v += float(i % uint32_t(base)) * f;
        i /= uint32_t(base);
        f *= inv;
    }
    return v;
}

}  // namespace

std::vector<float> read_lens_table(const std::string& path, const FileLoc& loc) {
    std::ifstream in(path);
    if (!in) throw_input_error(loc, "{}: cannot read the lens file", path);
    std::vector<float> values;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        line = line.substr(0, line.find('#'));
        std::istringstream words(line);
        std::string w;
        while (words >> w) {
            float v = 0;
            auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
            if (ec != std::errc() || end != w.data() + w.size() || !std::isfinite(v))
                throw_input_error(loc, "{}:{}: \"{}\" is not a number", path, number, w);
            values.push_back(v);
        }
    }
    if (values.empty()) throw_input_error(loc, "{}: the lens file holds no numbers", path);
    if (values.size() % 4 != 0)
        throw_input_error(loc,
                          "{}: a lens file holds rows of 4 numbers (curvature radius, thickness, "
                          "eta, aperture diameter), got {} numbers",
                          path, values.size());
    return values;
}

LensSystem::LensSystem(const std::vector<float>& table, float aperture_diameter_mm,
                       float focus_distance, float film_diagonal_mm, float aspect,
                       ApertureImage aperture, const FileLoc& loc)
    : m_aperture(std::move(aperture)), m_film_diagonal(film_diagonal_mm / 1000) {
    // 1. The film's physical extent, from its diagonal and the image's aspect.
    float x = std::sqrt(sqr(m_film_diagonal) / (1 + sqr(aspect)));
    m_film_half = Vec2(x / 2, aspect * x / 2);

    // 2. The interfaces, mm to metres; the stop's aperture is the one asked for, at most the
    // table's.
    int stops = 0;
    for (size_t i = 0; i + 3 < table.size(); i += 4) {
        Element e{table[i] / 1000, table[i + 1] / 1000, table[i + 2], table[i + 3] / 1000 / 2};
        if (e.radius == 0) {
            ++stops;
            e.aperture_radius = std::min(e.aperture_radius, aperture_diameter_mm / 1000 / 2);
        }
        if (!(e.aperture_radius > 0) || e.thickness < 0 || e.eta < 0)
            throw_input_error(loc,
                              "lens row {}: the aperture diameter must be positive, the "
                              "thickness and eta not negative",
                              i / 4 + 1);
        m_elements.push_back(e);
    }
    if (m_elements.empty()) throw_input_error(loc, "the lens file has no elements");
    (void)stops;

    // 3. Focus: the last thickness (the rear element to the film) from the thick-lens model.
    m_elements.back().thickness = focus_thick_lens(focus_distance, loc);

    // 4. Exit-pupil bounds for 64 bands of film radius.
    const int bands = 64;
    m_pupil.resize(bands);
    parallel_for(0, bands, [&](int i) {
        float r0 = float(i) / bands * m_film_diagonal / 2;
        float r1 = float(i + 1) / bands * m_film_diagonal / 2;
        m_pupil[size_t(i)] = bound_exit_pupil(r0, r1);
    });
}

float LensSystem::front_z() const {
    float z = 0;
    for (const Element& e : m_elements) z += e.thickness;
    return z;
}

float LensSystem::trace_from_film(const Ray& r_camera, Ray* out) const {
    float element_z = 0, weight = 1;
    Ray r = flip_z(r_camera);
    for (int i = int(m_elements.size()) - 1; i >= 0; --i) {
        const Element& e = m_elements[size_t(i)];
        element_z -= e.thickness;
        float t;
        Vec3 n;
        bool stop = e.radius == 0;
        if (stop) {
            t = (element_z - r.o.z) / r.d.z;
            if (!(t >= 0)) return 0;
        } else if (!intersect_element(e.radius, element_z + e.radius, r, &t, &n)) {
            return 0;
        }
        Vec3 p = r.at(t);
        if (stop && !m_aperture.empty()) {
            weight = m_aperture.lookup(p.x / e.aperture_radius, p.y / e.aperture_radius);
            if (!(weight > 0)) return 0;
        } else if (sqr(p.x) + sqr(p.y) > sqr(e.aperture_radius)) {
            return 0;
        }
        r.o = p;
        if (!stop) {
            float eta_i = e.eta;
            float eta_t =
                (i > 0 && m_elements[size_t(i - 1)].eta != 0) ? m_elements[size_t(i - 1)].eta : 1.f;
            Vec3 w;
            if (!refract_dir(normalize(-r.d), n, eta_t / eta_i, &w)) return 0;
            r.d = w;
        }
    }
    if (out) *out = flip_z(r);
    return weight;
}

bool LensSystem::trace_from_scene(const Ray& r_camera, Ray* out) const {
    float element_z = -front_z();
    Ray r = flip_z(r_camera);
    for (size_t i = 0; i < m_elements.size(); ++i) {
        const Element& e = m_elements[i];
        float t;
        Vec3 n;
        bool stop = e.radius == 0;
        if (stop) {
            t = (element_z - r.o.z) / r.d.z;
            if (!(t >= 0)) return false;
        } else if (!intersect_element(e.radius, element_z + e.radius, r, &t, &n)) {
            return false;
        }
        Vec3 p = r.at(t);
        if (sqr(p.x) + sqr(p.y) > sqr(e.aperture_radius)) return false;
        r.o = p;
        if (!stop) {
            float eta_i = (i == 0 || m_elements[i - 1].eta == 0) ? 1.f : m_elements[i - 1].eta;
            float eta_t = e.eta != 0 ? e.eta : 1.f;
            Vec3 w;
            if (!refract_dir(normalize(-r.d), n, eta_t / eta_i, &w)) return false;
            r.d = w;
        }
        element_z += e.thickness;
    }
    if (out) *out = flip_z(r);
    return true;
}

float LensSystem::focus_thick_lens(float focus_distance, const FileLoc& loc) const {
    // Cardinal points of each side: a ray parallel to the axis at a small height, traced
    // through; where it crosses the axis is the focal point, where it reaches its incoming
    // height the principal plane.
    auto cardinal = [](const Ray& in, const Ray& out, float* pz, float* fz) {
        float tf = -out.o.x / out.d.x;
        *fz = -out.at(tf).z;
        float tp = (in.o.x - out.o.x) / out.d.x;
        *pz = -out.at(tp).z;
    };
    const float h = 0.001f * m_film_diagonal;
    float pz[2], fz[2];
    Ray scene_in{Vec3(h, 0, front_z() + 1), Vec3(0, 0, -1)}, film_out;
    if (!trace_from_scene(scene_in, &film_out))
        throw_input_error(loc,
                          "realistic camera: a ray near the axis does not pass the lens from the "
                          "scene (is the aperture stop extremely small?)");
    cardinal(scene_in, film_out, &pz[0], &fz[0]);
    Ray film_in{Vec3(h, 0, rear_z() - 1), Vec3(0, 0, 1)}, scene_out;
    if (trace_from_film(film_in, &scene_out) == 0)
        throw_input_error(loc,
                          "realistic camera: a ray near the axis does not pass the lens from the "
                          "film (is the aperture stop extremely small?)");
    cardinal(film_in, scene_out, &pz[1], &fz[1]);
    // The shift delta of the lens that images the plane at z = -focus_distance onto the film.
    float f = fz[0] - pz[0], z = -focus_distance;
    float c = (pz[1] - z - pz[0]) * (pz[1] - z - 4 * f - pz[0]);
    if (!(c > 0))
        throw_input_error(loc, "realistic camera: \"focusdistance\" {} is too short for this lens",
                          focus_distance);
    float delta = (pz[1] - z + pz[0] - std::sqrt(c)) / 2;
    return m_elements.back().thickness + delta;
}

PupilBounds LensSystem::bound_exit_pupil(float r0, float r1) const {
    // Rays from film points along [r0, r1] on the x axis to points of a square around the rear
    // element (half again its radius): the bounds of those that pass, grown by a sample spacing.
    // The bounds are rotated to each film point's angle, which holds for a round stop alone: a
    // shaped stop (an aperture image) is not rotationally symmetric, so its rotated bounds cut
    // some of its light, and the more samples (the less the bounds grow) the more, as pbrt-v4's
    // with its 2^20 (an L-shaped image stop against pbrt-v4: +3.2% with 2^16, +1.0% with 2^18,
    // -0.2% with 2^20, which takes 4 s here).
    const int n_samples = m_aperture.empty() ? 1 << 16 : 1 << 18;
    const float rear = m_elements.back().aperture_radius * 1.5f;
    PupilBounds b;
    for (int i = 0; i < n_samples; ++i) {
        Vec3 p_film(lerp((float(i) + 0.5f) / n_samples, r0, r1), 0, 0);
        Vec2 u(radical_inverse(2, uint32_t(i)), radical_inverse(3, uint32_t(i)));
        Vec2 p_rear(lerp(u.x, -rear, rear), lerp(u.y, -rear, rear));
        if (b.inside(p_rear)) continue;
        Vec3 p(p_rear.x, p_rear.y, rear_z());
        if (trace_from_film(Ray{p_film, p - p_film}, nullptr) > 0) b.expand(p_rear);
    }
    if (b.lo.x > b.hi.x) return PupilBounds{};
    const float grow = 2 * std::sqrt(2.f) * 2 * rear / std::sqrt(float(n_samples));
    b.lo = Vec2(b.lo.x - grow, b.lo.y - grow);
    b.hi = Vec2(b.hi.x + grow, b.hi.y + grow);
    return b;
}

LensRay LensSystem::generate(const Vec2& s, const Vec2& u) const {
    // 1. The film point: raster x to -x (the lens flips the image), raster y down to +y.
    Vec2 q(lerp(s.x, -m_film_half.x, m_film_half.x), lerp(s.y, -m_film_half.y, m_film_half.y));
    Vec3 p_film(-q.x, q.y, 0);
    // 2. A point of the exit-pupil bounds of its band, rotated to the film point's angle.
    float r_film = std::sqrt(sqr(p_film.x) + sqr(p_film.y));
    int band = std::min(int(m_pupil.size()) - 1,
                        int(r_film / (m_film_diagonal / 2) * float(m_pupil.size())));
    const PupilBounds& b = m_pupil[size_t(band)];
    LensRay out;
    if (b.empty()) return out;
    Vec2 p_lens(lerp(u.x, b.lo.x, b.hi.x), lerp(u.y, b.lo.y, b.hi.y));
    float sin_t = r_film != 0 ? p_film.y / r_film : 0, cos_t = r_film != 0 ? p_film.x / r_film : 1;
    Vec3 p_pupil(cos_t * p_lens.x - sin_t * p_lens.y, sin_t * p_lens.x + cos_t * p_lens.y,
                 rear_z());
    // 3. Through the lens; the weight.
    Ray from_film{p_film, p_pupil - p_film};
    float weight = trace_from_film(from_film, &out.ray);
    if (weight == 0) return out;
    out.ray.d = normalize(out.ray.d);
    float cos_theta = normalize(from_film.d).z;
    out.weight = weight * sqr(sqr(cos_theta)) * b.area() / sqr(rear_z());
    return out;
}

}  // namespace ml
