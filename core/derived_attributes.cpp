#include "core/derived_attributes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace tc {

const std::vector<std::string>& derivedAttributeNames() {
    static const std::vector<std::string> names = {"arc_length", "line_length",   "curvature",
                                                   "torsion",    "local_density", "speed"};
    return names;
}

bool isDerivedAttribute(const std::string& name) {
    const auto& names = derivedAttributeNames();
    return std::find(names.begin(), names.end(), name) != names.end();
}

namespace {

// Runs f(begin, end) for every polyline, in parallel: each writes only its own vertices.
template <typename F>
void forEachPolyline(const LineSet& lines, F f) {
    tbb::parallel_for(std::size_t(0), lines.polylineCount(),
                      [&](std::size_t p) { f(std::size_t(lines.offsets[p]), std::size_t(lines.offsets[p + 1])); });
}

// Double precision: arc lengths of long polylines accumulate many small segments.
glm::dvec3 at(const LineSet& lines, std::size_t i) {
    return glm::dvec3(lines.positions[i]);
}

void arcLength(const LineSet& lines, std::vector<float>& out, bool total) {
    forEachPolyline(lines, [&](std::size_t begin, std::size_t end) {
        double s = 0;
        out[begin] = 0;
        for (std::size_t i = begin + 1; i < end; ++i) {
            s += glm::length(at(lines, i) - at(lines, i - 1));
            out[i] = float(s);
        }
        if (total) std::fill(out.begin() + std::ptrdiff_t(begin), out.begin() + std::ptrdiff_t(end), float(s));
    });
}

void curvature(const LineSet& lines, std::vector<float>& out) {
    forEachPolyline(lines, [&](std::size_t begin, std::size_t end) {
        if (end - begin < 3) {
            std::fill(out.begin() + std::ptrdiff_t(begin), out.begin() + std::ptrdiff_t(end), 0.0f);
            return;
        }
        for (std::size_t i = begin + 1; i + 1 < end; ++i) {
            // Menger curvature: 4 * triangle area / product of the side lengths.
            glm::dvec3 a = at(lines, i) - at(lines, i - 1), b = at(lines, i + 1) - at(lines, i);
            double denominator = glm::length(a) * glm::length(b) * glm::length(a + b);
            out[i] = denominator > 0 ? float(2 * glm::length(glm::cross(a, b)) / denominator) : 0.0f;
        }
        out[begin] = out[begin + 1];
        out[end - 1] = out[end - 2];
    });
}

void torsion(const LineSet& lines, std::vector<float>& out) {
    forEachPolyline(lines, [&](std::size_t begin, std::size_t end) {
        std::fill(out.begin() + std::ptrdiff_t(begin), out.begin() + std::ptrdiff_t(end), 0.0f);
        if (end - begin < 4) return;
        // Binormal at each interior vertex; zero where the two segments are (nearly) collinear.
        std::vector<glm::dvec3> binormal(end - begin, glm::dvec3(0));
        for (std::size_t i = begin + 1; i + 1 < end; ++i) {
            glm::dvec3 a = at(lines, i) - at(lines, i - 1), b = at(lines, i + 1) - at(lines, i);
            glm::dvec3 n = glm::cross(a, b);
            double len = glm::length(n);
            if (len > 1e-12 * glm::length(a) * glm::length(b)) binormal[i - begin] = n / len;
        }
        // Torsion per segment (i, i+1): the signed angle between the binormals at its ends; the
        // sign is + when the binormal turns right-handed about the tangent (a right-handed helix).
        std::vector<double> segment(end - begin, 0.0);
        for (std::size_t i = begin + 1; i + 2 < end; ++i) {
            glm::dvec3 b0 = binormal[i - begin], b1 = binormal[i + 1 - begin];
            if (b0 == glm::dvec3(0) || b1 == glm::dvec3(0)) continue;
            // A binormal that flips (an inflection of a planar curve: the curvature changes
            // sign) is not a twist of the osculating plane; compare against the flipped one.
            if (glm::dot(b0, b1) < 0) b1 = -b1;
            glm::dvec3 tangent = at(lines, i + 1) - at(lines, i);
            double angle = std::atan2(glm::dot(glm::cross(b0, b1), glm::normalize(tangent)), glm::dot(b0, b1));
            segment[i - begin] = angle / glm::length(tangent);
        }
        // Vertex = mean of its defined neighbouring segments (1..end-3 are defined).
        for (std::size_t i = begin; i < end; ++i) {
            std::size_t k = i - begin;
            std::size_t lo = std::max<std::size_t>(k, 2) - 1, hi = std::min(k, end - begin - 3);
            if (lo > hi) lo = hi = std::clamp<std::size_t>(k, 1, end - begin - 3);
            double sum = 0;
            for (std::size_t s = lo; s <= hi; ++s) sum += segment[s];
            out[i] = float(sum / double(hi - lo + 1));
        }
    });
}

void localDensity(const LineSet& lines, std::vector<float>& out) {
    if (lines.vertexCount() == 0) return;
    const glm::dvec3 lo(lines.bounds.lo), extent(lines.bounds.extent());
    const double longest = std::max({extent.x, extent.y, extent.z});
    const double voxel = longest > 0 ? longest / kLocalDensityResolution : 1.0;
    glm::ivec3 dims = glm::max(glm::ivec3(glm::ceil(extent / voxel)), glm::ivec3(1));
    dims = glm::min(dims, glm::ivec3(kLocalDensityResolution));
    auto cellOf = [&](const glm::dvec3& p) {
        glm::ivec3 c = glm::ivec3(glm::floor((p - lo) / voxel));
        c = glm::clamp(c, glm::ivec3(0), dims - 1);
        return std::uint32_t((c.z * dims.y + c.y) * dims.x + c.x);
    };
    const std::size_t voxels = std::size_t(dims.x) * dims.y * dims.z;
    std::vector<std::uint32_t> count(voxels, 0);
    // lastLine[c] = 1 + the last polyline counted in voxel c: each polyline is counted once per
    // voxel however often it returns there, without sorting its voxel list.
    std::vector<std::uint32_t> lastLine(voxels, 0);
    for (std::size_t p = 0; p < lines.polylineCount(); ++p) {
        const std::uint32_t stamp = std::uint32_t(p + 1);
        for (std::size_t i = lines.offsets[p]; i + 1 < lines.offsets[p + 1]; ++i) {
            glm::dvec3 a = at(lines, i), b = at(lines, i + 1);
            int steps = std::max(1, int(std::ceil(4 * glm::length(b - a) / voxel)));
            for (int s = 0; s <= steps; ++s) {
                std::uint32_t c = cellOf(glm::mix(a, b, double(s) / steps));
                if (lastLine[c] != stamp) lastLine[c] = stamp, ++count[c];
            }
        }
    }
    tbb::parallel_for(std::size_t(0), lines.vertexCount(),
                      [&](std::size_t i) { out[i] = float(count[cellOf(at(lines, i))]); });
}

void speed(const LineSet& lines, std::vector<float>& out) {
    std::vector<std::string> bases;
    if (!lines.velocity.empty()) bases.push_back(lines.velocity);  // the vector the lines were traced along
    for (const char* base : {"velocity", "vel", "v"}) bases.push_back(base);
    for (const std::string& base : bases)
        if (const Attribute* m = lines.attribute(base + "_magnitude")) {
            out = m->values;
            return;
        }
    for (const std::string& base : bases) {
        const Attribute* x = lines.attribute(std::string(base) + "_x");
        const Attribute* y = lines.attribute(std::string(base) + "_y");
        const Attribute* z = lines.attribute(std::string(base) + "_z");
        if (!x || !y || !z) continue;
        for (std::size_t i = 0; i < out.size(); ++i)
            out[i] = glm::length(glm::vec3(x->values[i], y->values[i], z->values[i]));
        return;
    }
    throw InputError(
        "\"speed\" needs a velocity: an attribute \"velocity_magnitude\" or components "
        "velocity_x/_y/_z (or vel_*, v_*)");
}

}  // namespace

Attribute computeDerivedAttribute(const LineSet& lines, const std::string& name) {
    Attribute a;
    a.name = name;
    a.values.assign(lines.vertexCount(), 0.0f);
    if (name == "arc_length")
        arcLength(lines, a.values, false);
    else if (name == "line_length")
        arcLength(lines, a.values, true);
    else if (name == "curvature")
        curvature(lines, a.values);
    else if (name == "torsion")
        torsion(lines, a.values);
    else if (name == "local_density")
        localDensity(lines, a.values);
    else if (name == "speed")
        speed(lines, a.values);
    else
        TC_CHECK(isDerivedAttribute(name));
    a.updateRange();
    return a;
}

void addDerivedAttributes(LineSet& lines, const std::vector<std::string>& names) {
    for (const auto& name : names)
        if (isDerivedAttribute(name) && !lines.attribute(name))
            lines.attributes.push_back(computeDerivedAttribute(lines, name));
}

}  // namespace tc
