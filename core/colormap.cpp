#include "core/colormap.h"

#include <algorithm>
#include <map>

#include "core/error.h"

namespace tc {

glm::vec3 Colormap::sampleSrgb(float x) const {
    x = std::clamp(x, 0.0f, 1.0f);
    auto it = std::upper_bound(t.begin(), t.end(), x);
    if (it == t.begin()) return srgb.front();
    if (it == t.end()) return srgb.back();
    std::size_t i = std::size_t(it - t.begin());
    float f = (x - t[i - 1]) / std::max(t[i] - t[i - 1], 1e-12f);
    return glm::mix(srgb[i - 1], srgb[i], f);
}

namespace {

Colormap make(const std::string& name, std::vector<glm::vec3> colors) {
    Colormap m{name, {}, std::move(colors)};
    for (std::size_t i = 0; i < m.srgb.size(); ++i) m.t.push_back(float(i) / float(m.srgb.size() - 1));
    return m;
}

// Control points at t = 0, 1/8, ..., 1 of matplotlib's perceptually uniform maps (entries
// 0, 32, ..., 224, 255 of the 256-entry tables), Google's Turbo and Moreland's cool-warm.
const std::map<std::string, Colormap>& table() {
    static const std::map<std::string, Colormap> maps = [] {
        std::map<std::string, Colormap> m;
        auto add = [&](Colormap c) { m.emplace(c.name, std::move(c)); };
        add(make("viridis", {{0.267004f, 0.004874f, 0.329415f}, {0.282623f, 0.140926f, 0.457517f},
                             {0.253935f, 0.265254f, 0.529983f}, {0.206756f, 0.371758f, 0.553117f},
                             {0.163625f, 0.471133f, 0.558148f}, {0.127568f, 0.566949f, 0.550556f},
                             {0.134692f, 0.658636f, 0.517649f}, {0.266941f, 0.748751f, 0.440573f},
                             {0.477504f, 0.821444f, 0.318195f}, {0.993248f, 0.906157f, 0.143936f}}));
        add(make("inferno", {{0.001462f, 0.000466f, 0.013866f}, {0.087411f, 0.044556f, 0.224813f},
                             {0.258234f, 0.038571f, 0.406485f}, {0.416331f, 0.090203f, 0.432943f},
                             {0.578304f, 0.148039f, 0.404411f}, {0.735683f, 0.215906f, 0.330245f},
                             {0.865006f, 0.316822f, 0.226055f}, {0.954506f, 0.468744f, 0.099874f},
                             {0.987622f, 0.645320f, 0.039886f}, {0.988362f, 0.998364f, 0.644924f}}));
        add(make("magma", {{0.001462f, 0.000466f, 0.013866f}, {0.078815f, 0.054184f, 0.211667f},
                           {0.232077f, 0.059889f, 0.437695f}, {0.390384f, 0.100379f, 0.501864f},
                           {0.550287f, 0.161158f, 0.505719f}, {0.716387f, 0.214982f, 0.475290f},
                           {0.868793f, 0.287728f, 0.409303f}, {0.967671f, 0.439703f, 0.359810f},
                           {0.994738f, 0.624350f, 0.427397f}, {0.987053f, 0.991438f, 0.749504f}}));
        add(make("plasma", {{0.050383f, 0.029803f, 0.527975f}, {0.254627f, 0.013882f, 0.615419f},
                            {0.417642f, 0.000564f, 0.658390f}, {0.562738f, 0.051545f, 0.641509f},
                            {0.692840f, 0.165141f, 0.564522f}, {0.798216f, 0.280197f, 0.469538f},
                            {0.881443f, 0.392529f, 0.383229f}, {0.949217f, 0.517763f, 0.295662f},
                            {0.988260f, 0.652325f, 0.211364f}, {0.940015f, 0.975158f, 0.131326f}}));
        add(make("turbo", {{0.18995f, 0.07176f, 0.23217f}, {0.27469f, 0.38125f, 0.84335f},
                           {0.24427f, 0.62626f, 0.98903f}, {0.10342f, 0.85095f, 0.79040f},
                           {0.30537f, 0.98237f, 0.43856f}, {0.64746f, 0.98907f, 0.22395f},
                           {0.93226f, 0.81058f, 0.21952f}, {0.98483f, 0.53136f, 0.13839f},
                           {0.84425f, 0.22813f, 0.03008f}, {0.47960f, 0.01583f, 0.01055f}}));
        add(make("cool_warm", {{0.230f, 0.299f, 0.754f}, {0.552f, 0.690f, 0.996f}, {0.865f, 0.865f, 0.865f},
                               {0.958f, 0.603f, 0.482f}, {0.706f, 0.016f, 0.150f}}));
        add(make("grayscale", {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}));
        return m;
    }();
    return maps;
}

}  // namespace

std::vector<std::string> builtinColormapNames() {
    std::vector<std::string> names;
    for (const auto& [name, map] : table()) names.push_back(name);
    return names;
}

const Colormap& builtinColormap(const std::string& name) {
    auto it = table().find(name);
    if (it == table().end()) {
        std::string known;
        for (const auto& n : builtinColormapNames()) known += (known.empty() ? "" : ", ") + n;
        throw InputError("unknown colormap \"" + name + "\" (built-in: " + known + ")");
    }
    return it->second;
}

}  // namespace tc
