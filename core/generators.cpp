#include "core/generators.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

namespace tc {

glm::vec3 tornadoVelocity(const glm::vec3& p) {
    // Crawfis' gen_tornado at time 0, evaluated continuously instead of on a grid.
    const float x = p.x, y = p.y, z = p.z;
    float xc = 0.5f + 0.1f * std::sin(10.0f * z);
    float yc = 0.5f + 0.1f * std::cos(3.0f * z);
    float r = 0.1f + 0.4f * z * z + 0.1f * z * std::sin(8.0f * z);
    float r2 = 0.2f + 0.1f * z;
    float temp = std::sqrt((y - yc) * (y - yc) + (x - xc) * (x - xc));
    float scale = std::abs(r - temp);
    scale = scale > r2 ? 0.8f - scale : 1.0f;
    float z0 = std::max(0.0f, 0.1f * (0.1f - temp * z));
    temp = std::sqrt(temp * temp + z0 * z0);
    scale = (r + r2 - temp) * scale / (temp + 1e-11f);
    scale = scale / (1.0f + z);
    return {scale * (y - yc) + 0.1f * (x - xc), scale * -(x - xc) + 0.1f * (y - yc), scale * z0 + 0.05f};
}

namespace {

// One streamline: RK4 on the unit-speed direction field, so vertices are evenly spaced.
std::vector<glm::vec3> trace(glm::vec3 p, int points, float step) {
    std::vector<glm::vec3> line;
    line.reserve(std::size_t(points));
    line.push_back(p);
    auto dir = [](const glm::vec3& q) {
        glm::vec3 v = tornadoVelocity(q);
        float len = glm::length(v);
        return len > 1e-6f ? v / len : glm::vec3(0.0f);
    };
    auto inside = [](const glm::vec3& q) {
        return q.x >= 0.0f && q.x <= 1.0f && q.y >= 0.0f && q.y <= 1.0f && q.z >= 0.0f && q.z <= 1.0f;
    };
    while (int(line.size()) < points) {
        glm::vec3 k1 = dir(p);
        glm::vec3 k2 = dir(p + 0.5f * step * k1);
        glm::vec3 k3 = dir(p + 0.5f * step * k2);
        glm::vec3 k4 = dir(p + step * k3);
        glm::vec3 next = p + step / 6.0f * (k1 + 2.0f * k2 + 2.0f * k3 + k4);
        if (!inside(next) || glm::length(next - p) < 0.25f * step) break;
        line.push_back(next);
        p = next;
    }
    return line;
}

}  // namespace

LineSet generateTornado(int lines, int points, std::uint32_t seed) {
    // Arc-length step: a streamline of `points` vertices covers about 1.5 turns of the vortex
    // at any resolution.
    const float step = 3.0f / float(std::max(points - 1, 1));
    std::vector<std::vector<glm::vec3>> traced(static_cast<std::size_t>(lines));
    tbb::parallel_for(0, lines, [&](int i) {
        std::mt19937 rng(seed * 0x9E3779B9u + std::uint32_t(i));
        std::uniform_real_distribution<float> u(0.05f, 0.95f);
        std::vector<glm::vec3> best;
        for (int attempt = 0; attempt < 32 && int(best.size()) < points; ++attempt) {
            glm::vec3 p{u(rng), u(rng), 0.9f * u(rng) * u(rng)};  // more seeds low in the funnel
            auto line = trace(p, points, step);
            if (line.size() > best.size()) best = std::move(line);
        }
        traced[std::size_t(i)] = std::move(best);
    });

    LineSet set;
    Attribute speed{"speed", {}}, height{"height", {}}, arc{"arc_length", {}};
    for (const auto& line : traced) {
        if (line.size() < 2) continue;
        float s = 0.0f;
        for (std::size_t k = 0; k < line.size(); ++k) {
            if (k > 0) s += glm::length(line[k] - line[k - 1]);
            set.positions.push_back(line[k]);
            speed.values.push_back(glm::length(tornadoVelocity(line[k])));
            height.values.push_back(line[k].z);
            arc.values.push_back(s);
        }
        set.offsets.push_back(std::uint32_t(set.positions.size()));
    }
    set.attributes = {std::move(speed), std::move(height), std::move(arc)};
    for (auto& a : set.attributes) a.updateRange();
    set.updateBounds();
    return set;
}

// ---------------------------------------------------------------------------------------------
// The stand-ins for the performance tables.

namespace {

constexpr float kPi = 3.14159265358979f;

// Random numbers from the raw mt19937 output instead of std::uniform_real_distribution /
// std::normal_distribution, whose algorithms the standard leaves to the library: the data sets
// stay the same with another standard library.
struct Rng {
    std::mt19937 engine;
    explicit Rng(std::uint32_t s) : engine(s) {}
    float uniform() { return float(engine() >> 8) * (1.0f / 16777216.0f); }  // [0, 1)
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    float gaussian() {  // Box-Muller
        float u1 = 1.0f - uniform(), u2 = uniform();
        return std::sqrt(-2.0f * std::log(u1)) * std::cos(2.0f * kPi * u2);
    }
    glm::vec3 direction() {  // uniform on the unit sphere
        float z = uniform(-1.0f, 1.0f), phi = 2.0f * kPi * uniform();
        float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        return {s * std::cos(phi), s * std::sin(phi), z};
    }
};

// Per-line generators, as for the tornado: the data does not depend on how lines are scheduled.
std::uint32_t lineSeed(std::uint32_t seed, int line) {
    return seed * 0x9E3779B9u + std::uint32_t(line);
}

template <class Field>
glm::vec3 rk4Step(const Field& f, const glm::vec3& p, float h) {
    glm::vec3 k1 = f(p);
    glm::vec3 k2 = f(p + 0.5f * h * k1);
    glm::vec3 k3 = f(p + 0.5f * h * k2);
    glm::vec3 k4 = f(p + h * k3);
    return p + h / 6.0f * (k1 + 2.0f * k2 + 2.0f * k3 + k4);
}

// Traces `points` vertices into out[0..points) with the seed in the middle (index
// (points - 1) / 2): backward to the start, forward to the end, so a line is centred on its seed.
template <class Field>
void traceCentred(const Field& f, const glm::vec3& seed, float h, int points, glm::vec3* out) {
    const int mid = (points - 1) / 2;
    out[mid] = seed;
    for (int k = mid + 1; k < points; ++k) out[k] = rk4Step(f, out[k - 1], h);
    for (int k = mid - 1; k >= 0; --k) out[k] = rk4Step(f, out[k + 1], -h);
}

template <class Field>
glm::vec3 curlByCentralDifferences(const Field& f, const glm::vec3& p, float e) {
    glm::vec3 fx = (f(p + glm::vec3(e, 0, 0)) - f(p - glm::vec3(e, 0, 0))) / (2.0f * e);
    glm::vec3 fy = (f(p + glm::vec3(0, e, 0)) - f(p - glm::vec3(0, e, 0))) / (2.0f * e);
    glm::vec3 fz = (f(p + glm::vec3(0, 0, e)) - f(p - glm::vec3(0, 0, e))) / (2.0f * e);
    return {fy.z - fz.y, fz.x - fx.z, fx.y - fy.x};
}

// A line set of exactly lines x points vertices, filled in place by line-parallel loops.
LineSet fixedLineSet(int lines, int points, std::initializer_list<const char*> attributes) {
    LineSet set;
    const std::size_t n = std::size_t(lines) * std::size_t(points);
    set.positions.resize(n);
    set.offsets.resize(std::size_t(lines) + 1);
    for (std::size_t i = 0; i <= std::size_t(lines); ++i) set.offsets[i] = std::uint32_t(i * std::size_t(points));
    for (const char* name : attributes) set.attributes.push_back({name, std::vector<float>(n)});
    return set;
}

LineSet finish(LineSet set) {
    for (auto& a : set.attributes) a.updateRange();
    set.updateBounds();
    return set;
}

template <class Body>
void forEachLine(int lines, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, lines, 16), [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) body(i);
    });
}

// Propeller ---------------------------------------------------------------------------------

constexpr int kBlades = 3;
constexpr float kPropellerMaxW = 1.4f;  // max of the axial velocity below

}  // namespace

glm::vec3 propellerVelocity(const glm::vec3& p) {
    const float dx = p.x - 0.5f, dy = p.y - 0.5f, r2 = dx * dx + dy * dy;
    // Radial rate < 0 everywhere (wake contraction with a blade-periodic helical wobble), so the
    // radius of a streamline never grows; swirl decays away from the axis; jet-like axial flow.
    const float phase = float(kBlades) * (std::atan2(dy, dx) - 2.0f * kPi * p.z);
    const float radial = -0.35f + 0.25f * std::sin(phase);
    const float swirl = 16.0f * std::exp(-r2 / (0.3f * 0.3f));
    const float w = 0.8f + 0.6f * std::exp(-r2 / (0.25f * 0.25f));
    return {radial * dx - swirl * dy, radial * dy + swirl * dx, w};
}

LineSet generatePropeller(int lines, int points, std::uint32_t seed) {
    // Time span: z rises by at most kPropellerMaxW * T (an RK4 step's z increment is a convex
    // combination of w samples), so lines seeded at z <= 0.02 end below z = 0.98.
    const float T = 0.96f / kPropellerMaxW;
    const float h = T / float(points - 1);
    LineSet set = fixedLineSet(lines, points, {"speed", "vorticity", "height", "radius"});
    forEachLine(lines, [&](int i) {
        Rng rng(lineSeed(seed, i));
        const int blade = i % kBlades;
        const float r0 = rng.uniform(0.12f, 0.42f);
        // Blade sweep: the outer part of a blade trails, so each sheet starts slightly curved.
        const float theta = 2.0f * kPi * float(blade) / kBlades + 0.4f * (r0 - 0.12f) + 0.08f * (rng.uniform() - 0.5f);
        glm::vec3 p{0.5f + r0 * std::cos(theta), 0.5f + r0 * std::sin(theta), rng.uniform(0.01f, 0.02f)};
        const std::size_t base = std::size_t(i) * std::size_t(points);
        for (int k = 0; k < points; ++k) {
            if (k > 0) p = rk4Step(propellerVelocity, p, h);
            const std::size_t v = base + std::size_t(k);
            set.positions[v] = p;
            set.attributes[0].values[v] = glm::length(propellerVelocity(p));
            set.attributes[1].values[v] = glm::length(curlByCentralDifferences(propellerVelocity, p, 1e-3f));
            set.attributes[2].values[v] = p.z;
            set.attributes[3].values[v] = glm::length(glm::vec2(p.x - 0.5f, p.y - 0.5f));
        }
    });
    return finish(std::move(set));
}

// Brain ----------------------------------------------------------------------------------------

namespace {

constexpr glm::vec3 kBrainCentre{0.5f, 0.5f, 0.5f};
constexpr glm::vec3 kBrainAxes{0.36f, 0.45f, 0.32f};

struct Bundle {
    glm::vec3 mid;     // centre of the bundle's seed region, inside 0.7 x the ellipsoid
    glm::vec3 axis;    // arcs circle this axis ...
    glm::vec3 centre;  // ... through this point
    float twist, spread, length;
};

float brainDepth(const glm::vec3& p) {
    return glm::length((p - kBrainCentre) / kBrainAxes);
}

const std::array<Bundle, kBrainBundles>& brainBundles() {
    // A fixed layout (its own seed): dataset.seed chooses the fibers, not the anatomy.
    static const std::array<Bundle, kBrainBundles> bundles = [] {
        std::array<Bundle, kBrainBundles> b{};
        Rng rng(0xB4A1u);
        for (Bundle& bundle : b) {
            glm::vec3 q;
            do q = glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
            while (glm::length(q) > 1.0f);
            bundle.mid = kBrainCentre + 0.7f * q * kBrainAxes;
            bundle.axis = rng.direction();
            glm::vec3 n = rng.direction();
            n = n - glm::dot(n, bundle.axis) * bundle.axis;
            if (glm::length(n) < 1e-3f) n = glm::cross(bundle.axis, glm::vec3(1, 0, 0));
            n = glm::normalize(n);
            bundle.centre = bundle.mid - rng.uniform(0.15f, 0.5f) * n;
            bundle.twist = rng.uniform(-0.25f, 0.25f);
            bundle.spread = rng.uniform(0.03f, 0.08f);
            bundle.length = rng.uniform(0.12f, 0.3f);
        }
        return b;
    }();
    return bundles;
}

}  // namespace

bool insideBrain(const glm::vec3& p) {
    return brainDepth(p) <= 1.0f;
}

glm::vec3 brainBundleDirection(int bundle, const glm::vec3& p) {
    const Bundle& b = brainBundles()[std::size_t(bundle)];
    glm::vec3 q = p - b.centre;
    glm::vec3 radial = q - glm::dot(q, b.axis) * b.axis;
    float r = glm::length(radial);
    if (r < 1e-6f) return b.axis;  // on the axis itself (never seeded there: radius >= 0.15 - spread)
    return glm::normalize(glm::cross(b.axis, radial) / r + b.twist * b.axis);
}

LineSet generateBrain(int lines, int points, std::uint32_t seed) {
    LineSet set = fixedLineSet(lines, points, {"bundle", "arc_length", "depth"});
    forEachLine(lines, [&](int i) {
        Rng rng(lineSeed(seed, i));
        const int bundle = int(rng.engine() % kBrainBundles);
        const Bundle& b = brainBundles()[std::size_t(bundle)];
        auto field = [bundle](const glm::vec3& p) { return brainBundleDirection(bundle, p); };
        glm::vec3* out = set.positions.data() + std::size_t(i) * std::size_t(points);
        auto fits = [&] {
            for (int k = 0; k < points; ++k)
                if (!insideBrain(out[k])) return false;
            return true;
        };
        bool placed = false;
        for (int attempt = 0; attempt < 16 && !placed; ++attempt) {
            glm::vec3 s = b.mid + b.spread * glm::vec3(rng.gaussian(), rng.gaussian(), rng.gaussian());
            float length = b.length * rng.uniform(0.7f, 1.3f);
            if (!insideBrain(s)) continue;
            traceCentred(field, s, length / float(points - 1), points, out);
            placed = fits();
        }
        if (!placed) {
            // mid lies >= 0.3 x 0.32 = 0.096 inside the surface and a unit-speed RK4 step moves at
            // most h, so a fiber of length 0.18 centred there always fits.
            traceCentred(field, b.mid, std::min(b.length, 0.18f) / float(points - 1), points, out);
        }
        const std::size_t base = std::size_t(i) * std::size_t(points);
        float s = 0.0f;
        for (int k = 0; k < points; ++k) {
            if (k > 0) s += glm::length(out[k] - out[k - 1]);
            set.attributes[0].values[base + std::size_t(k)] = float(bundle);
            set.attributes[1].values[base + std::size_t(k)] = s;
            set.attributes[2].values[base + std::size_t(k)] = brainDepth(out[k]);
        }
    });
    return finish(std::move(set));
}

// Convection -----------------------------------------------------------------------------------

namespace {

constexpr float kRollWidth = 0.25f;      // 4 rolls across x in [0, 1]
constexpr float kThroughFlow = 0.1f;     // peak axial velocity (at mid height)
constexpr float kConvectionTime = 5.0f;  // about 10 turns around a roll (period ~ 2 roll widths)

float throughFlow(float z) {
    float zeta = z / kConvectionHeight;
    return kThroughFlow * (0.25f + 3.0f * zeta * (1.0f - zeta));
}

}  // namespace

glm::vec3 convectionVelocity(const glm::vec3& p) {
    // Stream function psi = sin(pi x / d) sin(pi z / H) in x-z (divergence-free rolls, zero
    // normal velocity on the walls x = k d and on z = 0, H), plus the through-flow along y.
    const float a = kPi * p.x / kRollWidth, c = kPi * p.z / kConvectionHeight;
    return {std::sin(a) * std::cos(c), throughFlow(p.z), -(kConvectionHeight / kRollWidth) * std::cos(a) * std::sin(c)};
}

namespace {

glm::vec3 convectionVorticity(const glm::vec3& p) {
    const float a = kPi * p.x / kRollWidth, c = kPi * p.z / kConvectionHeight;
    const float zeta = p.z / kConvectionHeight;
    const float dvdz = kThroughFlow * 3.0f * (1.0f - 2.0f * zeta) / kConvectionHeight;
    const float wy =
        -(kPi / kConvectionHeight + kPi * kConvectionHeight / (kRollWidth * kRollWidth)) * std::sin(a) * std::sin(c);
    return {-dvdz, wy, 0.0f};
}

}  // namespace

LineSet generateConvection(int lines, int points, std::uint32_t seed) {
    // The through-flow is at most kThroughFlow, so a line spans at most kThroughFlow * T in y
    // around its seed: seeds in y in [0.255, 0.745] keep every line inside y in [0.005, 0.995].
    const float h = kConvectionTime / float(points - 1);
    const float halfSpan = 0.5f * kThroughFlow * kConvectionTime;
    LineSet set = fixedLineSet(lines, points, {"speed", "vorticity", "temperature"});
    forEachLine(lines, [&](int i) {
        Rng rng(lineSeed(seed, i));
        const int roll = int(rng.engine() % 4u);
        // Away from the cell corners (stagnation points), so no line crawls there.
        glm::vec3 s{(float(roll) + rng.uniform(0.05f, 0.95f)) * kRollWidth,
                    rng.uniform(halfSpan + 0.005f, 1.0f - halfSpan - 0.005f),
                    rng.uniform(0.05f, 0.95f) * kConvectionHeight};
        glm::vec3* out = set.positions.data() + std::size_t(i) * std::size_t(points);
        traceCentred(convectionVelocity, s, h, points, out);
        const std::size_t base = std::size_t(i) * std::size_t(points);
        for (int k = 0; k < points; ++k) {
            const glm::vec3& p = out[k];
            const std::size_t v = base + std::size_t(k);
            set.attributes[0].values[v] = glm::length(convectionVelocity(p));
            set.attributes[1].values[v] = glm::length(convectionVorticity(p));
            // Conductive profile plus the roll's perturbation: warm where the fluid rises (w > 0).
            set.attributes[2].values[v] =
                1.0f - p.z / kConvectionHeight -
                0.4f * std::cos(kPi * p.x / kRollWidth) * std::sin(kPi * p.z / kConvectionHeight);
        }
    });
    return finish(std::move(set));
}

// Turbulence -----------------------------------------------------------------------------------

namespace {

struct Mode {
    glm::vec3 k, a, b;  // a, b perpendicular to k: divergence-free
};
constexpr int kModes = 8;
constexpr float kTurbulenceTime = 2.0f;  // about one cube length of arc per line

const std::array<Mode, kModes>& turbulenceModes() {
    static const std::array<Mode, kModes> modes = [] {
        std::array<Mode, kModes> m{};
        Rng rng(0x7u);
        for (Mode& mode : m) {
            // Integer wave vectors keep the flow 2*pi-periodic; energy spectrum E(k) ~ k^-5/3 means
            // amplitudes ~ k^-5/6.
            glm::vec3 k;
            do
                k = glm::vec3(float(int(rng.engine() % 13u) - 6), float(int(rng.engine() % 13u) - 6),
                              float(int(rng.engine() % 13u) - 6));
            while (glm::length(k) < 2.0f || glm::length(k) > 6.0f);
            const glm::vec3 kn = glm::normalize(k);
            auto perpendicular = [&] {
                glm::vec3 d;
                do {
                    d = rng.direction();
                    d -= glm::dot(d, kn) * kn;
                } while (glm::length(d) < 0.1f);
                return glm::normalize(d);
            };
            const float amplitude = 1.5f * std::pow(glm::length(k), -5.0f / 6.0f);
            mode = {k, amplitude * perpendicular(), amplitude * perpendicular()};
        }
        return m;
    }();
    return modes;
}

constexpr float kA = 1.7320508f, kB = 1.4142136f, kC = 1.0f;

// Velocity and vorticity in the flow's coordinates X = 2 pi p.
glm::vec3 turbulenceFlow(const glm::vec3& X) {
    glm::vec3 v{kA * std::sin(X.z) + kC * std::cos(X.y), kB * std::sin(X.x) + kA * std::cos(X.z),
                kC * std::sin(X.y) + kB * std::cos(X.x)};
    for (const Mode& m : turbulenceModes()) {
        const float phi = glm::dot(m.k, X);
        v += m.a * std::cos(phi) + m.b * std::sin(phi);
    }
    return v;
}

glm::vec3 turbulenceVorticity(const glm::vec3& X) {
    // The ABC flow is a Beltrami field (curl v = v); curl(a cos(k.X) + b sin(k.X)) =
    // -sin(k.X) k x a + cos(k.X) k x b.
    glm::vec3 w{kA * std::sin(X.z) + kC * std::cos(X.y), kB * std::sin(X.x) + kA * std::cos(X.z),
                kC * std::sin(X.y) + kB * std::cos(X.x)};
    for (const Mode& m : turbulenceModes()) {
        const float phi = glm::dot(m.k, X);
        w += -std::sin(phi) * glm::cross(m.k, m.a) + std::cos(phi) * glm::cross(m.k, m.b);
    }
    return w;
}

}  // namespace

glm::vec3 turbulenceVelocity(const glm::vec3& p) {
    return turbulenceFlow(2.0f * kPi * p);
}

LineSet generateTurbulence(int lines, int points, std::uint32_t seed) {
    const float h = kTurbulenceTime / float(points - 1);
    const std::size_t n = std::size_t(lines) * std::size_t(points);
    // Traced unwrapped in flow coordinates, then cut where a line changes periodic cell.
    std::vector<glm::vec3> X(n);
    forEachLine(lines, [&](int i) {
        Rng rng(lineSeed(seed, i));
        glm::vec3 s = 2.0f * kPi * glm::vec3(rng.uniform(), rng.uniform(), rng.uniform());
        traceCentred(turbulenceFlow, s, h, points, X.data() + std::size_t(i) * std::size_t(points));
    });
    std::vector<glm::vec3> cell(n);
    LineSet set = fixedLineSet(lines, points, {"speed", "vorticity"});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            glm::vec3 q = X[v] / (2.0f * kPi);
            cell[v] = glm::floor(q);
            // Clamp: q - floor(q) can round up to 1 for tiny negative q.
            set.positions[v] = glm::min(q - cell[v], glm::vec3(1.0f));
            set.attributes[0].values[v] = glm::length(turbulenceFlow(X[v]));
            set.attributes[1].values[v] = glm::length(turbulenceVorticity(X[v]));
        }
    });
    // Compact in place: split at cell changes, drop single-vertex pieces (serial; the order of
    // vertices is kept, so the result is the same for any thread count).
    std::size_t write = 0;
    std::vector<std::uint32_t> offsets{0};
    for (int i = 0; i < lines; ++i) {
        std::size_t begin = std::size_t(i) * std::size_t(points), end = begin + std::size_t(points);
        std::size_t piece = begin;
        for (std::size_t v = begin + 1; v <= end; ++v) {
            if (v < end && cell[v] == cell[v - 1]) continue;
            if (v - piece >= 2) {
                for (std::size_t u = piece; u < v; ++u, ++write) {
                    set.positions[write] = set.positions[u];
                    for (auto& a : set.attributes) a.values[write] = a.values[u];
                }
                offsets.push_back(std::uint32_t(write));
            }
            piece = v;
        }
    }
    set.positions.resize(write);
    for (auto& a : set.attributes) a.values.resize(write);
    set.offsets = std::move(offsets);
    return finish(std::move(set));
}

// Spiral -----------------------------------------------------------------------------------------

LineSet generateSpiral(int lines, int points, std::uint32_t seed) {
    LineSet set = fixedLineSet(lines, points, {"shell", "parameter"});
    const glm::vec3 centre(0.5f);
    forEachLine(lines, [&](int i) {
        Rng rng(lineSeed(seed, i));
        // Uniform in the volume of the shell kSpiralMinShell..kSpiralMaxShell: r^3 uniform.
        const float lo3 = kSpiralMinShell * kSpiralMinShell * kSpiralMinShell;
        const float hi3 = kSpiralMaxShell * kSpiralMaxShell * kSpiralMaxShell;
        const float shell = std::cbrt(rng.uniform(lo3, hi3));
        const glm::vec3 axis = rng.direction();
        // An orthonormal basis (e1, e2, axis).
        const glm::vec3 other = std::abs(axis.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        const glm::vec3 e1 = glm::normalize(glm::cross(axis, other));
        const glm::vec3 e2 = glm::cross(axis, e1);
        const float phase = 2.0f * kPi * rng.uniform();
        const std::size_t base = std::size_t(i) * std::size_t(points);
        for (int k = 0; k < points; ++k) {
            const float s = points > 1 ? float(k) / float(points - 1) : 0.0f;
            // Away from the poles, where the turns would crowd into zero-length segments.
            const float theta = kPi * (0.05f + 0.9f * s);
            const float phi = phase + 2.0f * kPi * float(kSpiralTurns) * s;
            const glm::vec3 d = std::sin(theta) * (std::cos(phi) * e1 + std::sin(phi) * e2) + std::cos(theta) * axis;
            const std::size_t v = base + std::size_t(k);
            set.positions[v] = centre + shell * d;
            set.attributes[0].values[v] = shell;
            set.attributes[1].values[v] = s;
        }
    });
    return finish(std::move(set));
}

// Dispatch -------------------------------------------------------------------------------------

const std::vector<std::string>& generatorNames() {
    static const std::vector<std::string> names{"tornado", "propeller", "brain", "convection", "turbulence", "spiral"};
    return names;
}

LineSet generateDataset(const std::string& name, int lines, int points, std::uint32_t seed) {
    if (name == "tornado") return generateTornado(lines, points, seed);
    if (name == "propeller") return generatePropeller(lines, points, seed);
    if (name == "brain") return generateBrain(lines, points, seed);
    if (name == "convection") return generateConvection(lines, points, seed);
    if (name == "turbulence") return generateTurbulence(lines, points, seed);
    if (name == "spiral") return generateSpiral(lines, points, seed);
    throw std::invalid_argument("unknown generator \"" + name + "\"");
}

}  // namespace tc
